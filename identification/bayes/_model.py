"""The numpyro model of the Bayesian bearing fit: priors, simulator, Gaussian likelihood.

For each record r with samples F_r,k of the measured force and the model force
M_r,k(theta) of `identification.bearing_fit.simulate_record_force` (the 1990 model, the
same simulator as the least-squares fit),

    F_r,k / s_r ~ Normal(M_r,k(theta) / s_r, noise_rel_r)       independent over k,

with s_r the RMS measured force of record r [N] and `noise_rel_r` the noise standard
deviation relative to it (sampled; reported in newtons as `noise_level`).
"""

import functools

import jax
import jax.numpy as jnp
import numpyro
import numpyro.distributions as dist
from numpyro.distributions import biject_to

from ..bearing_fit import simulate_record_force

NOISE_RANGE = (1e-4, 1.0)
"""Range of the log-uniform prior of the relative noise level [-]."""


def base_name(p) -> str:
    """Name of the sampled (base-scale) variable of a prior (`ParameterPrior` or `PriorShape`)."""
    return p.site if p.kind == "uniform_physical" else f"{p.site}__{p.scale}"


def distribution(p, values=None):
    """The numpyro distribution of the base-scale variable of one prior (bounded support):
    `p` a `ParameterPrior`, or a `PriorShape` with `values` = (lower, upper, loc, sd) on the
    base scale (`ParameterPrior.base_values`; traced inside a compiled sampler)."""
    lo, hi, loc, sd = p.base_values() if values is None else values
    if p.kind in ("uniform_physical", "uniform"):
        return dist.Uniform(lo, hi)
    if p.kind == "normal":
        return dist.Normal(loc, sd)
    return dist.TruncatedNormal(loc, sd, low=lo, high=hi)


def to_base(p, x):
    """Physical value -> base-scale value (numpy or jax)."""
    if p.kind == "uniform_physical":
        return x
    if p.scale == "log":
        return jnp.log(x)
    if p.scale == "logit":
        return jnp.log(x) - jnp.log1p(-x)
    return jnp.log(x - 1.0)


def to_physical(p, b):
    """Base-scale value -> physical value."""
    if p.kind == "uniform_physical":
        return b
    if p.scale == "log":
        return jnp.exp(b)
    if p.scale == "logit":
        return jax.nn.sigmoid(b)
    return 1.0 + jnp.exp(b)


_ORDER = ("f_max", "delta_f", "rate_a", "yield_disp", "breakaway_ratio")


def _forward_mode_force(n_interfaces: tuple[int, int], names: tuple[str, ...]):
    """The record force with a vector-Jacobian product computed in forward mode.

    `n_interfaces`: (interfaces in parallel, interfaces in series) of the record (FORMATS.md);
    `names`: the constants in `theta`, in its order (without `breakaway_ratio`: no breakaway).

    NUTS asks for gradients (reverse mode); through a `lax.scan` over thousands of samples
    reverse mode stores and replays the whole history, while five forward tangents cost
    about as much as two simulations. The VJP is `J^T g` with `J` from `jax.jacfwd`.
    """

    def simulate(theta, rec):
        values = dict(zip(names, theta))
        return simulate_record_force(values, rec["time"], rec["ux"], rec["load"], z0=rec["z0"],
                                     z_peak0=rec["z_peak0"], velocity=rec["velocity"],
                                     interfaces_in_parallel=n_interfaces[0],
                                     interfaces_in_series=n_interfaces[1])

    return forward_mode(simulate)


def forward_mode(simulate):
    """`simulate(theta, data)` -> a vector, with its vector-Jacobian product in `theta` taken
    in forward mode: `J^T g`, `J` from `jax.jacfwd` (the data get no cotangent)."""

    @jax.custom_vjp
    def value(theta, data):
        return simulate(theta, data)

    def fwd(theta, data):
        jac, out = jax.jacfwd(lambda th: (simulate(th, data),) * 2, has_aux=True)(theta)
        return out, (jac, data)

    def bwd(res, g):
        jac, data = res
        return jac.T @ g, jax.tree_util.tree_map(jnp.zeros_like, data)

    value.defvjp(fwd, bwd)
    return value


