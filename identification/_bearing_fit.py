"""Fit the constants of a PTFE bearing model to bearing tests.

The model is the one of Constantinou, Mokha & Reinhorn (1990): the force is

    F = mu N Z,   mu = f_max - delta_f exp(-rate_a |v| / n)        (Eq. 1, n interfaces in series)
                  mu = breakaway_ratio (f_max - delta_f)            (Eq. 17, before max|Z| >= 0.999)

with Z from Bouc-Wen (Eq. 3; A = 1, beta = 0.1, gamma = 0.9, eta = 2, yield displacement
`yield_disp`). The fitter minimises the force residual, sample by sample, of the core model (the exact Riccati
update of Z at the record's own samples, the computation of `teflon_jax.simulate_bearing_test`
with a `tabulated_motion` and its default `RiccatiNewmark` solver; see `simulate_record_force`),
divided by the RMS measured force
of each record, with optimistix Levenberg-Marquardt and forward-mode Jacobians
(`identification._fit.fit_least_squares`).

Parameters (SI): `f_max` [-], `delta_f` [-], `rate_a` [s/m], `yield_disp` [m],
`breakaway_ratio` [-]. Inside the optimiser `delta_f` is written as `delta_ratio * f_max` with
`0 < delta_ratio < 1` (so that `f_max - delta_f > 0` always), `breakaway_ratio > 1`, the others
`> 0`; standard errors are reported in the parameters above.

Normal load: the `N` column of the record, else its constant `normal_load` (or
`contact_area * contact_pressure`) metadata, else the `normal_load=` argument. A record with
none of these is an error. The friction damper of the ARTS Laboratory has no normal load: fit it
with `normal_load=1.0`, so that `F = mu Z` and `f_max`, `delta_f` come out in newtons.
"""

import dataclasses
import math
from collections.abc import Mapping, Sequence
from typing import Any

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from teflon_jax._bearing import DEFAULT_YIELD_DISP, SlidingBearing
from teflon_jax._bearing_test import force_along_path
from teflon_jax._friction import FrictionParameters
from teflon_jax._hysteresis import BoucWen
from teflon_jax._records import TestRecord

from ._fit import (
    LeastSquaresResult,
    _correlation,
    check_bounds,
    covariance_from_jacobian,
    fit_least_squares_batch,
)

PARAMETER_NAMES = ("f_max", "delta_f", "rate_a", "yield_disp", "breakaway_ratio")
"""Parameters the fitter can free, in the order of the reports."""

PARAMETER_UNITS = {
    "f_max": "-", "delta_f": "-", "rate_a": "s/m", "yield_disp": "m", "breakaway_ratio": "-",
}

# x at which Z crosses 0 after a reversal from Z = -1 (Bouc-Wen, A = 1, gamma - beta = 0.8):
# x = atan(sqrt(gamma - beta)) / sqrt(gamma - beta), in units of Y.
_ZERO_CROSSING = math.atan(math.sqrt(0.8)) / math.sqrt(0.8)
_MIN_ELASTIC_SAMPLES = 3


# ---------------------------------------------------------------------------------------------
# Data prepared for the residual


@dataclasses.dataclass
class PreparedRecord:
    """A record ready for fitting (numpy, SI): what the residual needs and what was detected.

    - `name`: the file name or `record <i>`.
    - `kind`: `"time"` (a time history) or `"digitised"` (points of a loop plus a protocol).
    - `arrays`: the pytree of arrays passed to the residual.
    - `first_motion`: whether the record starts from rest (contains the first excursion).
    - `start`: feature-based start values of all five parameters.
    - `warnings`: identifiability and data warnings.
    - `elastic_samples`: median number of samples within 2 Y after a reversal.
    """

    name: str
    kind: str
    arrays: dict
    first_motion: bool
    start: dict
    warnings: list
    elastic_samples: float
    n_interfaces: int
    measured: np.ndarray
    ux: np.ndarray
    time: np.ndarray | None


def _record_name(record: TestRecord, index: int) -> str:
    return record.path.name if record.path is not None else f"record {index}"


