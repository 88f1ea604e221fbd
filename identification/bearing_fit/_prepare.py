"""Checks a test record and extracts the loop features the fitter starts from."""


import numpy as np

from teflon_jax.bearing import DEFAULT_YIELD_DISP
from teflon_jax.formats import TestRecord, interface_counts
from teflon_jax.solver import park_substeps
from teflon_jax.systems import sample_velocity

from ._loop_features import (
    _ZERO_CROSSING,
    PreparedBiaxialRecord,
    PreparedRecord,
    _excursion,
    _friction_law_start,
    _reversals,
)
from ._record_force import PERPENDICULAR_NAMES


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


def _features_time(time, ux, fx, load, velocity, series, name, yield_ref):
    """Loop features of a time history (x direction): starts, first motion, identifiability."""
    v = velocity
    speed = np.abs(v) / series
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
    parallel, series = interface_counts(record.metadata)
    load = _normal_load(record, name, normal_load)
    if np.any(load <= 0):
        i = int(np.argmax(load <= 0))
        raise ValueError(f"{name}: normal load must be positive (compression); sample {i} is "
                         f"{load[i]} N.")
    yield_ref = float(DEFAULT_YIELD_DISP) if yield_ref is None else float(yield_ref)
    if record.is_digitised:
        if record.is_biaxial:
            raise ValueError(f"{name}: digitised biaxial loops are not supported; give the "
                             "time history (time, ux, uy, fx, fy).")
        return prepare_digitised(record, name=name, load=load, parallel=parallel,
                                 series=series, yield_ref=yield_ref)
    if record.ux.size < 10:
        raise ValueError(f"{name}: only {record.ux.size} samples; a fit needs a full loop.")
    if record.is_biaxial:
        return _prepare_biaxial(record, name, load, parallel, series, yield_ref)
    time, ux, fx = (np.asarray(x, dtype=float) for x in (record.time, record.ux, record.fx))
    velocity = sample_velocity(time, ux)
    feats = _features_time(time, ux, fx / parallel, load, velocity, series, name, yield_ref)
    scale = float(np.sqrt(np.mean(fx**2)))
    arrays = dict(
        time=time, ux=ux, fx=fx, load=load, velocity=velocity, weight=np.ones_like(time) / scale,
        z0=np.asarray(feats["z0"]), z_peak0=np.asarray(0.0 if feats["first_motion"] else 1.0),
    )
    return PreparedRecord(
        name=name, kind="time", arrays=arrays, first_motion=feats["first_motion"],
        start=feats["start"], warnings=[], elastic_samples=feats["elastic"],
        measured=fx, ux=ux, time=time, interfaces_in_parallel=parallel,
        interfaces_in_series=series, velocity=velocity,
        speed_low=feats["speed_low"], speed_high=feats["speed_high"],
    )


def _prepare_biaxial(record, name, load, parallel, series, yield_ref):
    """A biaxial time history (ux, uy, fx, fy): the residual stacks fx and fy."""
    if record.fy is None:
        raise ValueError(f"{name}: the record has 'uy' but no 'fy'; a biaxial fit needs both.")
    time, ux, uy, fx, fy = (np.asarray(x, dtype=float) for x in
                            (record.time, record.ux, record.uy, record.fx, record.fy))
    vx, vy = sample_velocity(time, ux), sample_velocity(time, uy)
    # Start values from the x direction, then Eq. 1 fitted separately near each axis.
    feats = _features_time(time, ux, fx / parallel, load, vx, series, name, yield_ref)
    speed = np.hypot(vx, vy) / series
    moving = speed > 0
    along = np.where(moving, (fx * vx + fy * vy) / np.where(moving, np.hypot(vx, vy), 1.0), 0.0)
    mu = along / (load * parallel)
    weight = np.arctan2(np.abs(vy), np.abs(vx)) / (np.pi / 2)
    start = dict(feats["start"])
    sliding = moving & (np.hypot(fx, fy) > 0.5 * np.percentile(np.hypot(fx, fy), 90))
    for names, near in ((("f_max", "delta_f", "rate_a"), weight < 0.35),
                        (PERPENDICULAR_NAMES, weight > 0.65)):
        use = sliding & near
        if np.count_nonzero(use) >= 10:
            start.update(zip(names, _friction_law_start(speed[use], mu[use])))
        else:
            start.update(zip(names, (start["f_max"], start["delta_f"], start["rate_a"])))
    measured = np.concatenate([fx, fy])
    scale = float(np.sqrt(np.mean(measured**2)))
    arrays = dict(time=time, ux=ux, uy=uy, fx=measured, load=load, velocity=vx, velocity_y=vy,
                  weight=np.ones_like(measured) / scale)
    return PreparedBiaxialRecord(
        name=name, kind="time", arrays=arrays, first_motion=feats["first_motion"],
        start=start, warnings=[], elastic_samples=feats["elastic"],
        measured=measured, ux=ux, time=time, interfaces_in_parallel=parallel,
        interfaces_in_series=series,
        park_elements=park_substeps(ux, uy, start["yield_disp"]), velocity=vx,
        speed_low=float(np.percentile(speed[sliding], 5)),
        speed_high=float(np.percentile(speed[sliding], 95)),
    )

