"""Bayesian identification of the 1990 model's constants with NUTS (numpyro).

`fit_bayes` (i) runs the least-squares fit (`identification.bearing_fit.fit_bearing_test`) for
the free set, the warm start and the standard errors to compare with; (ii) samples the
posterior of the free constants and of the noise level with the No-U-Turn Sampler (Hoffman &
Gelman 2014) through the same simulator, with a dense mass matrix adapted in warm-up
(the friction constants correlate strongly); (iii) checks convergence: rank-normalised split
R-hat, bulk and tail effective sample sizes (Vehtari et al. 2021, "Rank-normalization,
folding, and localization", Bayesian Analysis 16) and divergent transitions; (iv) compares
the posterior spread of each constant with its prior spread to say which ones the data do
not identify.
"""

import functools
import time as _time
from collections.abc import Mapping, Sequence

import jax
import jax.numpy as jnp
import numpy as np
from numpyro.distributions import biject_to, constraints

from teflon_jax.systems import sample_velocity

from ..bearing_fit import (
    PARAMETER_NAMES,
    as_records,
    fit_bearing_test,
    simulate_record_force,
)
from ._model import (
    NOISE_RANGE,
    base_name,
    make_postprocess,
    model_args,
    prior_values,
    shapes_of,
    unconstrain,
)
from ._priors import PHYSICAL, _checked_range, build_priors
from ._result import BayesResult, diagnose_run
from ._sampler import SamplingInterrupted, block_length, compiled_sampler, sample_uncached

MIN_SAMPLES_PER_PARAMETER = 20
"""A record set needs at least this many samples per sampled variable (constants + noise)."""

def _as_records(records):
    records = as_records(records)
    for i, r in enumerate(records):
        if r.is_digitised:
            raise ValueError(f"records[{i}]: the Bayesian fit takes time histories; a digitised "
                             "loop has no noise model (fit it with fit_bearing_test).")
    return records


def _count_reversals(ux) -> int:
    du = np.diff(np.asarray(ux, dtype=float))
    tol = 1e-9 * max(float(np.ptp(ux)), 1e-300)
    sign = np.sign(np.where(np.abs(du) > tol, du, 0.0))
    sign = sign[sign != 0]
    return int(np.count_nonzero(sign[1:] != sign[:-1]))


def _check_sample_count(records, free_names):
    n_total = sum(r.ux.size for r in records)
    n_vars = len(free_names) + len(records)
    if n_total < MIN_SAMPLES_PER_PARAMETER * n_vars:
        raise ValueError(
            f"records: {n_total} samples for {n_vars} sampled variables ({', '.join(free_names)} "
            f"and the noise level); need at least {MIN_SAMPLES_PER_PARAMETER} per variable. Use a "
            "longer record or fix parameters.")


@functools.partial(jax.jit, static_argnums=(7, 8))
def _record_force(values, time, ux, load, velocity, z0, z_peak0, parallel, series):
    """`simulate_record_force` compiled once per record length (the record is data)."""
    return simulate_record_force(values, time, ux, load, z0=z0, z_peak0=z_peak0,
                                 velocity=velocity, interfaces_in_parallel=parallel,
                                 interfaces_in_series=series)