def _normal_load(record: TestRecord, name: str, normal_load) -> np.ndarray:
    if record.normal_load is not None:
        return np.asarray(record.normal_load, dtype=float)
    if normal_load is None:
        raise ValueError(
            f"{name}: no normal load (no 'N' column and no 'normal_load' or 'contact_area' and "
            f"'contact_pressure' metadata); add one to the record, or pass normal_load=<N> to "
            f"the fitter (normal_load=1.0 fits the force itself, e.g. for the friction damper)."
        )
    value = np.asarray(normal_load, dtype=float)
    if value.ndim != 0 or not np.isfinite(value) or value <= 0:
        raise ValueError(f"normal_load: must be one positive number [N], got {normal_load!r}.")
    return np.full(record.ux.shape, float(value))


def _forward_velocity(time, ux):
    v = np.diff(ux) / np.diff(time)
    return np.concatenate([v, v[-1:]])


def _reversals(ux) -> np.ndarray:
    """Indices where the direction of motion changes (the sample at the extreme)."""
    du = np.diff(ux)
    sign = np.sign(du)
    # carry the last non-zero direction over pauses
    for i in range(1, sign.size):
        if sign[i] == 0:
            sign[i] = sign[i - 1]
    change = np.flatnonzero(sign[1:] * sign[:-1] < 0) + 1
    return change


def _excursion(ux, reversals) -> np.ndarray:
    """|u - u at the last reversal (or at the start)| for each sample."""
    anchors = np.zeros(ux.size, dtype=int)
    for r in reversals:
        anchors[r:] = r
    return np.abs(ux - ux[anchors])


def _friction_law_start(speed, mu_sliding):
    """Start values of (f_max, delta_f, rate_a) by a grid over rate_a and linear least squares."""
    v_ref = np.median(speed)
    best = None
    for a in np.geomspace(0.01, 30.0, 80) / max(v_ref, 1e-12):
        e = np.exp(-a * speed)
        design = np.stack([np.ones_like(e), -e], axis=1)
        coef, *_ = np.linalg.lstsq(design, mu_sliding, rcond=None)
        cost = np.sum((design @ coef - mu_sliding) ** 2)
        if coef[0] > 0 and 0 < coef[1] < coef[0] and (best is None or cost < best[0]):
            best = (cost, coef[0], coef[1], a)
    if best is None:
        f = float(np.median(mu_sliding))
        return f, 0.5 * f, 3.0 / max(v_ref, 1e-12)
    _, f_max, delta_f, a = best
    delta_f = float(np.clip(delta_f, 0.05 * f_max, 0.95 * f_max))
    return float(f_max), delta_f, float(a)