def make_model(shapes: dict, fixed_names: tuple, n_interfaces: tuple):
    """A numpyro model `model(data, prior_values, fixed_values)`: `shapes` name ->
    `PriorShape` of each sampled constant, `fixed_names` the constants held, `n_interfaces`
    (parallel, series) of each record. Its arguments are data: `data` a list of record dicts
    (see `record_data`), `prior_values` name -> `ParameterPrior.base_values()`, `fixed_values`
    name -> value, so that one compiled sampler serves records of one shape. The model has
    breakaway (Eq. 17) where `breakaway_ratio` has a prior or a fixed value."""

    names = tuple(k for k in _ORDER if k in shapes or k in fixed_names)
    forces = {n: _forward_mode_force(n, names) for n in set(n_interfaces)}

    def model(data, prior_values, fixed_values):
        values = {k: jnp.asarray(fixed_values[k]) for k in fixed_names}
        for name, p in shapes.items():
            b = numpyro.sample(base_name(p), distribution(p, prior_values[name]))
            values[name] = to_physical(p, b)
        if "delta_f" in shapes:
            values["delta_f"] = values["delta_f"] * values["f_max"]
        noise = numpyro.sample(
            "noise_rel", dist.LogUniform(*NOISE_RANGE).expand([len(data)]).to_event(1))
        theta = jnp.stack([jnp.asarray(values[k], dtype=float) for k in names])
        for i, (rec, n) in enumerate(zip(data, n_interfaces)):
            force = forces[n](theta, rec)
            numpyro.sample(f"obs_{i}", dist.Normal(force / rec["scale"], noise[i]),
                           obs=rec["fx"] / rec["scale"])

    return model


def prior_values(priors: dict) -> dict:
    """name -> `ParameterPrior.base_values()` as arrays (data of a compiled sampler)."""
    return {name: jnp.asarray(p.base_values()) for name, p in priors.items()}


def model_args(priors: dict, fixed: dict, arrays: list) -> tuple:
    """The arguments of `make_model`'s model: (record arrays, prior values, fixed values)."""
    return (arrays, prior_values(priors), {name: jnp.asarray(float(v)) for name, v in fixed.items()})


def shapes_of(priors: dict) -> tuple:
    """((name, `PriorShape`), ...) of the priors: the static part, a key of compiled code."""
    return tuple((name, p.shape) for name, p in priors.items())


@functools.partial(jax.jit, static_argnums=0)
def unconstrain(shapes: tuple, values: dict, values_of_priors: dict) -> dict:
    """Sampled site -> unconstrained value (NUTS's coordinates) of the sampled variables'
    physical `values` (delta_f as delta_f / f_max); `shapes` as `shapes_of`."""
    return {base_name(p): biject_to(distribution(p, values_of_priors[name]).support).inv(
        to_base(p, values[name])) for name, p in shapes}


@functools.partial(jax.jit, static_argnums=0)
def constrain(shapes: tuple, params: dict, values_of_priors: dict) -> dict:
    """Unconstrained draws -> base-scale draws of every sampled site (noise_rel included)."""
    out = {base_name(p): biject_to(distribution(p, values_of_priors[name]).support)(
        params[base_name(p)]) for name, p in shapes}
    out["noise_rel"] = biject_to(dist.LogUniform(*NOISE_RANGE).support)(params["noise_rel"])
    return out


def make_postprocess(priors: dict):
    """Unconstrained -> base-scale samples without re-running the simulator per draw.

    numpyro's default post-processing traces the model (the whole simulation) for every
    draw to fill deterministic sites; this model has none, so the bijections of the
    supports suffice (`constrain`, compiled once per shape of priors).
    """
    shapes, values = shapes_of(priors), prior_values(priors)
    return lambda params: constrain(shapes, params, values)
