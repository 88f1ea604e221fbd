"""Which parameters are free, their start values, bounds and bijections; the fit's result objects."""

import dataclasses
import math
from collections.abc import Sequence

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from teflon_jax.bearing import DEFAULT_YIELD_DISP, PARAMETER_BOUNDS

from ..least_squares import (
    LeastSquaresResult,
    correlation_from_covariance,
    covariance_from_jacobian,
)
from ._loop_features import _MIN_ELASTIC_SAMPLES, PreparedBiaxialRecord, PreparedRecord
from ._model import PARAMETER_NAMES, PARAMETER_UNITS
from ._ratio import RATIO_PAIRS, from_ratios, to_ratios
from ._record_force import PERPENDICULAR_NAMES

ASYMMETRY_LIMIT = 0.05
"""A record whose mean residual while moving in +x and in -x differ by more than this fraction
of its RMS force gets an asymmetric-misfit warning (the fit is then not clean)."""

RELATIVE_ERROR_LIMIT = 0.5
"""A free parameter whose standard error exceeds this fraction of its value is reported as
poorly determined, and the fit is not clean."""

# ---------------------------------------------------------------------------------------------
# Results


@dataclasses.dataclass
class RecordResidual:
    """Fit quality of one record: `nrmse` = RMS(model - measured) / RMS(measured)."""

    name: str
    nrmse: float
    rms_residual: float
    measured: np.ndarray
    fitted: np.ndarray
    ux: np.ndarray
    time: np.ndarray | None
    mean_residual_positive: float
    mean_residual_negative: float
    uy: np.ndarray | None = None  # biaxial records: measured and fitted stack (fx, fy)


@dataclasses.dataclass
class BearingFit:
    """Result of a bearing fit (SI).

    - `parameters`: all five parameters (fixed ones at their fixed value; `breakaway_ratio`
      `None` when the model has no breakaway).
    - `free`: names of the fitted parameters; `std_errors` and `correlation` refer to them.
    - `converged`, `message`, `n_steps`: status of the optimistix solve.
    - `nrmse`: over all records; `records`: per-record metrics and loops.
    - `warnings`: identifiability and fit-quality warnings (text).
    - `clean`: True only for a converged fit in which every free parameter is identifiable,
      has a relative standard error at most `RELATIVE_ERROR_LIMIT` (50 %) and is off its
      bounds, and no record or plan warning applies; high correlations alone (with small
      standard errors) are reported in `warnings` but leave the fit clean. When the friction
      law was reduced (below), `clean` refers to the reduced model that was fitted: the
      reduction is what the records determine, so it alone does not make a fit unclean.
    - `start`: the start that won the multi-start; `n_starts`.
    - `condition_number`: of the Jacobian with each column scaled to unit norm (the
      conditioning of the fit independent of the parameters' units; 1 for orthogonal
      directions, above ~1e4 for directions the records hardly separate).
    - `reduced`: name -> what was done with a constant of Eq. 1 that the records do not
      determine (held, or fixed for Coulomb friction); empty when nothing was reduced.
      `reduction`: why, with the numbers; `full_model`: the full fit that showed it
      (parameters, standard errors, nrmse, status). See `identification.bearing_fit._reduce`.
    """

    parameters: dict
    std_errors: dict
    correlation: np.ndarray
    free: tuple
    converged: bool
    message: str
    n_steps: int
    cost: float
    nrmse: float
    records: list
    warnings: list
    start: dict
    n_starts: int
    clean: bool = False
    condition_number: float = math.nan
    reduced: dict = dataclasses.field(default_factory=dict)
    reduction: str = ""
    full_model: dict | None = None

    def to_json_dict(self) -> dict:
        """The JSON report of the CLI (SI units)."""
        def clean(x):
            if x is None:
                return None
            x = float(x)
            return x if math.isfinite(x) else None

        corr = [[clean(c) for c in row] for row in np.asarray(self.correlation)]
        return {
            "parameters": {k: clean(v) for k, v in self.parameters.items()},
            "units": dict(PARAMETER_UNITS),
            "free": list(self.free),
            "std_errors": {k: clean(v) for k, v in self.std_errors.items()},
            "correlation": corr,
            "nrmse": clean(self.nrmse),
            "records": [
                {"name": r.name, "nrmse": clean(r.nrmse), "rms_residual [N]": clean(r.rms_residual),
                 "mean_residual_positive_velocity [N]": clean(r.mean_residual_positive),
                 "mean_residual_negative_velocity [N]": clean(r.mean_residual_negative)}
                for r in self.records
            ],
            "converged": bool(self.converged),
            "clean": self.clean,
            "message": self.message,
            "n_steps": int(self.n_steps),
            "warnings": list(self.warnings),
            "condition_number": clean(self.condition_number),
            "reduced": dict(self.reduced),
            "reduction": self.reduction or None,
            "full_model": None if self.full_model is None else {
                "parameters": {k: clean(v) for k, v in self.full_model["parameters"].items()},
                "free": list(self.full_model["free"]),
                "std_errors": {k: clean(v) for k, v in self.full_model["std_errors"].items()},
                "nrmse": clean(self.full_model["nrmse"]),
                "converged": self.full_model["converged"],
                "message": self.full_model["message"],
                "condition_number": clean(self.full_model["condition_number"]),
            },
        }