def _features_time(time, ux, fx, load, n_interfaces, name, yield_ref):
    """Loop features of a time history: starts, first motion, identifiability numbers."""
    v = _forward_velocity(time, ux)
    speed = np.abs(v) / n_interfaces
    reversals = _reversals(ux)
    excursion = _excursion(ux, reversals)
    stroke = float(np.ptp(ux))
    if excursion.max() < 3.0 * yield_ref:
        raise ValueError(
            f"{name}: the bearing never slides: the largest excursion between reversals "
            f"({excursion.max():.3g} m) is below 3 Y = {3 * yield_ref:.3g} m, so friction "
            f"and yield displacement cannot be told apart; use a test with a larger amplitude."
        )
    mu = fx / load
    sliding = (excursion > max(0.02 * stroke, 4.0 * yield_ref)) & (speed > 0)
    if np.count_nonzero(sliding) < 10:
        raise ValueError(
            f"{name}: fewer than 10 samples while sliding; the record is too short or the "
            f"amplitude too small to fit a friction law."
        )
    mu_s = mu[sliding] * np.sign(v[sliding])
    f_max, delta_f, rate_a = _friction_law_start(speed[sliding], mu_s)
    level = float(np.median(np.abs(mu[sliding])))

    # First excursion from rest: the record starts with (almost) no force and the first
    # reversal comes after the bearing has slid.
    first_end = reversals[0] if reversals.size else ux.size
    first_motion = bool(
        abs(mu[0]) < 0.2 * level and excursion[:first_end].max() > 4.0 * yield_ref
    )

    # Yield displacement from where the force changes sign after each reversal.
    y_estimates, counts = [], []
    for r in reversals:
        s_new = np.sign(v[r])
        seg = slice(r, min(r + 2000, ux.size))
        f_seg = fx[seg] * s_new
        d_seg = excursion[seg]
        positive = np.flatnonzero(f_seg > 0)
        if positive.size == 0 or f_seg[0] >= 0:
            continue
        j = positive[0]
        if j < 2:  # crossing not resolved by the sampling
            continue
        d0 = d_seg[j - 1] + (d_seg[j] - d_seg[j - 1]) * (-f_seg[j - 1]) / (f_seg[j] - f_seg[j - 1])
        y_estimates.append(d0 / _ZERO_CROSSING)
    yield_disp = float(np.median(y_estimates)) if y_estimates else float(DEFAULT_YIELD_DISP)
    if not np.isfinite(yield_disp) or yield_disp <= 0:
        yield_disp = float(DEFAULT_YIELD_DISP)
    for r in reversals:
        seg = excursion[r + 1: r + 2000]
        counts.append(int(np.count_nonzero(seg < 2.0 * yield_disp)))
    elastic = float(np.median(counts)) if counts else 0.0

    breakaway = 1.5
    if first_motion:
        early = excursion[:first_end] < 6.0 * yield_disp
        peak = float(np.max(np.abs(mu[:first_end][early]))) if early.any() else 0.0
        breakaway = float(np.clip(peak / (f_max - delta_f), 1.05, 20.0))
    return dict(
        start=dict(f_max=f_max, delta_f=delta_f, rate_a=rate_a, yield_disp=yield_disp,
                   breakaway_ratio=breakaway),
        first_motion=first_motion,
        elastic=elastic,
        speed_low=float(np.percentile(speed[sliding], 5)),
        speed_high=float(np.percentile(speed[sliding], 95)),
        level=level,
        z0=0.0 if first_motion else float(np.clip(mu[0] / max(level, 1e-300), -1.0, 1.0)),
    )


def prepare_record(record: TestRecord, *, index: int = 0, normal_load=None,
                   yield_ref: float | None = None) -> PreparedRecord:
    """Check a record and extract its loop features (see `PreparedRecord`)."""
    from ._digitised import prepare_digitised

    name = _record_name(record, index)
    if record.is_biaxial:
        raise ValueError(
            f"{name}: biaxial records (with 'uy') are not supported by the fitter yet; "
            f"fit a uniaxial test (ux, fx)."
        )
    n_interfaces = int(record.metadata.get("interfaces", 1))
    load = _normal_load(record, name, normal_load)
    if np.any(load <= 0):
        i = int(np.argmax(load <= 0))
        raise ValueError(f"{name}: normal load must be positive (compression); sample {i} is "
                         f"{load[i]} N.")
    yield_ref = float(DEFAULT_YIELD_DISP) if yield_ref is None else float(yield_ref)
    if record.is_digitised:
        return prepare_digitised(record, name=name, load=load, n_interfaces=n_interfaces,
                                 yield_ref=yield_ref)
    if record.ux.size < 10:
        raise ValueError(f"{name}: only {record.ux.size} samples; a fit needs a full loop.")
    time, ux, fx = (np.asarray(x, dtype=float) for x in (record.time, record.ux, record.fx))
    feats = _features_time(time, ux, fx, load, n_interfaces, name, yield_ref)
    scale = float(np.sqrt(np.mean(fx**2)))
    arrays = dict(
        time=time, ux=ux, fx=fx, load=load, weight=np.ones_like(time) / scale,
        z0=np.asarray(feats["z0"]), z_peak0=np.asarray(0.0 if feats["first_motion"] else 1.0),
    )
    warnings = []
    prepared = PreparedRecord(
        name=name, kind="time", arrays=arrays, first_motion=feats["first_motion"],
        start=feats["start"], warnings=warnings, elastic_samples=feats["elastic"],
        n_interfaces=n_interfaces, measured=fx, ux=ux, time=time,
    )
    prepared.speed_low = feats["speed_low"]
    prepared.speed_high = feats["speed_high"]
    return prepared


# ---------------------------------------------------------------------------------------------
# The model and its residual


