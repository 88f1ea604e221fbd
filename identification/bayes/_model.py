"""The numpyro model of the Bayesian bearing fit: priors, simulator, Gaussian likelihood.

For each record r with samples F_r,k of the measured force and the model force
M_r,k(theta) of `identification.bearing_fit.simulate_record_force` (the 1990 model, the
same simulator as the least-squares fit),

    F_r,k / s_r ~ Normal(M_r,k(theta) / s_r, noise_rel_r)       independent over k,

with s_r the RMS measured force of record r [N] and `noise_rel_r` the noise standard
deviation relative to it (sampled; reported in newtons as `noise_level`).
"""

import jax
import jax.numpy as jnp
import numpy as np
import numpyro
import numpyro.distributions as dist
from numpyro.distributions import biject_to

from ..bearing_fit import simulate_record_force
from ._priors import ParameterPrior

NOISE_RANGE = (1e-4, 1.0)
"""Range of the log-uniform prior of the relative noise level [-]."""


def base_name(p: ParameterPrior) -> str:
    """Name of the sampled (base-scale) variable of a prior."""
    return p.site if (p.scale == "logit" and p.loc is None) else f"{p.site}__{p.scale}"


def distribution(p: ParameterPrior):
    """The numpyro distribution of the base-scale variable of one prior (bounded support)."""
    if p.scale == "logit" and p.loc is None:
        return dist.Uniform(p.low, p.high)
    t_lo, t_hi = (float(x) for x in p.transformed_bounds())
    if p.loc is None:
        return dist.Uniform(t_lo, t_hi)
    if not (np.isfinite(t_lo) or np.isfinite(t_hi)):
        return dist.Normal(p.loc, p.sd)
    return dist.TruncatedNormal(p.loc, p.sd, low=t_lo, high=t_hi)


def to_base(p: ParameterPrior, x):
    """Physical value -> base-scale value (numpy or jax)."""
    if p.scale == "logit" and p.loc is None:
        return x
    if p.scale == "log":
        return jnp.log(x)
    if p.scale == "logit":
        return jnp.log(x) - jnp.log1p(-x)
    return jnp.log(x - 1.0)


def to_physical(p: ParameterPrior, b):
    """Base-scale value -> physical value."""
    if p.scale == "logit" and p.loc is None:
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

    @jax.custom_vjp
    def force(theta, rec):
        return simulate(theta, rec)

    def fwd(theta, rec):
        jac, value = jax.jacfwd(lambda th: (simulate(th, rec),) * 2, has_aux=True)(theta)
        return value, (jac, rec)

    def bwd(res, g):
        jac, rec = res
        return jac.T @ g, jax.tree_util.tree_map(jnp.zeros_like, rec)

    force.defvjp(fwd, bwd)
    return force


def make_model(priors: dict, fixed: dict, n_interfaces: tuple):
    """A numpyro model `model(data)`; `data` is a list of record dicts (see `record_data`).
    The model has breakaway (Eq. 17) where `breakaway_ratio` has a prior or a fixed value."""

    names = tuple(k for k in _ORDER if k in priors or k in fixed)
    forces = {n: _forward_mode_force(n, names) for n in set(n_interfaces)}

    def model(data):
        values = {k: jnp.asarray(v) for k, v in fixed.items()}
        for name, p in priors.items():
            b = numpyro.sample(base_name(p), distribution(p))
            values[name] = to_physical(p, b)
        if "delta_f" in priors:
            values["delta_f"] = values["delta_f"] * values["f_max"]
        noise = numpyro.sample(
            "noise_rel", dist.LogUniform(*NOISE_RANGE).expand([len(data)]).to_event(1))
        theta = jnp.stack([jnp.asarray(values[k], dtype=float) for k in names])
        for i, (rec, n) in enumerate(zip(data, n_interfaces)):
            force = forces[n](theta, rec)
            numpyro.sample(f"obs_{i}", dist.Normal(force / rec["scale"], noise[i]),
                           obs=rec["fx"] / rec["scale"])

    return model


def make_postprocess(priors: dict):
    """Unconstrained -> base-scale samples without re-running the simulator per draw.

    numpyro's default post-processing traces the model (the whole simulation) for every
    draw to fill deterministic sites; this model has none, so the bijections of the
    supports suffice.
    """
    supports = {base_name(p): distribution(p).support for p in priors.values()}
    supports["noise_rel"] = dist.LogUniform(*NOISE_RANGE).support

    def constrain(params):
        return {k: biject_to(supports[k])(v) for k, v in params.items()}

    return constrain
