"""The posterior of a double or triple friction pendulum's surface friction, sampled with NUTS
through the same series model the least-squares fit and the structures run.

For one test record with force samples F_k under the normal load N_k and the series model's
force M_k(theta) along the record's displacement (`teflon_jax.systems.imposed_path_test`,
the sliders of the pendulum in series: Fenz & Constantinou 2006, 2008; Eq. 1 of Constantinou,
Mokha & Reinhorn 1990 on each surface),

    F_k / s ~ Normal(M_k(theta) / s, noise_rel)        independent over k,

with s the RMS measured force [N] and the relative noise level noise_rel sampled
(log-uniform on `NOISE_RANGE`, as the flat bearing's posterior). theta holds the Eq. 1
constants of each surface that the least-squares fit freed (`SeriesFit.free`); its radii and
capacities are held at their least-squares values, as the single pendulum's posterior holds
its radius: they follow from the loop's slopes and reach, which the force fixes far more
sharply than it fixes friction. Each constant's prior is uniform on a bounded scale:

    <surface>_f_max ~ LogUniform(F_MAX_RANGE)                                   [-]
    <surface>_delta_f / <surface>_f_max ~ Uniform(0, 1)                          [-]
    <surface>_rate_a ~ LogUniform(search range of PARAMETER_BOUNDS["rate_a"])  [s/m]

NUTS (Hoffman & Gelman 2014; numpyro, dense mass matrix adapted in warm-up) runs in
coordinates whitened by the least-squares curvature (`_Laplace`), from the least-squares
constants; the force's gradient is taken in forward mode (`forward_mode`: a handful of
tangents through the record's scan cost about one more simulation, where reverse mode would
store the history).
The draws are taken in blocks, so that Ctrl-C keeps those finished (`SamplingInterrupted`).
The run is checked as the flat bearing's is (`diagnose_run`: rank-normalised R-hat, bulk and
tail ESS, divergences; Vehtari et al. 2021).
"""

import math
import time as _time

import jax
import jax.numpy as jnp
import numpy as np
from numpyro.infer import NUTS

from teflon_jax.bearing import PARAMETER_BOUNDS
from teflon_jax.systems import imposed_path_test, sampled_path

from ..bearing_fit import SeriesFit, parameter_units, series_arrays, series_with_parameters
from ._model import NOISE_RANGE, base_name, forward_mode, to_base, to_physical
from ._priors import ParameterPrior
from ._result import BayesResult, diagnose_run
from ._sampler import SamplingInterrupted, block_length, run_in_blocks

F_MAX_RANGE = (1e-3, 0.5)
"""Range of the log-uniform prior of each surface's f_max [-]: from a polished stainless
surface on lubricated PTFE to well beyond any liner of the catalogues."""

SAMPLED = ("f_max", "delta_f", "rate_a")
"""The constants of a surface the posterior samples (those of Eq. 1) where the fit freed them."""


def series_priors(fit: SeriesFit) -> dict:
    """name -> `ParameterPrior` of each sampled constant of `fit`'s pendulum (module docstring):
    the Eq. 1 constants among `fit.free`, delta_f as its ratio to f_max."""
    priors = {}
    for name in fit.free:
        surface, constant = name.split("_", 1)
        if constant == "f_max":
            priors[name] = ParameterPrior(name, *F_MAX_RANGE, scale="log")
        elif constant == "delta_f":
            priors[name] = ParameterPrior(f"{surface}_delta_ratio", 0.0, 1.0, scale="logit")
        elif constant == "rate_a":
            priors[name] = ParameterPrior(name, *PARAMETER_BOUNDS["rate_a"].search, scale="log")
    return priors


def _physical(priors: dict, fit: SeriesFit, base: dict) -> dict:
    """The constants (traced) from the sampled base-scale values, delta_f from its ratio."""
    values = {name: to_physical(p, base[base_name(p)]) for name, p in priors.items()}
    for name in list(values):
        surface, constant = name.split("_", 1)
        if constant == "delta_f":
            values[name] = values[name] * values.get(f"{surface}_f_max", fit.parameters[f"{surface}_f_max"])
    return values