def simulate_record_force(values: Mapping[str, Any], time, ux, load, *, z0=0.0, z_peak0=0.0,
                          use_breakaway: bool = True, n_interfaces: int = 1):
    """Force [N] of the model at the samples of a record (jit/vmap/grad-safe).

    The core's `teflon_jax.force_along_path` (a `lax.scan` of the exact Z update, the same
    computation as `simulate_bearing_test` with `RiccatiNewmark`) for a parameter dict;
    `tests/test_fit.py` checks it against `simulate_bearing_test`.

    **Arguments:** `values` with `f_max`, `delta_f`, `rate_a` [s/m], `yield_disp` [m],
    `breakaway_ratio`; `time` [s], `ux` [m], `load` [N] arrays of the samples.

    **Returns:** the force history [N] (same length as `time`).
    """
    bearing = SlidingBearing(
        friction=FrictionParameters(values["f_max"], values["delta_f"], values["rate_a"]),
        hysteresis=BoucWen(yield_disp=values["yield_disp"]),
        breakaway_ratio=values["breakaway_ratio"] if use_breakaway else None,
        n_interfaces=n_interfaces,
    )
    return force_along_path(bearing, time, ux, load, z0=z0, z_peak0=z_peak0)[0]


class BearingModel(eqx.Module):
    """Residual of the bearing fit (static configuration only; data come in `args`).

    `args = {"fixed": {name: value for all five}, "records": [arrays of each record]}`.
    With `ratio=True` the free `delta_f` is the parameter `delta_ratio = delta_f / f_max`.
    """

    free: tuple[str, ...] = eqx.field(static=True)
    kinds: tuple[str, ...] = eqx.field(static=True)
    n_interfaces: tuple[int, ...] = eqx.field(static=True)
    use_breakaway: bool = eqx.field(static=True)
    ratio: bool = eqx.field(static=True)

    def values(self, params, fixed):
        values = {name: params.get(name, fixed[name]) for name in PARAMETER_NAMES}
        if self.ratio and "delta_ratio" in params:
            values["delta_f"] = params["delta_ratio"] * values["f_max"]
        return values

    def _time_force(self, values, n, rec):
        return simulate_record_force(
            values, rec["time"], rec["ux"], rec["load"], z0=rec["z0"],
            z_peak0=rec["z_peak0"], use_breakaway=self.use_breakaway, n_interfaces=n)

    def forces(self, params, args):
        from ._digitised import digitised_model_force

        values = self.values(params, args["fixed"])
        return [
            self._time_force(values, n, rec) if kind == "time"
            else digitised_model_force(values, rec, use_breakaway=self.use_breakaway, n_interfaces=n)
            for kind, n, rec in zip(self.kinds, self.n_interfaces, args["records"])
        ]

    def __call__(self, params, args):
        from ._digitised import digitised_residual

        values = self.values(params, args["fixed"])
        out = []
        for kind, n, rec in zip(self.kinds, self.n_interfaces, args["records"]):
            if kind == "time":
                out.append((self._time_force(values, n, rec) - rec["fx"]) * rec["weight"])
            else:
                out.append(digitised_residual(values, rec, use_breakaway=self.use_breakaway,
                                              n_interfaces=n))
        return jnp.concatenate(out)


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