def _record_data(records, fit, normal_load):
    """Arrays of each record, and the initial state that reproduces the least-squares fit."""
    data = []
    values = dict(fit.parameters)
    for i, (record, res) in enumerate(zip(records, fit.records)):
        n = (int(record.metadata.get("interfaces_in_parallel", 1)),
             int(record.metadata.get("interfaces_in_series", 1)))
        load = (np.asarray(record.normal_load, dtype=float) if record.normal_load is not None
                else np.full(record.ux.shape, float(normal_load)))
        time, ux = np.asarray(record.time, dtype=float), np.asarray(record.ux, dtype=float)
        fx = np.asarray(record.fx, dtype=float)
        velocity = sample_velocity(time, ux)  # the fitter's convention
        # candidates: from rest (z0 = 0, z_peak0 = 0), or in steady cycling (z_peak0 = 1, z0
        # such that the first fitted force is matched); keep the one the LS fit used.
        best = None
        for z_peak0 in (0.0, 1.0):
            unit = np.asarray(_record_force(values, time, ux, load, velocity, 1.0, z_peak0, *n))
            z0 = 0.0 if z_peak0 == 0.0 else float(np.clip(res.fitted[0] / unit[0], -1.0, 1.0))
            force = np.asarray(_record_force(values, time, ux, load, velocity, z0, z_peak0, *n))
            err = float(np.max(np.abs(force - res.fitted)))
            if best is None or err < best[0]:
                best = (err, z0, z_peak0)
        data.append(dict(time=time, ux=ux, velocity=velocity, load=load, fx=fx, z0=best[1],
                         z_peak0=best[2],
                         scale=float(np.sqrt(np.mean(fx**2))), n_interfaces=n, index=i))
    return data


def _chain_starts(priors, fit, data, num_chains, seed):
    """Per-chain starts (unconstrained): the LS estimate, jittered by its standard errors."""
    rng = np.random.default_rng(seed)
    values = {}
    for name, p in priors.items():
        x = fit.parameters[name]
        if name == "delta_f":
            x = x / fit.parameters["f_max"]
        se = fit.std_errors.get(name, np.inf)
        rel = se / abs(fit.parameters[name]) if np.isfinite(se) and fit.parameters[name] else 0.1
        rel = float(np.clip(rel, 1e-3, 0.1))
        span = p.high - p.low
        xs = []
        for _ in range(num_chains):
            xi = x * np.exp(rel * rng.standard_normal())
            xi = float(np.clip(xi, p.low + 1e-3 * span, p.high - 1e-3 * span))
            if p.scale == "log1":
                xi = max(xi, 1.0 + 1e-3 * (p.high - 1.0))
            xs.append(xi)
        values[name] = jnp.asarray(xs)
    out = unconstrain(shapes_of(priors), values, prior_values(priors))
    noise = []
    for rec, res in zip(data, fit.records):
        lo, hi = NOISE_RANGE
        noise.append(np.clip(res.rms_residual / rec["scale"], 2 * lo, 0.5 * hi))
    noise = np.asarray(noise)
    starts = noise[None, :] * np.exp(0.05 * rng.standard_normal((num_chains, noise.size)))
    out["noise_rel"] = jnp.asarray(
        biject_to(constraints.interval(*NOISE_RANGE)).inv(jnp.asarray(starts)))
    return out


@functools.partial(jax.jit, static_argnums=(0, 1))
def _jacobian(shapes, free, x0, f_max, values_of_priors):
    """d(unconstrained coordinates) / d(free constants `free` at `x0`), delta_f as delta_f /
    f_max (`f_max` where it is held); compiled once per free set."""

    def unconstrained(x):
        phys = dict(zip(free, x))
        ratio = phys.get("f_max", f_max)
        return unconstrain(shapes, {name: phys[name] / ratio if name == "delta_f" else phys[name]
                                    for name, _ in shapes}, values_of_priors)

    return jax.jacfwd(unconstrained)(x0)