def _series_force(fit: SeriesFit, names: tuple, reference_load):
    """The series model's force [N] along a `SampledPath`, flattened ((nt,), or (2 nt,) along
    an orbit), as a function `force(theta, path)` of the constants `names` (a vector) and the
    path."""
    def force(theta, path):
        bearing = series_with_parameters(fit.bearing, dict(zip(names, theta)))
        return imposed_path_test(bearing, path, reference_load=reference_load).force.reshape(-1)

    return force


def _base_force(priors, fit: SeriesFit, force_of, path, scale: float):
    """The force over its RMS `scale` (flattened) as a function of the base-scale variables b,
    in the order of `priors` (`force_of(theta, path)`, theta the constants in that order)."""
    sites, names = [base_name(p) for p in priors.values()], tuple(priors)

    def force(b):
        values = _physical(priors, fit, dict(zip(sites, b)))
        return force_of(jnp.stack([jnp.asarray(values[n], float) for n in names]), path).reshape(-1) / scale

    return force


class _Laplace:
    """The Laplace approximation at the least-squares constants, in the sampled base-scale
    variables b (`ParameterPrior.base_values`: log f_max, delta_f / f_max, log rate_a) and
    log sigma of the noise: b = b0 + L z, log sigma = log sigma0 + s z_noise, L the Cholesky
    factor of sigma0^2 (J^T J)^-1 (J the Jacobian of the force over its RMS in b, the radii
    and capacities held), s = 1 / sqrt(2 n). NUTS runs in z, where the posterior is close to
    a unit normal: its metric adapts from the first window, where in the priors' own
    coordinates a posterior a thousandth of the prior wide meets the adaptation's
    regularisation (numpyro shrinks the estimated matrix towards 1e-3 I) and trajectories
    hundreds of steps long."""

    def __init__(self, priors, fit, force_of, path, measured, scale: float):
        self.sites = [base_name(p) for p in priors.values()]
        self.bounds = np.array([np.asarray(p.base_values())[:2] for p in priors.values()])
        b0 = []
        for name, p in priors.items():
            x = fit.parameters[name]
            if name.endswith("delta_f"):
                x = x / fit.parameters[name.replace("delta_f", "f_max")]
            span = p.high - p.low
            b0.append(float(to_base(p, float(np.clip(x, p.low + 1e-3 * span, p.high - 1e-3 * span)))))
        self.b0 = jnp.asarray(b0)
        self.measured = jnp.asarray(measured).reshape(-1) / scale
        force_of_base = _base_force(priors, fit, force_of, path, scale)
        jacobian = np.asarray(jax.jacfwd(force_of_base)(self.b0))
        residual = np.asarray(force_of_base(self.b0)) - np.asarray(self.measured)
        self.n = residual.size
        self.noise0 = float(np.clip(np.sqrt(np.mean(residual**2)), 2 * NOISE_RANGE[0], 0.5 * NOISE_RANGE[1]))
        covariance = self.noise0**2 * np.linalg.pinv(jacobian.T @ jacobian)
        self.cholesky = jnp.asarray(np.linalg.cholesky(covariance + 1e-14 * np.trace(covariance) * np.eye(len(b0))))
        self.noise_spread = 1.0 / math.sqrt(2.0 * self.n)

    def base(self, z):
        """(b, log sigma) of the whitened point z (p + 1,) (or draws (..., p + 1))."""
        b = self.b0 + jnp.einsum("ij,...j->...i", self.cholesky, z[..., :-1])
        return b, math.log(self.noise0) + self.noise_spread * z[..., -1]

    def potential(self, force_of_base):
        """-log posterior(z) + const (of {"z": z}): the Gaussian likelihood of the record at noise sigma
        (relative to the RMS force) and the priors, uniform in b and in log sigma on their
        bounded ranges (+inf outside); z -> (b, log sigma) is linear, so no Jacobian."""
        low, high = (math.log(v) for v in NOISE_RANGE)
        bounds = jnp.asarray(self.bounds)

        def potential(params):
            b, log_noise = self.base(params["z"])
            r = force_of_base(b) - self.measured
            energy = self.n * log_noise + 0.5 * jnp.sum(r**2) * jnp.exp(-2 * log_noise)
            inside = jnp.all((b > bounds[:, 0]) & (b < bounds[:, 1])) & (log_noise > low) & (log_noise < high)
            return jnp.where(inside, energy, jnp.inf)

        return potential