@dataclasses.dataclass
class BearingFit:
    """Result of a bearing fit (SI).

    - `parameters`: all five parameters (fixed ones at their fixed value; `breakaway_ratio`
      `None` when the model has no breakaway).
    - `free`: names of the fitted parameters; `std_errors` and `correlation` refer to them.
    - `converged`, `message`, `n_steps`: status of the optimistix solve.
    - `nrmse`: over all records; `records`: per-record metrics and loops.
    - `warnings`: identifiability and fit-quality warnings (text).
    - `start`: the start that won the multi-start; `n_starts`.
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
            "message": self.message,
            "n_steps": int(self.n_steps),
            "warnings": list(self.warnings),
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
    if "yield_disp" not in free and "yield_disp" not in fixed:
        values["yield_disp"] = float(DEFAULT_YIELD_DISP)
    for key in ("f_max", "delta_f", "rate_a", "yield_disp"):
        if key not in free and key not in fixed and key != "yield_disp":
            raise ValueError(
                f"{key}: not free, so give its value in fixed= (or --fixed).")
    if "f_max" in free and "delta_f" not in free and values["delta_f"] >= start["f_max"]:
        start["f_max"] = 1.5 * values["delta_f"]

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

    use_breakaway = values["breakaway_ratio"] is not None
    return free, values, start, warnings, use_breakaway


_DEFAULT_BOUNDS = {
    "f_max": (0.0, math.inf), "rate_a": (0.0, math.inf), "yield_disp": (0.0, math.inf),
    "breakaway_ratio": (1.0, math.inf),
}


def _internal(free, values, start, bounds):
    """Internal names, bounds, and a function start -> internal start."""
    bounds = dict(bounds or {})
    ratio = "delta_f" in free
    names, internal_bounds = [], {}
    for name in free:
        if name == "delta_f":
            names.append("delta_ratio")
            lo, hi = 0.0, 1.0
            if "delta_f" in bounds:
                if "f_max" in free:
                    raise ValueError(
                        "bounds['delta_f']: cannot bound delta_f while f_max is free (delta_f "
                        "is kept between 0 and f_max); bound f_max instead or fix it.")
                f = values["f_max"]
                lo, hi = max(bounds["delta_f"][0] / f, 0.0), min(bounds["delta_f"][1] / f, 1.0)
            internal_bounds["delta_ratio"] = (lo, hi)
        else:
            names.append(name)
            lo, hi = bounds.get(name, _DEFAULT_BOUNDS[name])
            if name == "f_max" and "delta_f" not in free:
                lo = max(lo, values["delta_f"])
            internal_bounds[name] = (lo, hi)

    def to_internal(s):
        out = {}
        for name in free:
            if name == "delta_f":
                f = s["f_max"] if "f_max" in free else values["f_max"]
                out["delta_ratio"] = s["delta_f"] / f
            else:
                out[name] = s[name]
        return out

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
        starts.append(s)
    return starts


def _fixed_tree(values):
    return {k: jnp.asarray(1.0 if v is None else v, dtype=float) for k, v in values.items()}


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
    estimate = dict(values)
    for name in free:
        if name == "delta_f":
            estimate["delta_f"] = raw.parameters["delta_ratio"] * (
                raw.parameters["f_max"] if "f_max" in free else values["f_max"])
        else:
            estimate[name] = raw.parameters[name]
    x = jnp.asarray([estimate[n] for n in free])
    jac, forces = _user_jacobian(model_user, x, free, args)
    jac = np.asarray(jac)
    used = np.concatenate([np.asarray(rec["weight"]) > 0 for rec in args["records"]])
    cov, notes = covariance_from_jacobian(jac[used], raw.residual[used])
    std = np.sqrt(np.abs(np.diag(cov)))
    warnings = list(warnings)
    for i, name in enumerate(free):
        if not np.isfinite(std[i]):
            warnings.append(f"{name}: not identifiable from these records (singular Jacobian).")
    corr = _correlation(cov)
    for i in range(len(free)):
        for j in range(i + 1, len(free)):
            if np.isfinite(corr[i, j]) and abs(corr[i, j]) > 0.99:
                warnings.append(
                    f"{free[i]}, {free[j]}: correlation {corr[i, j]:.3f}; the records hardly "
                    "separate them.")
    if "delta_f" in free and raw.parameters["delta_ratio"] > 0.995:
        warnings.append("delta_f: at its bound (f_max - delta_f -> 0).")
    if "breakaway_ratio" in free and estimate["breakaway_ratio"] < 1.005:
        warnings.append("breakaway_ratio: at its lower bound 1.")
    if not raw.converged:
        warnings.append(f"solver: {raw.message}; the estimates are not a converged optimum.")
    records = []
    total_res, total_meas = 0.0, 0.0
    for p, f in zip(prepared, forces):
        f = np.asarray(f)[: p.measured.size] if p.kind == "time" else np.asarray(f)
        r = f - p.measured
        total_res += float(np.sum(r**2))
        total_meas += float(np.sum(p.measured**2))
        if p.kind == "time":
            v = _forward_velocity(p.time, p.ux)
        else:
            v = p.arrays["branch"]
        pos, neg = r[v > 0], r[v < 0]
        records.append(RecordResidual(
            name=p.name,
            nrmse=float(np.sqrt(np.mean(r**2)) / np.sqrt(np.mean(p.measured**2))),
            rms_residual=float(np.sqrt(np.mean(r**2))),
            measured=p.measured, fitted=f, ux=p.ux, time=p.time,
            mean_residual_positive=float(pos.mean()) if pos.size else float("nan"),
            mean_residual_negative=float(neg.mean()) if neg.size else float("nan"),
        ))
        warnings.extend(f"{p.name}: {w}" for w in p.warnings)
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
        warnings=warnings,
        start=start,
        n_starts=n_starts,
    )


def _as_records(records):
    if isinstance(records, TestRecord):
        return [records]
    records = list(records)
    if not records:
        raise ValueError("records: give at least one test record.")
    for i, r in enumerate(records):
        if not isinstance(r, TestRecord):
            raise ValueError(f"records[{i}]: expected a TestRecord, got {type(r).__name__}.")
    return records


def fit_bearing_test(
    records,
    *,
    free: Sequence[str] | None = None,
    fixed: Mapping[str, float] | None = None,
    initial: Mapping[str, float] | None = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    normal_load: float | None = None,
    n_starts: int = 8,
    max_steps: int = 200,
    rtol: float = 1e-8,
    atol: float = 1e-8,
) -> BearingFit:
    """Fit one parameter set to one record, or jointly to several records of one interface.

    **Arguments:**

    - `records`: a `TestRecord` or a list of them (time histories and/or digitised loops).
    - `free`: names to fit among `PARAMETER_NAMES`. Default: f_max, delta_f, rate_a,
      yield_disp (unless the sampling is too coarse to see the elastic branch), and
      breakaway_ratio when a record starts from rest (contains the first excursion).
    - `fixed`: values of parameters held fixed (SI). `yield_disp` defaults to 0.005 in;
      `breakaway_ratio` not free and not fixed means no breakaway (Eq. 1 throughout).
    - `initial`: start values overriding the loop features; `bounds`: name -> (lower, upper).
    - `normal_load` [N]: for records without one (1.0 fits the force itself).
    - `n_starts`: number of starts (the feature start and perturbations), solved in one
      vmapped call; the lowest converged cost wins.

    **Returns:** a `BearingFit`.
    """
    records = _as_records(records)
    _check_names(free or (), "free")
    yield_ref = (fixed or {}).get("yield_disp")
    prepared = [prepare_record(r, index=i, normal_load=normal_load, yield_ref=yield_ref)
                for i, r in enumerate(records)]
    free, values, start, warnings, use_breakaway = _plan(prepared, free, fixed, initial, bounds)
    if normal_load is not None and any(r.normal_load is None for r in records):
        warnings.append(
            f"normal load: records without one were fitted with normal_load = {normal_load} N; "
            "f_max and delta_f are then force / normal_load, in newtons for normal_load = 1.")
    names, internal_bounds, to_internal, ratio = _internal(free, values, start, bounds)
    kinds = tuple(p.kind for p in prepared)
    n_int = tuple(p.n_interfaces for p in prepared)
    model = BearingModel(free=names, kinds=kinds, n_interfaces=n_int,
                         use_breakaway=use_breakaway, ratio=ratio)
    model_user = BearingModel(free=free, kinds=kinds, n_interfaces=n_int,
                              use_breakaway=use_breakaway, ratio=False)
    args = {"fixed": _fixed_tree(values), "records": [p.arrays for p in prepared]}
    starts = _multi_starts(start, free, n_starts) if not initial else [start]
    internal_starts = [to_internal(s) for s in starts]
    check_bounds(internal_starts[0], internal_bounds)
    batch_initial = {n: np.array([s[n] for s in internal_starts]) for n in names}
    # keep perturbed starts inside the bounds
    for n, (lo, hi) in internal_bounds.items():
        x = batch_initial[n]
        span = np.where(np.isfinite(hi - lo), hi - lo, np.abs(x))
        batch_initial[n] = np.clip(x, lo + 1e-6 * span, hi - 1e-6 * span)
    results = fit_least_squares_batch(
        model, batch_initial, internal_bounds, args=args, args_batched=False,
        max_steps=max_steps, rtol=rtol, atol=atol)
    best = _best(results)
    return _finish(prepared, model_user, free, values, results[best], args, warnings,
                   starts[best], len(starts))


def _best(results) -> int:
    costs = [r.cost if (r.converged and np.isfinite(r.cost)) else np.inf for r in results]
    if np.all(np.isinf(costs)):
        costs = [r.cost if np.isfinite(r.cost) else np.inf for r in results]
    return int(np.argmin(costs))


def fit_bearing_tests_batch(
    records: Sequence[TestRecord],
    *,
    free: Sequence[str] | None = None,
    fixed: Mapping[str, float] | None = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    normal_load: float | None = None,
    n_starts: int = 3,
    max_steps: int = 200,
    rtol: float = 1e-8,
    atol: float = 1e-8,
) -> list[BearingFit]:
    """Fit many independent time-history records (one parameter set each) in one vmapped call.

    Records are padded to a common length (padding has zero weight). The free set is common;
    by default it is the default of `fit_bearing_test` for the first record (all records are
    expected to come from the same kind of test, e.g. one per Table 1 interface).

    **Returns:** one `BearingFit` per record, each with its own `converged` status.
    """
    records = _as_records(records)
    _check_names(free or (), "free")
    yield_ref = (fixed or {}).get("yield_disp")
    prepared = [prepare_record(r, index=i, normal_load=normal_load, yield_ref=yield_ref)
                for i, r in enumerate(records)]
    if any(p.kind != "time" for p in prepared):
        raise ValueError("records: the batch fit takes time histories; fit digitised loops "
                         "with fit_bearing_test.")
    plans = [_plan([p], free, fixed, None, bounds) for p in prepared]
    common_free = plans[0][0] if free is None else tuple(free)
    plans = [_plan([p], common_free, fixed, None, bounds) for p in prepared]
    use_breakaway = plans[0][4]
    if any(pl[4] != use_breakaway for pl in plans):
        raise ValueError("records: some records use breakaway and others not; fit them apart.")
    length = max(p.arrays["time"].size for p in prepared)
    n_int = prepared[0].n_interfaces
    if any(p.n_interfaces != n_int for p in prepared):
        raise ValueError("records: all records of a batch need the same 'interfaces'.")
    names = None
    initial_rows, trees, meta = [], [], []
    bounds_all = None
    for p, (fr, values, start, warnings, _) in zip(prepared, plans):
        names, internal_bounds, to_internal, ratio = _internal(fr, values, start, bounds)
        if bounds_all is None:
            bounds_all = internal_bounds
        elif any(internal_bounds[k] != bounds_all[k] for k in internal_bounds):
            raise ValueError("records: parameter bounds differ between records (fixed values "
                             "enter the bounds); fit them apart.")
        starts = _multi_starts(start, fr, n_starts)
        tree = {"fixed": _fixed_tree(values), "records": [_pad(p.arrays, length)]}
        for s in starts:
            initial_rows.append(to_internal(s))
            trees.append(tree)
        meta.append((fr, values, warnings, starts))
    kinds = ("time",)
    model = BearingModel(free=names, kinds=kinds, n_interfaces=(n_int,),
                         use_breakaway=use_breakaway, ratio=ratio)
    model_user = BearingModel(free=common_free, kinds=kinds, n_interfaces=(n_int,),
                              use_breakaway=use_breakaway, ratio=False)
    batch_initial = {n: np.array([row[n] for row in initial_rows]) for n in names}
    for n, (lo, hi) in bounds_all.items():
        x = batch_initial[n]
        span = np.where(np.isfinite(hi - lo), hi - lo, np.abs(x))
        batch_initial[n] = np.clip(x, lo + 1e-6 * span, hi - 1e-6 * span)
    args = _stack(trees)
    results = fit_least_squares_batch(
        model, batch_initial, bounds_all, args=args, args_batched=True,
        max_steps=max_steps, rtol=rtol, atol=atol)
    fits = []
    k = 0
    for p, (fr, values, warnings, starts) in zip(prepared, meta):
        group = results[k: k + len(starts)]
        best = _best(group)
        args_i = _tree_index(args, k + best)
        k += len(starts)
        raw = group[best]
        fits.append(_finish([p], model_user, fr, values, raw, args_i, warnings, starts[best],
                            len(starts)))
    return fits
