"""Discovery's view of a test record: the data of a record and the bearing of a candidate model.

A candidate model is the one bearing model (`teflon_jax.bearing.SlidingBearing`) with every
optional part present and each part's constants multiplied by a 0/1 switch (`active`, in the
order of `EFFECT_NAMES`): a part switched off sits at its neutral constants, where it gives the
numbers of the bearing without it. So one compiled function serves every combination of
effects (vmapped over candidates), and its force is that of `teflon_jax.imposed_path_test`,
the function the fitter and the simulator use.

Reference: Constantinou, Mokha & Reinhorn (1990), Eqs. 1, 3, 17.
"""

import abc
import dataclasses

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from teflon_jax.bearing import (
    AMBIENT_TEMPERATURE,
    STEEL_CONDUCTIVITY,
    STEEL_DIFFUSIVITY,
    Backlash,
    BoucWen,
    DirectionAsymmetry,
    FrictionalHeating,
    FrictionParameters,
    PressureDependence,
    SlidingBearing,
    Wear,
)
from teflon_jax.formats import interface_counts
from teflon_jax.systems import (
    SampledPath,
    imposed_path_test,
    sampled_path,
)
from teflon_jax.units import PSI

from ._effects import BASELINE_PARAMETERS, EFFECT_NAMES, EFFECTS

MIN_SAMPLES = 20
"""The fewest samples a record may have, and may be decimated to (`max_samples`), for a search."""

NOMINAL_CONTACT_PRESSURE = 1000.0 * PSI
"""Contact pressure assumed for the heating effect when a record states no contact area [Pa]."""

PARAMETERS = BASELINE_PARAMETERS + tuple(p for e in EFFECTS.values() for p in e.parameters)
"""Every parameter of the augmented model, in the order of the parameter vector."""


PARAMETER_NAMES = tuple(p.name for p in PARAMETERS)


PARAMETER_EFFECT = ("baseline",) * len(BASELINE_PARAMETERS) + tuple(
    e.name for e in EFFECTS.values() for _ in e.parameters
)
"""The effect each parameter belongs to (`"baseline"` for f_max and yield_disp)."""


class AugmentedData(eqx.Module):
    """A test record as discovery sees it (SI units; arrays have one entry per kept sample).

    **Fields:** `path` the `SampledPath` the bearing is driven along (time, displacement,
    velocity, normal load per bearing, measured temperature rise); `force`, `force_y` measured
    [N] (zeros along x only); `time`, `ux`, `uy`, `velocity`, `velocity_y` the path's
    arrays (zeros along x only); `normal` effective normal force [N] (load times
    `interfaces_in_parallel`); regressors of the diagnostics: `log_load_ratio` log(N / mean N),
    `travel_fraction` accumulated travel over its final value, `angle_weight` the sliding-angle
    weight (0 along x, 1 along y); the constants the optional parts are referred to:
    `reference_load` mean N [N], `total_travel` [m], `contact_area` [m^2],
    `reference_temperature` [degC] (the first measured value, else 20 degC);
    `in_parallel`, `series` interfaces recorded together and in series (static).

    One of two kinds: `UniaxialAugmentedData` (a record along x) or `BiaxialAugmentedData` (a
    record in the plane), which differ in the components their residual compares (`stack`).
    """

    path: SampledPath
    force: jnp.ndarray
    force_y: jnp.ndarray
    time: jnp.ndarray
    ux: jnp.ndarray
    uy: jnp.ndarray
    velocity: jnp.ndarray
    velocity_y: jnp.ndarray
    normal: jnp.ndarray
    log_load_ratio: jnp.ndarray
    travel_fraction: jnp.ndarray
    angle_weight: jnp.ndarray
    reference_load: jnp.ndarray
    total_travel: jnp.ndarray
    contact_area: jnp.ndarray
    reference_temperature: jnp.ndarray
    in_parallel: int = eqx.field(static=True, default=1)
    series: int = eqx.field(static=True, default=1)

    @property
    def n_samples(self) -> int:
        return self.time.shape[0]

    @property
    def measured_temperature(self) -> bool:
        return self.path.temperature_rise is not None

    @abc.abstractmethod
    def stack(self, x, y):
        """The components a residual compares, along the last axis: x of a record along x,
        x then y of a record in the plane."""


class UniaxialAugmentedData(AugmentedData):
    """`AugmentedData` of a record along x (`uy`, `force_y`, `velocity_y` zeros)."""

    def stack(self, x, y):
        return x


class BiaxialAugmentedData(AugmentedData):
    """`AugmentedData` of a record in the plane (ux, uy, fx, fy): Park's Z (Eqs. 8-9)."""

    def stack(self, x, y):
        traced = isinstance(x, jax.core.Tracer) or isinstance(y, jax.core.Tracer)
        return (jnp if traced else np).concatenate([x, y], axis=-1)