# ---------------------------------------------------------------------------------------------
# Fitting


def _check_names(names, what):
    unknown = [n for n in names if n not in PARAMETER_NAMES]
    if unknown:
        raise ValueError(
            f"{what}: unknown parameter {', '.join(repr(u) for u in unknown)}; the parameters "
            f"are {', '.join(PARAMETER_NAMES)}."
        )


def parse_free(text: str) -> tuple[str, ...]:
    """`"f_max,delta_f"` -> `("f_max", "delta_f")`, checked against `PARAMETER_NAMES`."""
    names = tuple(n.strip() for n in text.split(",") if n.strip())
    if not names:
        raise ValueError("--free: give at least one parameter name, e.g. f_max,delta_f.")
    _check_names(names, "--free")
    if len(set(names)) != len(names):
        raise ValueError(f"--free: a parameter is named twice in '{text}'.")
    return names


def _plan(prepared: Sequence[PreparedRecord], free, fixed, initial, bounds):
    """Decide the free set, the fixed values, the starts and warnings for a joint fit."""
    fixed = dict(fixed or {})
    initial = dict(initial or {})
    bounds = dict(bounds or {})
    _check_names(fixed, "fixed")
    _check_names(initial, "initial")
    _check_names(bounds, "bounds")
    warnings = []
    first_motion = any(p.first_motion for p in prepared)
    in_plane = any(isinstance(p, PreparedBiaxialRecord) for p in prepared)
    coarse = all(p.elastic_samples < _MIN_ELASTIC_SAMPLES for p in prepared)
    explicit = free is not None
    if free is None:
        free = ["f_max", "delta_f", "rate_a"]
        if "yield_disp" not in fixed:
            if coarse:
                warnings.append(
                    "yield_disp: the sampling is too coarse to see the elastic branch (fewer "
                    f"than {_MIN_ELASTIC_SAMPLES} samples within 2 Y after a reversal); Y is "
                    f"held at {fixed.get('yield_disp', float(DEFAULT_YIELD_DISP)):.4g} m "
                    "(paper: 0.005 in).")
            else:
                free.append("yield_disp")
        if first_motion and "breakaway_ratio" not in fixed:
            free.append("breakaway_ratio")
        if in_plane:
            free += list(PERPENDICULAR_NAMES)
        free = [n for n in free if n not in fixed]
    free = tuple(free)
    _check_names(free, "free")
    both = sorted(set(free) & set(fixed))
    if both:
        raise ValueError(f"{', '.join(both)}: both free and fixed; choose one.")
    if not free:
        raise ValueError("free: no parameter left to fit.")
    if explicit:
        if "breakaway_ratio" in free and not first_motion:
            warnings.append(
                "breakaway_ratio: not identifiable; no record starts from rest (no first "
                "excursion), and b of Eq. 17 acts only there.")
        perpendicular = [n for n in PERPENDICULAR_NAMES if n in free]
        if perpendicular and not in_plane:
            raise ValueError(
                f"free: {', '.join(perpendicular)} need a biaxial record (ux, uy, fx, fy); "
                "uniaxial records slide along x only.")
        if "yield_disp" in free and coarse:
            warnings.append(
                "yield_disp: not identifiable; the sampling is too coarse to see the elastic "
                f"branch (fewer than {_MIN_ELASTIC_SAMPLES} samples within 2 Y after a reversal).")

    start = dict(prepared[0].start)
    if len(prepared) > 1:
        for key in start:
            start[key] = float(np.median([p.start[key] for p in prepared]))
    start.update({k: float(v) for k, v in initial.items()})
    values = dict(start)
    values.update({k: float(v) for k, v in fixed.items()})
    if "breakaway_ratio" not in free and "breakaway_ratio" not in fixed:
        values["breakaway_ratio"] = None
    anisotropic = any(n in free or n in fixed for n in PERPENDICULAR_NAMES)
    if anisotropic:
        missing = [n for n in PERPENDICULAR_NAMES if n not in free and n not in fixed]
        if missing:
            raise ValueError(
                f"{', '.join(missing)}: the perpendicular constants go together; free or fix "
                "all three (or none, for an isotropic bearing).")
    for name in PERPENDICULAR_NAMES:
        values.setdefault(name, values[name.removesuffix("_perpendicular")])
        start.setdefault(name, start[name.removesuffix("_perpendicular")])
    if "yield_disp" not in free and "yield_disp" not in fixed:
        values["yield_disp"] = float(DEFAULT_YIELD_DISP)
    for key in ("f_max", "delta_f", "rate_a", "yield_disp"):
        if key not in free and key not in fixed and key != "yield_disp":
            raise ValueError(
                f"{key}: not free, so give its value in fixed= (or --fixed).")
    for delta, f_max, _ in RATIO_PAIRS:
        if f_max in free and delta not in free and values[delta] >= start[f_max]:
            start[f_max] = 1.5 * values[delta]

    # identifiability of rate_a from the speeds of the time records
    rate = values["rate_a"] if "rate_a" not in free else start["rate_a"]
    lows = [getattr(p, "speed_low", None) for p in prepared]
    highs = [getattr(p, "speed_high", None) for p in prepared]
    lows = [x for x in lows if x is not None]
    highs = [x for x in highs if x is not None]
    if lows and ("rate_a" in free or "delta_f" in free):
        v_low, v_high = min(lows), max(highs)
        if math.exp(-rate * v_low) < 0.02:
            warnings.append(
                f"rate_a, delta_f: not identifiable; every sliding velocity (from "
                f"{v_low:.3g} m/s) is on the plateau of Eq. 1 (exp(-a v) < 0.02).")
        elif v_high < 1.5 * v_low:
            warnings.append(
                f"f_max, delta_f, rate_a: not separately identifiable; the sliding speed "
                f"hardly varies ({v_low:.3g} to {v_high:.3g} m/s).")

    values["anisotropic"] = anisotropic
    return free, values, start, warnings