def _initial_mass(priors, fit, data):
    """Inverse mass matrix for NUTS from the least-squares covariance (Laplace approximation).

    The covariance of the free constants, `C = S R S` (standard errors S, correlation R), is
    carried to the sampler's unconstrained coordinates by the delta method, `J C J^T`; the
    noise levels get var(log sigma) = 1 / (2 n). Constants without a finite standard error
    get unit variance. Warm-up still adapts the matrix; the start only spares it the long
    trajectories of an identity metric on a posterior that is 1e-3 wide.
    """
    free = tuple(fit.free)
    x0 = jnp.asarray([fit.parameters[n] for n in free])
    jac = _jacobian(shapes_of(priors), free, x0, float(fit.parameters["f_max"]),
                    prior_values(priors))
    se = np.array([fit.std_errors.get(n, np.inf) for n in free])
    corr = np.nan_to_num(np.asarray(fit.correlation, dtype=float), nan=0.0)
    good = np.isfinite(se)
    se_ok = np.where(good, se, 0.0)
    cov = se_ok[:, None] * corr * se_ok[None, :]
    sites = sorted([base_name(p) for p in priors.values()] + ["noise_rel"])
    blocks, size = {}, 0
    for site in sites:
        n = len(data) if site == "noise_rel" else 1
        blocks[site] = slice(size, size + n)
        size += n
    mass = np.zeros((size, size))
    rows = {site: np.asarray(jac[site]) for site in jac}
    for a in rows:
        for b in rows:
            mass[blocks[a], blocks[b]] = rows[a] @ cov @ rows[b]
    for p in priors.values():
        i = blocks[base_name(p)].start
        involved = np.abs(rows[base_name(p)]) > 0
        if not np.all(good[involved]) or not mass[i, i] > 0:
            mass[i, :] = 0.0
            mass[:, i] = 0.0
            mass[i, i] = 1.0
    lo, hi = NOISE_RANGE
    for k, (rec, res) in enumerate(zip(data, fit.records)):
        x = float(np.clip(res.rms_residual / rec["scale"], 2 * lo, 0.5 * hi))
        du_dx = (hi - lo) / ((x - lo) * (hi - x))
        i = blocks["noise_rel"].start + k
        mass[i, i] = (du_dx * x) ** 2 / (2.0 * rec["fx"].size)
    return jnp.asarray(mass + 1e-12 * np.trace(mass) * np.eye(size))


def _check_request(records, free, bounds, num_chains):
    """The refusals of `fit_bayes` that need no fit (biaxial, no reversal, one chain, a
    prior range outside the physical one, too few samples for the free set given)."""
    for i, r in enumerate(records):
        if r.is_biaxial:
            name = r.path.name if r.path is not None else f"record {i}"
            raise ValueError(f"{name}: biaxial records are not sampled yet; fit them by least "
                             "squares (fit_bearing_test), which gives the P and T constants.")
        if _count_reversals(r.ux) < 1:
            name = r.path.name if r.path is not None else f"record {i}"
            raise ValueError(
                f"{name}: the motion never reverses, so the record has no hysteresis loop and "
                "does not separate friction from the elastic branch; use a cyclic test.")
    if num_chains < 2:
        raise ValueError("num_chains: R-hat needs at least 2 chains.")
    for name, pair in dict(bounds or {}).items():
        if name not in PHYSICAL:
            raise ValueError(f"bounds: unknown parameter '{name}'; the parameters are "
                             f"{', '.join(PARAMETER_NAMES)}.")
        if name != "delta_f":
            _checked_range(name, pair)
    if free is not None:
        _check_sample_count(records, tuple(free))