@dataclasses.dataclass(frozen=True)
class RecordInfo:
    """What `prepare_record` decided about a record (for reports).

    `decimation` (every k-th sample kept), `n_interfaces_recorded` (`interfaces_in_parallel`:
    forces added), `n_interfaces_in_series` (`interfaces_in_series`),
    `contact_area_assumed` (True when the heating effect uses `NOMINAL_CONTACT_PRESSURE`),
    `varying_normal_load` (coefficient of variation of N above 1 %), `measured_temperature`
    (the record has a `temperature` column), `source`. Whether the record is along x or in the
    plane is the type of its `AugmentedData`.
    """

    decimation: int
    n_interfaces_recorded: int
    n_interfaces_in_series: int
    contact_area_assumed: bool
    varying_normal_load: bool
    source: str
    measured_temperature: bool = False


def prepare_record(record, *, max_samples: int = 3000, heat_terms_per_decade: float = 3.0):
    """Turn a `TestRecord` into `AugmentedData` for the augmented simulator.

    **Arguments:**

    - `record`: a `teflon_jax` `TestRecord` with a time column and a normal load.
    - `max_samples`: records longer than this keep every k-th sample (Z stays exact: the
      Riccati update integrates any monotone increment).

    **Returns:** `(AugmentedData, RecordInfo)`, the data a `UniaxialAugmentedData` for a record
    along x, a `BiaxialAugmentedData` for one with `uy` and `fy`. Raises `ValueError` when the
    record has no time column (digitised loop) or no normal load.
    """
    where = str(record.path) if getattr(record, "path", None) is not None else "record"
    _check_diagnosable(record, where, max_samples)
    step = int(np.ceil(record.ux.size / max_samples))
    keep = np.arange(0, record.ux.size, step)
    time = np.asarray(record.time, float)[keep]
    ux = np.asarray(record.ux, float)[keep]
    fx = np.asarray(record.fx, float)[keep]
    load = np.asarray(record.normal_load, float)[keep]
    if np.any(load <= 0):
        raise ValueError(f"{where}: normal load must be > 0 (compression) at every sample.")
    _check_positive_work(record, keep, ux, fx, where)
    n_rec, n_series = interface_counts(record.metadata)
    normal = load * n_rec

    if record.uy is not None and record.fy is None:
        raise ValueError(
            f"{where}: the record has 'uy' but no 'fy'; a biaxial test needs both."
        )
    in_plane = {} if record.uy is None else {
        "uy": np.asarray(record.uy, float)[keep], "fy": np.asarray(record.fy, float)[keep]}
    uy, fy = in_plane.get("uy", np.zeros_like(ux)), in_plane.get("fy", np.zeros_like(ux))
    contact_area, assumed = _contact_area(record.metadata, load)
    measured = getattr(record, "temperature", None) is not None
    if measured:
        temperature = np.asarray(record.temperature, float)[keep]
        reference_temperature, measured_rise = temperature[0], temperature - temperature[0]
    else:
        reference_temperature, measured_rise = AMBIENT_TEMPERATURE, None
    path = sampled_path(time, ux, load, uy=in_plane.get("uy"),
                        temperature_rise=measured_rise,
                        heat_terms_per_decade=heat_terms_per_decade)
    velocity = np.asarray(path.velocity_x)
    velocity_y = np.zeros_like(ux) if path.uy is None else np.asarray(path.velocity_y)
    angle = np.arctan2(np.abs(velocity_y), np.abs(velocity))
    angle_weight = np.where(np.hypot(velocity, velocity_y) > 0, angle / (np.pi / 2), 0.0)
    travel = np.cumsum(np.hypot(np.diff(ux, prepend=ux[0]), np.diff(uy, prepend=uy[0])))
    total_travel = max(float(travel[-1]), 1e-300)
    kind = UniaxialAugmentedData if path.uy is None else BiaxialAugmentedData
    data = kind(
        path=path,
        force=jnp.asarray(fx),
        force_y=jnp.asarray(fy),
        time=jnp.asarray(time),
        ux=jnp.asarray(ux),
        uy=jnp.asarray(uy),
        velocity=jnp.asarray(velocity),
        velocity_y=jnp.asarray(velocity_y),
        normal=jnp.asarray(normal),
        log_load_ratio=jnp.asarray(np.log(load / np.mean(load))),
        travel_fraction=jnp.asarray(travel / total_travel),
        angle_weight=jnp.asarray(angle_weight),
        reference_load=jnp.asarray(float(np.mean(load))),
        total_travel=jnp.asarray(total_travel),
        contact_area=jnp.asarray(contact_area),
        reference_temperature=jnp.asarray(float(reference_temperature)),
        in_parallel=n_rec,
        series=n_series,
    )
    info = RecordInfo(
        decimation=step,
        n_interfaces_recorded=n_rec,
        n_interfaces_in_series=n_series,
        contact_area_assumed=assumed,
        varying_normal_load=bool(np.std(load) > 0.01 * np.mean(load)),
        source=where,
        measured_temperature=measured,
    )
    return data, info