RATE_NAMES = ("rate_a", "rate_a_perpendicular")
"""The rates of Eq. 1, bounded by their search range (`PARAMETER_BOUNDS`) rather than by 0."""

_DEFAULT_BOUNDS = {name: PARAMETER_BOUNDS[name].search if name in RATE_NAMES
                   else PARAMETER_BOUNDS[name].physical for name in PARAMETER_NAMES}
"""Bounds of a free parameter the caller does not bound: its physical range (the delta_f are
fitted as ratios to f_max in (0, 1) instead), except the rates, kept in their search range
(0.005 to 50 s/in). Towards rate_a = 0 Eq. 1 tends to a straight line in the speed,
`mu = (f_max - delta_f) + delta_f rate_a |v|`, reached only as delta_f and f_max grow without
bound: a record whose friction rises linearly over its speeds has its least-squares minimum
there, at infinity, and the solve would creep after it for ever. The lower rate bounds it: the
minimum is then on the bound, with finite f_max and delta_f, where the solve ends."""


def _internal(free, values, start, bounds):
    """Internal names, bounds, and a function start -> internal start."""
    bounds = dict(bounds or {})
    ratio = any(delta in free for delta, _, _ in RATIO_PAIRS)
    pairs = {delta: (f_max, internal) for delta, f_max, internal in RATIO_PAIRS}
    names, internal_bounds = [], {}
    for name in free:
        if name in pairs:
            f_max, internal = pairs[name]
            names.append(internal)
            lo, hi = 0.0, 1.0
            if name in bounds:
                if f_max in free:
                    raise ValueError(
                        f"bounds['{name}']: cannot bound {name} while {f_max} is free ({name} "
                        f"is kept between 0 and {f_max}); bound {f_max} instead or fix it.")
                f = values[f_max]
                lo, hi = max(bounds[name][0] / f, 0.0), min(bounds[name][1] / f, 1.0)
            internal_bounds[internal] = (lo, hi)
        else:
            names.append(name)
            lo, hi = bounds.get(name, _DEFAULT_BOUNDS[name])
            delta = name.replace("f_max", "delta_f")
            if name in ("f_max", "f_max_perpendicular") and delta not in free:
                lo = max(lo, values[delta])
            internal_bounds[name] = (lo, hi)

    def to_internal(s):
        return to_ratios({name: s[name] for name in free}, RATIO_PAIRS, values)

    return tuple(names), internal_bounds, to_internal, ratio