def fit_series_bayes(record, fit: SeriesFit, *, normal_load=None, num_warmup: int = 500,
                     num_samples: int = 500, num_chains: int = 2, seed: int = 0,
                     target_accept: float = 0.9, rhat_max: float = 1.01,
                     ess_min_per_chain: float = 100.0, progress_bar: bool = False,
                     on_block=None) -> BayesResult:
    """The posterior of the Eq. 1 constants of a double or triple pendulum's surfaces from one
    test record (module docstring), started from its least-squares `fit`
    (`identification.bearing_fit.fit_series_pendulum_test` of the same record and
    `normal_load` [N]). `num_warmup`, `num_samples` per chain, `num_chains` (vectorised),
    `seed`, `target_accept`; `rhat_max` and `ess_min_per_chain` (times the chains) the
    convergence checks; `on_block(done, total)` after the warm-up (`done = 0`) and after each
    block of draws (`block_length`). **Returns:** a `BayesResult` named by the pendulum's
    constants (`<surface>_f_max`, ...). `ValueError` where the fit did not converge or freed no
    Eq. 1 constant, or the counts are too small. **Raises:** `SamplingInterrupted` on Ctrl-C,
    carrying the result of the blocks of draws finished so far (not converged)."""
    if not isinstance(fit, SeriesFit):
        raise ValueError(f"fit: expected the SeriesFit of fit_series_pendulum_test, got {type(fit).__name__}.")
    if not fit.converged:
        raise ValueError(f"fit: the least-squares fit did not converge ({fit.message}); its constants "
                         "cannot start the sampler.")
    priors = series_priors(fit)
    if not priors:
        raise ValueError(f"fit: frees none of the surfaces' Eq. 1 constants ({', '.join(SAMPLED)}); "
                         f"its free constants are {', '.join(fit.free) or 'none'}.")
    if num_chains < 2 or num_warmup < 10 or num_samples < 10:
        raise ValueError("num_chains >= 2 (R-hat needs two chains) and num_warmup, num_samples >= 10.")
    time, displacement, measured, load = series_arrays(record, normal_load)
    names = tuple(priors)
    path = sampled_path(time, displacement, load)
    scale = float(np.sqrt(np.mean(measured**2)))
    force_of = _series_force(fit, names, fit.reference_load)
    laplace = _Laplace(priors, fit, force_of, path, measured, scale)
    potential = laplace.potential(_base_force(priors, fit, forward_mode(force_of), path, scale))
    kernel = NUTS(potential_fn=potential, dense_mass=True, target_accept_prob=target_accept)
    rng = np.random.default_rng(seed)
    starts = {"z": jnp.asarray(0.5 * rng.standard_normal((num_chains, len(names) + 1)))}
    began = _time.perf_counter()
    draws, diverging, interrupted = run_in_blocks(
        kernel, jax.random.key(seed), starts, num_warmup=num_warmup, num_samples=num_samples,
        num_chains=num_chains, block=block_length(num_samples), on_block=on_block, progress_bar=progress_bar)
    elapsed = _time.perf_counter() - began
    if draws is None:
        raise SamplingInterrupted(None)
    b, log_noise = laplace.base(jnp.asarray(draws["z"]))
    base = {site: b[..., i] for i, site in enumerate(laplace.sites)}
    base["noise_rel"] = jnp.exp(log_noise)[..., None]
    ratios = tuple((n, n.replace("delta_f", "f_max")) for n in names if n.endswith("delta_f"))
    result = diagnose_run(base, diverging, priors, fit, [{"scale": scale}], rhat_max=rhat_max,
                          ess_min=ess_min_per_chain * num_chains, elapsed=elapsed, elapsed_least_squares=math.nan,
                          prior="bounds", seed=seed, order=names, ratios=ratios,
                          units=parameter_units(fit.bearing.slider_names), interrupted=interrupted)
    if interrupted is not None:
        raise SamplingInterrupted(result)
    return result