def _check_diagnosable(record, where: str, max_samples: int) -> None:
    """Raise unless the record has a time column, a normal load and at least 20 samples."""
    if record.time is None:
        raise ValueError(
            f"{where}: diagnose needs a time column; a digitised loop (protocol only) cannot be "
            "diagnosed sample by sample."
        )
    if record.normal_load is None:
        raise ValueError(
            f"{where}: the record states no normal load; add an 'N' column or a "
            "'# normal_load [kip]: ...' line (friction coefficient = force / normal load)."
        )
    if record.ux.size < MIN_SAMPLES:
        raise ValueError(
            f"{where}: only {record.ux.size} samples; diagnose needs at least {MIN_SAMPLES}."
        )
    if max_samples < MIN_SAMPLES:
        raise ValueError(f"max_samples: must be >= {MIN_SAMPLES}, got {max_samples}.")


def _check_positive_work(record, keep, ux, fx, where: str) -> None:
    """Raise when the measured force does negative work over the kept samples."""
    work = float(np.sum(0.5 * (fx[1:] + fx[:-1]) * np.diff(ux)))
    if record.uy is not None and record.fy is not None:
        fy_k, uy_k = np.asarray(record.fy, float)[keep], np.asarray(record.uy, float)[keep]
        work += float(np.sum(0.5 * (fy_k[1:] + fy_k[:-1]) * np.diff(uy_k)))
    if work < 0:
        raise ValueError(
            f"{where}: the friction force does negative work over the test (loops run "
            "counter-clockwise): 'fx' must be the force the bearing resists with, positive "
            "while sliding in +x (FORMATS.md); flip the sign of the force column."
        )


def _contact_area(metadata, load) -> tuple:
    """(contact area [m^2], whether it was assumed from `NOMINAL_CONTACT_PRESSURE`)."""
    if "contact_area" in metadata:
        return float(metadata["contact_area"]), False
    if "contact_pressure" in metadata:
        return float(np.mean(load)) / float(metadata["contact_pressure"]), False
    return float(np.mean(load)) / NOMINAL_CONTACT_PRESSURE, True


def active_mask(effects) -> jnp.ndarray:
    """0/1 array over `EFFECT_NAMES` with ones for the named effects (checked names)."""
    unknown = [e for e in effects if e not in EFFECTS]
    if unknown:
        raise ValueError(f"effects: unknown {unknown}; choose from {list(EFFECT_NAMES)}.")
    return jnp.asarray([1.0 if name in effects else 0.0 for name in EFFECT_NAMES])


def default_parameters() -> dict[str, float]:
    """Starting values of every parameter (effects at their fit starting values)."""
    return {p.name: p.initial for p in PARAMETERS}