def _multi_starts(start, free, n_starts):
    """The feature start and perturbations of the poorly known parameters."""
    factors = [
        {}, {"rate_a": 0.3}, {"rate_a": 3.0}, {"yield_disp": 0.4}, {"yield_disp": 2.5},
        {"delta_f": 0.6, "rate_a": 0.6}, {"delta_f": 1.2, "rate_a": 2.0},
        {"breakaway_ratio": 1.5, "yield_disp": 0.7},
    ]
    starts = []
    for f in factors[: max(1, n_starts)]:
        s = dict(start)
        for k, m in f.items():
            if k == "breakaway_ratio":
                s[k] = 1.0 + (s[k] - 1.0) * m
            else:
                s[k] = s[k] * m
        if s["delta_f"] >= 0.97 * s["f_max"]:
            s["delta_f"] = 0.9 * s["f_max"]
        for k, m in f.items():
            if k in ("delta_f", "rate_a") and f"{k}_perpendicular" in s:
                s[f"{k}_perpendicular"] = start[f"{k}_perpendicular"] * m
        if s["delta_f_perpendicular"] >= 0.97 * s["f_max_perpendicular"]:
            s["delta_f_perpendicular"] = 0.9 * s["f_max_perpendicular"]
        starts.append(s)
    return starts


def _fixed_tree(values):
    return {k: None if v is None else jnp.asarray(v, dtype=float) for k, v in values.items()
            if k in PARAMETER_NAMES}


def _pad(arrays, length):
    """Pad a time record to `length` samples: time continues, nothing moves, weight 0."""
    n = arrays["time"].size
    if n == length:
        return arrays
    extra = length - n
    dt = arrays["time"][-1] - arrays["time"][-2]
    out = dict(arrays)
    out["time"] = np.concatenate([arrays["time"], arrays["time"][-1] + dt * np.arange(1, extra + 1)])
    for key in ("ux", "fx", "load"):
        out[key] = np.concatenate([arrays[key], np.full(extra, arrays[key][-1])])
    out["velocity"] = np.concatenate([arrays["velocity"], np.zeros(extra)])
    out["weight"] = np.concatenate([arrays["weight"], np.zeros(extra)])
    return out


def _stack(trees):
    return jax.tree_util.tree_map(lambda *xs: jnp.stack([jnp.asarray(x) for x in xs]), *trees)


def _tree_index(tree, i):
    return jax.tree_util.tree_map(lambda x: x[i], tree)


@eqx.filter_jit
def _user_jacobian(model, x, names, args):
    def residual(xx):
        params = {n: xx[i] for i, n in enumerate(names)}
        return model(params, args)

    return jax.jacfwd(residual)(x), model.forces({n: x[i] for i, n in enumerate(names)}, args)