def fit_bayes(
    records,
    *,
    free: Sequence[str] | None = None,
    fixed: Mapping[str, float] | None = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    prior: str = "bounds",
    normal_load: float | None = None,
    num_warmup: int = 1000,
    num_samples: int = 1000,
    num_chains: int = 4,
    seed: int = 0,
    target_accept: float = 0.9,
    rhat_max: float = 1.01,
    ess_min_per_chain: float = 100.0,
    least_squares=None,
    progress_bar: bool = False,
    on_block=None,
    reuse_compiled: bool = True,
) -> BayesResult:
    """Posterior of the 1990 model's constants and of the noise level, sampled with NUTS.

    **Arguments:**

    - `records`: a time-history `TestRecord` or a list of them (one interface).
    - `free`, `fixed`, `normal_load`: as `fit_bearing_test` (default free set: its default).
    - `bounds`: name -> (lower, upper) prior range (SI); must lie inside the physical range.
    - `prior`: `"bounds"` (log-uniform on the ranges) or `"table1"` (informative, from the
      spread of Table 1 of the paper); see `identification.bayes._priors`.
    - `num_warmup`, `num_samples`, `num_chains`, `seed`: NUTS settings (chains vectorised).
    - `rhat_max`, `ess_min_per_chain`: convergence thresholds; a run with any divergence, an
      R-hat above `rhat_max` or a bulk/tail ESS below `ess_min_per_chain * num_chains` is
      reported `converged=False` with the reason in `messages`.
    - `least_squares`: a `BearingFit` of these records to start from (else it is computed).
    - `progress_bar`: numpyro's bar on stderr (warm-up, then each block of draws, with the
      time left).
    - `on_block`: called as `on_block(done, total)` (draws per chain) after the warm-up
      (`done = 0`) and after each block of draws (`block_length`).
    - `reuse_compiled`: run the compiled sampler kept for records of this shape (same sample
      counts, free set, interfaces, chains and warm-up; `identification.bayes._sampler`),
      so that many fits in one process compile once and keep their memory flat; `False`
      makes and compiles a numpyro `MCMC` for this fit alone (the earlier way, whose
      compiled programs accumulate fit after fit).

    **Returns:** a `BayesResult`.

    **Raises:** `SamplingInterrupted` (a `KeyboardInterrupt`) on Ctrl-C, carrying the result
    of the blocks of draws finished so far.

    Refused (`ValueError` with the reason): digitised loops, a record without a reversal of
    the motion, fewer than `MIN_SAMPLES_PER_PARAMETER` samples per sampled variable, a prior
    range outside the physical range, an unknown prior.
    """
    records = _as_records(records)
    _check_request(records, free, bounds, num_chains)
    t0 = _time.perf_counter()
    fit = least_squares if least_squares is not None else fit_bearing_test(
        records, free=free, fixed=fixed, normal_load=normal_load)
    t_ls = _time.perf_counter() - t0
    free_names = tuple(fit.free)
    _check_sample_count(records, free_names)
    data = _record_data(records, fit, normal_load)
    arrays = []
    for d in data:
        arrays.append({k: jnp.asarray(d[k]) for k in ("time", "ux", "velocity", "load", "fx", "z0",
                                                      "z_peak0", "scale")})
    priors = build_priors(free_names, data, prior=prior, bounds=bounds)
    fixed_values = {k: float(v) for k, v in fit.parameters.items()
                    if k not in free_names and v is not None}
    shapes = {name: p.shape for name, p in priors.items()}
    statics = (shapes, tuple(fixed_values), tuple(d["n_interfaces"] for d in data))
    args = model_args(priors, fixed_values, arrays)
    block = block_length(num_samples)
    starts = _chain_starts(priors, fit, data, num_chains, seed)
    inverse_mass = _initial_mass(priors, fit, data)
    t1 = _time.perf_counter()
    if reuse_compiled:
        sampler = compiled_sampler(*statics, [d["fx"].size for d in data],
                                   num_warmup=num_warmup, num_chains=num_chains,
                                   target_accept=target_accept)
        base, diverging, interrupted = sampler.run(
            jax.random.PRNGKey(seed), starts, inverse_mass, args, num_samples=num_samples,
            block=block, on_block=on_block, progress_bar=progress_bar)
        base = None if base is None else make_postprocess(priors)(base)
    else:
        base, diverging, interrupted = sample_uncached(
            *statics, jax.random.PRNGKey(seed), starts, inverse_mass, args,
            num_warmup=num_warmup, num_samples=num_samples, num_chains=num_chains,
            target_accept=target_accept, block=block, postprocess=make_postprocess(priors),
            on_block=on_block, progress_bar=progress_bar)
    elapsed = _time.perf_counter() - t1
    result = None if base is None else diagnose_run(
        base, diverging, priors, fit, data, rhat_max=rhat_max,
        ess_min=ess_min_per_chain * num_chains, elapsed=elapsed, elapsed_least_squares=t_ls,
        prior=prior, interrupted=interrupted, seed=seed)
    if interrupted is not None:
        raise SamplingInterrupted(result)
    return result