def candidate_bearing(params, data: AugmentedData, active, *, conductivity=None,
                      diffusivity=None) -> SlidingBearing:
    """The bearing of a candidate model: every optional part present, each switched by `active`.

    Friction coefficient (each factor is 1 while its effect is off):

        c(w) = (1 - w) c_P + w c_T for c = f_max, delta_f, rate_a (anisotropy; c_T = c_P off)
        mu   = [f_max(w) - delta_f(w) exp(-rate_a(w) |v| / n)]            (Eq. 1; delta_f = 0 off)
               (breakaway: breakaway_ratio (f_max - delta_f) until max|Z| first reaches 0.999)
               (N / N_ref)^(-pressure_exponent) (1 + asymmetry Z_x)
               (1 + wear_change travel / travel_total) k_T(T0 + heat_scale dT) / k_T(T0)
        F    = mu N Z

    with w the sliding-angle weight, n the record's interfaces in series (or the fitted
    `n_interfaces`, through rate_a n_series / n: Eq. 1 depends on rate_a / n only) and N_ref,
    travel_total, the contact area and T0 those of the record (`AugmentedData`). With the
    breakaway effect off the path starts mobilised (`candidate_start`).

    **Arguments:** `params` mapping name -> value for every name in `PARAMETER_NAMES` (SI);
    `data`; `active` 0/1 over `EFFECT_NAMES`; `conductivity` [W/(m K)], `diffusivity` [m^2/s]
    of the steel (default stainless steel).
    """
    on = {name: active[i] for i, name in enumerate(EFFECT_NAMES)}
    p = params
    n_stack = jnp.where(on["interfaces"] > 0, p["n_interfaces"], data.series)
    rate_scale = data.series / n_stack

    def switched(perpendicular, parallel):
        return on["anisotropy"] * p[perpendicular] + (1.0 - on["anisotropy"]) * p[parallel]

    parallel = FrictionParameters(p["f_max"], on["velocity_dependence"] * p["delta_f"],
                                  p["rate_a"] * rate_scale)
    perpendicular = FrictionParameters(
        switched("f_max_perpendicular", "f_max"),
        on["velocity_dependence"] * switched("delta_f_perpendicular", "delta_f"),
        switched("rate_a_perpendicular", "rate_a") * rate_scale)
    return SlidingBearing(
        friction=parallel,
        hysteresis=BoucWen(yield_disp=p["yield_disp"]),
        breakaway_ratio=p["breakaway_ratio"],
        friction_perpendicular=perpendicular,
        n_interfaces=data.series,
        pressure_dependence=PressureDependence(
            on["pressure_dependence"] * p["pressure_exponent"], data.reference_load),
        heating=FrictionalHeating(
            contact_area=data.contact_area, heat_scale=on["heating"] * p["heat_scale"],
            conductivity=STEEL_CONDUCTIVITY if conductivity is None else conductivity,
            diffusivity=STEEL_DIFFUSIVITY if diffusivity is None else diffusivity,
            initial_temperature=data.reference_temperature),
        wear=Wear(on["wear"] * p["wear_change"], data.total_travel),
        asymmetry=DirectionAsymmetry(on["asymmetry"] * p["asymmetry"]),
        backlash=(None if isinstance(data, BiaxialAugmentedData)
                  else Backlash(on["backlash"] * p["backlash_gap"])),
    )


def discovered_bearing(parameters, data: AugmentedData, effects) -> SlidingBearing:
    """The bearing a discovery (or a fit of a chosen composition) found, with only its parts.

    `candidate_bearing` with the effects in `effects` switched on, the parts of the effects
    that are off removed (no perpendicular constants without anisotropy, no breakaway ratio
    without breakaway, ...), and a fitted stack count folded into rate_a (Eq. 1 depends on
    rate_a / n only); its force along the record is the candidate's (to rounding).

    **Arguments:** `parameters` name -> value (SI) of the fitted model (missing names take
    their defaults: they belong to effects that are off); `data` the record's `AugmentedData`;
    `effects` the effect names of the model.
    """
    values = default_parameters()
    values.update(parameters)
    full = candidate_bearing(values, data, active_mask(effects))

    def kept(name, part):
        return part if name in effects else None

    return eqx.tree_at(
        lambda b: (b.friction_perpendicular, b.breakaway_ratio, b.pressure_dependence,
                   b.heating, b.wear, b.asymmetry, b.backlash),
        full,
        (kept("anisotropy", full.friction_perpendicular), kept("breakaway", full.breakaway_ratio),
         kept("pressure_dependence", full.pressure_dependence), kept("heating", full.heating),
         kept("wear", full.wear), kept("asymmetry", full.asymmetry),
         kept("backlash", full.backlash)),
        is_leaf=lambda x: x is None,
    )


def candidate_start(active):
    """Running max |Z| before the first sample: 0 with breakaway (Eq. 17 applies until the
    first full mobilisation), 1 without (Eq. 1 from the start)."""
    return 1.0 - active[EFFECT_NAMES.index("breakaway")]


def simulate_augmented(params, data: AugmentedData, active, *, conductivity=None,
                       diffusivity=None):
    """Force of a candidate model along the record (`candidate_bearing` driven by
    `teflon_jax.imposed_path_test`), times the record's interfaces in parallel.

    **Returns:** dict of arrays over the samples: `force` [N] along x, `force_y` [N] (zeros
    along x only), `coefficient` mu [-], `z`, `z_y` [-], `temperature_rise` heat_scale dT [K],
    `heat_index` dT at heat_scale = 1 [K] (a regressor for diagnostics), `gap_position` [m].
    """
    bearing = candidate_bearing(params, data, active, conductivity=conductivity,
                                diffusivity=diffusivity)
    response = imposed_path_test(bearing, data.path, z_peak0=candidate_start(active))
    return {
        "force": data.in_parallel * response.fx,
        "force_y": data.in_parallel * response.fy,
        "coefficient": response.coefficient,
        "z": response.z[:, 0],
        "z_y": response.z[:, 1],
        "temperature_rise": response.temperature_rise,
        "heat_index": response.heat_index,
        "gap_position": response.gap_position,
    }