def _finish(prepared, model_user, free, values, raw: LeastSquaresResult, args, warnings, start,
            n_starts):
    """Standard errors in the user's parameters, residual metrics and warnings."""
    estimate = {k: v for k, v in values.items() if k in PARAMETER_NAMES}
    estimate.update(from_ratios(raw.parameters, RATIO_PAIRS, values))
    if not model_user.anisotropic:
        for name in PERPENDICULAR_NAMES:
            estimate.pop(name, None)
    x = jnp.asarray([estimate[n] for n in free])
    jac, forces = _user_jacobian(model_user, x, free, args)
    jac = np.asarray(jac)
    used = np.concatenate([np.asarray(rec["weight"]) > 0 for rec in args["records"]])
    cov, notes = covariance_from_jacobian(jac[used], raw.residual[used])
    std = np.sqrt(np.abs(np.diag(cov)))
    condition = _scaled_condition(jac[used])
    warnings = list(warnings)
    for i, name in enumerate(free):
        if not np.isfinite(std[i]):
            warnings.append(f"{name}: not identifiable from these records (singular Jacobian).")
        elif std[i] > RELATIVE_ERROR_LIMIT * abs(estimate[name]):
            warnings.append(
                f"{name}: poorly determined; standard error {std[i]:.3g} is "
                f"{std[i] / max(abs(estimate[name]), 1e-300):.0%} of the estimate "
                f"{estimate[name]:.4g} (limit {RELATIVE_ERROR_LIMIT:.0%}).")
    corr = correlation_from_covariance(cov)
    notes = []
    for i in range(len(free)):
        for j in range(i + 1, len(free)):
            if np.isfinite(corr[i, j]) and abs(corr[i, j]) > 0.99:
                notes.append(
                    f"{free[i]}, {free[j]}: correlation {corr[i, j]:.3f}; the records hardly "
                    "separate them.")
    for delta, f_max, internal in RATIO_PAIRS:
        if delta in free and raw.parameters[internal] > 0.995:
            warnings.append(f"{delta}: at its bound ({f_max} - {delta} -> 0).")
    if "breakaway_ratio" in free and estimate["breakaway_ratio"] < 1.005:
        warnings.append("breakaway_ratio: at its lower bound 1.")
    for name in RATE_NAMES:
        if name in free and estimate[name] < 1.001 * _DEFAULT_BOUNDS[name][0]:
            warnings.append(f"{name}: at its lower bound {_DEFAULT_BOUNDS[name][0]:.4g} s/m (0.005 s/in): the "
                            "friction rises about linearly over the tested speeds.")
    if not raw.converged:
        warnings.append(f"solver: {raw.message}; the estimates are not a converged optimum.")
    records = []
    total_res, total_meas = 0.0, 0.0
    for p, f in zip(prepared, forces):
        f = np.asarray(f)[: p.measured.size] if p.kind == "time" else np.asarray(f)
        r = f - p.measured
        total_res += float(np.sum(r**2))
        total_meas += float(np.sum(p.measured**2))
        v = p.residual_velocity
        pos, neg = r[v > 0], r[v < 0]
        records.append(RecordResidual(
            name=p.name,
            nrmse=float(np.sqrt(np.mean(r**2)) / np.sqrt(np.mean(p.measured**2))),
            rms_residual=float(np.sqrt(np.mean(r**2))),
            measured=p.measured, fitted=f, ux=p.ux, time=p.time,
            mean_residual_positive=float(pos.mean()) if pos.size else float("nan"),
            mean_residual_negative=float(neg.mean()) if neg.size else float("nan"),
            uy=p.uy,
        ))
        warnings.extend(f"{p.name}: {w}" for w in p.warnings)
        scale = math.sqrt(float(np.mean(p.measured**2)))
        if pos.size and neg.size and abs(pos.mean() - neg.mean()) > ASYMMETRY_LIMIT * scale:
            warnings.append(
                f"{p.name}: asymmetric misfit; the mean residual is {pos.mean():.4g} N while "
                f"moving in +x and {neg.mean():.4g} N in -x, a difference of "
                f"{abs(pos.mean() - neg.mean()) / scale:.0%} of the RMS force: the measured "
                "friction differs between the two directions, which the symmetric model "
                "cannot follow.")
    clean = bool(raw.converged and not warnings)
    message = raw.message
    return BearingFit(
        parameters={k: (None if v is None else float(v)) for k, v in estimate.items()},
        std_errors={n: float(std[i]) for i, n in enumerate(free)},
        correlation=corr,
        free=tuple(free),
        converged=raw.converged,
        message=message,
        n_steps=raw.n_steps,
        cost=raw.cost,
        nrmse=float(math.sqrt(total_res / total_meas)),
        records=records,
        warnings=warnings + notes,
        start=start,
        n_starts=n_starts,
        clean=clean,
        condition_number=condition,
    )


def _scaled_condition(jac) -> float:
    """Condition number of `jac` with its columns scaled to unit norm (inf when singular)."""
    norms = np.linalg.norm(jac, axis=0)
    if not np.all(np.isfinite(jac)) or np.any(norms == 0):
        return math.inf
    s = np.linalg.svd(jac / norms, compute_uv=False)
    return float(s[0] / s[-1]) if s[-1] > 0 else math.inf
