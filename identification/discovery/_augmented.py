"""The augmented bearing-test simulator: the 1990 model plus any set of candidate effects.

The imposed displacement of a test record drives the model sample by sample (one step per
record sample), with the force model and the velocity convention of the fitter
(`identification.bearing_fit.simulate_record_force`): Z follows the closed-form Riccati update
of Bouc-Wen along each increment (`bouc_wen_exact_update`, the simulator's step), or for
biaxial records Park et al.'s equations along the path (`park_path_update`); the velocity at a
sample is `sample_velocity` (second-order central differences); the running max |Z| decides
the breakaway switch of Eq. 17, and the surface temperature of the steel is carried as a sum
of exponential states (see `identification._effects.heat_kernel_exponentials`). The whole
simulation is one `jax.lax.scan`: jittable, vmappable and differentiable in every parameter.

Which effects are on is an array `active` of 0/1 per effect (in the order of `EFFECT_NAMES`),
so one compiled function serves every combination of effects.

Reference: Constantinou, Mokha & Reinhorn (1990), Eqs. 1, 3, 17.
"""

import dataclasses

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from teflon_jax import BoucWen, bouc_wen_exact_update
from teflon_jax.bearing import DEFAULT_YIELD_DISP
from teflon_jax.formats import interface_counts
from teflon_jax.units import PSI

from ..bearing_fit import park_path_update, park_substeps, sample_velocity
from ._effects import (
    AMBIENT_TEMPERATURE,
    BASELINE_PARAMETERS,
    EFFECT_NAMES,
    EFFECTS,
    STEEL_CONDUCTIVITY,
    STEEL_DIFFUSIVITY,
    backlash_update,
    breakaway_switch,
    heat_kernel_exponentials,
    heating_factor,
    surface_temperature_coefficient,
)

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
    """Inputs of the augmented simulator, derived from a test record (SI units).

    Arrays have one entry per retained sample. Fields:
    `time` [s], `ux` [m], `force` measured fx [N], `du` increment from the previous sample [m]
    (0 at the first), `velocity` [m/s] (`sample_velocity`), `mean_speed` |du|/dt over the
    interval ending at each sample [m/s] (the travel per interval, for the heat input only),
    `normal` effective normal force [N] (normal load times `interfaces_in_parallel`),
    `series` the record's `interfaces_in_series` (Eq. 1 at |v| / series while the
    `interfaces` effect is off), `pressure` contact pressure [Pa],
    `log_load_ratio` log(N / mean N), `travel_fraction` accumulated |du| over its final value,
    `heat_rates`, `heat_weights`: the exponential approximation of the 1/sqrt(t) kernel;
    `measured_rise` the measured temperature minus its first value [K] and
    `reference_temperature` that first value [degC] with the static flag
    `measured_temperature` (records with a `temperature` column; zeros and 20 degC otherwise);
    for biaxial records also `uy`, `force_y`, `du_y`, `velocity_y` and the sliding-angle
    weight `angle_weight` (0 along x, parallel to the lay; 1 along y), zeros otherwise, and the
    static flag `biaxial`. Speeds and travel are those of the path in the plane.
    """

    time: jnp.ndarray
    ux: jnp.ndarray
    force: jnp.ndarray
    du: jnp.ndarray
    velocity: jnp.ndarray
    mean_speed: jnp.ndarray
    normal: jnp.ndarray
    pressure: jnp.ndarray
    log_load_ratio: jnp.ndarray
    travel_fraction: jnp.ndarray
    heat_rates: jnp.ndarray
    heat_weights: jnp.ndarray
    uy: jnp.ndarray
    force_y: jnp.ndarray
    du_y: jnp.ndarray
    velocity_y: jnp.ndarray
    angle_weight: jnp.ndarray
    measured_rise: jnp.ndarray
    reference_temperature: jnp.ndarray
    series: jnp.ndarray = 1.0
    measured_temperature: bool = eqx.field(static=True, default=False)
    biaxial: bool = eqx.field(static=True, default=False)
    park_elements: int = eqx.field(static=True, default=16)

    @property
    def n_samples(self) -> int:
        return self.time.shape[0]


@dataclasses.dataclass(frozen=True)
class RecordInfo:
    """What `prepare_record` decided about a record (for reports).

    `decimation` (every k-th sample kept), `n_interfaces_recorded` (`interfaces_in_parallel`:
    forces added), `n_interfaces_in_series` (`interfaces_in_series`),
    `contact_area_assumed` (True when the heating effect uses `NOMINAL_CONTACT_PRESSURE`),
    `varying_normal_load` (coefficient of variation of N above 1 %), `biaxial`,
    `measured_temperature` (the record has a `temperature` column), `source`.
    """

    decimation: int
    n_interfaces_recorded: int
    n_interfaces_in_series: int
    contact_area_assumed: bool
    varying_normal_load: bool
    biaxial: bool
    source: str
    measured_temperature: bool = False


def prepare_record(record, *, max_samples: int = 3000, heat_terms_per_decade: float = 3.0):
    """Turn a `TestRecord` into `AugmentedData` for the augmented simulator.

    **Arguments:**

    - `record`: a `teflon_jax` `TestRecord` with a time column and a normal load.
    - `max_samples`: records longer than this keep every k-th sample (Z stays exact: the
      Riccati update integrates any monotone increment).

    **Returns:** `(AugmentedData, RecordInfo)`. Raises `ValueError` when the record has no time
    column (digitised loop) or no normal load.
    """
    where = str(record.path) if getattr(record, "path", None) is not None else "record"
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
    if record.ux.size < 20:
        raise ValueError(
            f"{where}: only {record.ux.size} samples; diagnose needs at least 20."
        )
    if max_samples < 20:
        raise ValueError(f"max_samples: must be >= 20, got {max_samples}.")
    step = int(np.ceil(record.ux.size / max_samples))
    keep = np.arange(0, record.ux.size, step)
    time = np.asarray(record.time, float)[keep]
    ux = np.asarray(record.ux, float)[keep]
    fx = np.asarray(record.fx, float)[keep]
    load = np.asarray(record.normal_load, float)[keep]
    if np.any(load <= 0):
        raise ValueError(f"{where}: normal load must be > 0 (compression) at every sample.")
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
    n_rec, n_series = interface_counts(record.metadata)
    normal = load * n_rec

    biaxial = record.uy is not None
    if biaxial and record.fy is None:
        raise ValueError(
            f"{where}: the record has 'uy' but no 'fy'; a biaxial test needs both."
        )
    uy = np.asarray(record.uy, float)[keep] if biaxial else np.zeros_like(ux)
    fy = np.asarray(record.fy, float)[keep] if biaxial else np.zeros_like(ux)
    du = np.concatenate([[0.0], np.diff(ux)])
    du_y = np.concatenate([[0.0], np.diff(uy)])
    dt = np.concatenate([[np.inf], np.diff(time)])
    step_length = np.hypot(du, du_y)
    mean_speed = step_length / dt
    velocity = sample_velocity(time, ux)
    velocity_y = sample_velocity(time, uy) if biaxial else np.zeros_like(ux)
    if biaxial:
        angle = np.arctan2(np.abs(velocity_y), np.abs(velocity))
        angle_weight = np.where(
            np.hypot(velocity, velocity_y) > 0, angle / (np.pi / 2), 0.0
        )
    else:
        angle_weight = np.zeros_like(ux)
    if "contact_area" in record.metadata:
        pressure = load / float(record.metadata["contact_area"])
        assumed = False
    elif "contact_pressure" in record.metadata:
        pressure = load / np.mean(load) * float(record.metadata["contact_pressure"])
        assumed = False
    else:
        pressure = load / np.mean(load) * NOMINAL_CONTACT_PRESSURE
        assumed = True
    measured = getattr(record, "temperature", None) is not None
    if measured:
        temperature = np.asarray(record.temperature, float)[keep]
        reference_temperature, measured_rise = temperature[0], temperature - temperature[0]
    else:
        reference_temperature, measured_rise = AMBIENT_TEMPERATURE, np.zeros_like(ux)
    travel = np.cumsum(step_length)
    travel_fraction = travel / max(travel[-1], 1e-300)
    duration = time[-1] - time[0]
    rates, weights = heat_kernel_exponentials(
        float(np.min(np.diff(time))), float(duration), per_decade=heat_terms_per_decade
    )
    data = AugmentedData(
        time=jnp.asarray(time),
        ux=jnp.asarray(ux),
        force=jnp.asarray(fx),
        du=jnp.asarray(du),
        velocity=jnp.asarray(velocity),
        mean_speed=jnp.asarray(mean_speed),
        normal=jnp.asarray(normal),
        pressure=jnp.asarray(pressure),
        log_load_ratio=jnp.asarray(np.log(load / np.mean(load))),
        travel_fraction=jnp.asarray(travel_fraction),
        heat_rates=jnp.asarray(rates),
        heat_weights=jnp.asarray(weights),
        uy=jnp.asarray(uy),
        force_y=jnp.asarray(fy),
        du_y=jnp.asarray(du_y),
        velocity_y=jnp.asarray(velocity_y),
        angle_weight=jnp.asarray(angle_weight),
        measured_rise=jnp.asarray(measured_rise),
        reference_temperature=jnp.asarray(float(reference_temperature)),
        series=jnp.asarray(float(n_series)),
        measured_temperature=measured,
        biaxial=biaxial,
        park_elements=park_substeps(ux, uy, DEFAULT_YIELD_DISP) if biaxial else 16,
    )
    info = RecordInfo(
        decimation=step,
        n_interfaces_recorded=n_rec,
        n_interfaces_in_series=n_series,
        contact_area_assumed=assumed,
        varying_normal_load=bool(np.std(load) > 0.01 * np.mean(load)),
        biaxial=biaxial,
        source=where,
        measured_temperature=measured,
    )
    return data, info


def active_mask(effects) -> jnp.ndarray:
    """0/1 array over `EFFECT_NAMES` with ones for the named effects (checked names)."""
    unknown = [e for e in effects if e not in EFFECTS]
    if unknown:
        raise ValueError(f"effects: unknown {unknown}; choose from {list(EFFECT_NAMES)}.")
    return jnp.asarray([1.0 if name in effects else 0.0 for name in EFFECT_NAMES])


def default_parameters() -> dict[str, float]:
    """Starting values of every parameter (effects at their fit starting values)."""
    return {p.name: p.initial for p in PARAMETERS}


def simulate_augmented(
    params, data: AugmentedData, active, *, conductivity=None, diffusivity=None
):
    """Friction force of the augmented model along the record's imposed displacement.

    Friction coefficient (each factor is 1 while its effect is off):

        c(w)   = (1 - w) c_P + w c_T,  c = f_max, delta_f, rate_a   (anisotropy; c_T = c_P off)
        mu_v   = f_max(w) - delta_f(w) exp(-rate_a(w) |v| / n)      (Eq. 1; delta_f = 0 when off)
        mu_0   = breakaway_ratio (f_max(w) - delta_f(w))  while max|Z| < 0.999 (Eq. 17), else mu_v
        mu     = mu_0 (N/N_ref)^(-pressure_exponent) (1 + asymmetry Z_x)
                      (1 + wear_change travel/travel_total) k_T(T0 + heat_scale dT)/k_T(T0)
        F      = mu N Z,    Z from the exact Bouc-Wen update (A = 1, beta = 0.1, gamma = 0.9)

    with w = |theta| / (pi/2) the sliding angle weight (0 along x, parallel to the lay), n the
    interfaces in series, and dT the measured temperature rise (record with a `temperature`
    column, T0 its first value) or else the surface temperature rise of a semi-infinite steel
    body under the heat flux q = mu p |v| / n (Carslaw & Jaeger; T0 = 20 degC). With `backlash`
    on (uniaxial records), Z follows `backlash_update`: a gap of `backlash_gap` [m] in series.

    **Arguments:**

    - `params`: mapping name -> value for every name in `PARAMETER_NAMES` (SI).
    - `data`: `AugmentedData` from `prepare_record`.
    - `active`: 0/1 array over `EFFECT_NAMES` (see `active_mask`).
    - `conductivity` [W/(m K)], `diffusivity` [m^2/s] of the steel (defaults: stainless steel).

    Biaxial records: Z is a vector following Park et al. along the path (`park_path_update`,
    as in the fitter), mu uses the speed of the path in the plane and F = mu N Z per component.

    **Returns:** dict of arrays over the samples: `force` [N] along x, `force_y` [N] (zeros for
    uniaxial records), `coefficient` mu [-], `z` [-] (x component), `z_y`,
    `z_peak` [-], `temperature_rise` heat_scale dT [K] (0 when heating is off),
    `heat_index` dT at heat_scale = 1 [K] (a regressor for diagnostics), `gap_position` [m].
    """
    on = {name: active[i] for i, name in enumerate(EFFECT_NAMES)}
    p = params
    coef = surface_temperature_coefficient(
        STEEL_CONDUCTIVITY if conductivity is None else conductivity,
        STEEL_DIFFUSIVITY if diffusivity is None else diffusivity,
    )
    hyst = BoucWen(yield_disp=p["yield_disp"])

    n_stack = jnp.where(on["interfaces"] > 0, p["n_interfaces"], data.series)
    w = on["anisotropy"] * data.angle_weight

    def mix(parallel, perpendicular):
        return (1.0 - w) * p[parallel] + w * p[perpendicular]

    f_max = mix("f_max", "f_max_perpendicular")
    delta_f = on["velocity_dependence"] * mix("delta_f", "delta_f_perpendicular")
    rate_a = mix("rate_a", "rate_a_perpendicular")
    speed = jnp.sqrt(data.velocity**2 + data.velocity_y**2)
    mu_v = f_max - delta_f * jnp.exp(-rate_a * speed / n_stack)
    mu_static = p["breakaway_ratio"] * (f_max - delta_f)
    factor = (
        jnp.exp(-on["pressure_dependence"] * p["pressure_exponent"] * data.log_load_ratio)
        * (1.0 + on["wear"] * p["wear_change"] * data.travel_fraction)
    )
    asymmetry = on["asymmetry"] * p["asymmetry"]
    gap = on["backlash"] * p["backlash_gap"]
    heat_on = on["heating"]
    breakaway_on = on["breakaway"] > 0
    rates, weights = data.heat_rates, data.heat_weights
    dts = jnp.concatenate([jnp.zeros(1), jnp.diff(data.time)])
    flux_speed = data.mean_speed / n_stack

    def step(carry, x):
        z, z_peak, heat, mu_prev, s = carry
        du, dt, speed_i, pressure, mu_v_i, mu_static_i, factor_i, normal, measured = x
        if data.biaxial:
            p0, p1, m0, m1 = du
            z = park_path_update(hyst, z, p0, p1, m0, m1, data.park_elements)
            z_peak = jnp.maximum(z_peak, jnp.sqrt(jnp.sum(z**2)))
            z_x = z[0]
        else:
            z, s = backlash_update(hyst, z, s, du, gap)
            z_peak = jnp.maximum(z_peak, jnp.abs(z))
            z_x = z
        if data.measured_temperature:
            heat_index = measured
        else:
            decay = jnp.exp(-rates * dt)
            flux = mu_prev * pressure * speed_i
            heat = decay * heat + flux * (1.0 - decay) / rates
            heat_index = coef * jnp.dot(weights, heat)
        rise = heat_on * p["heat_scale"] * heat_index
        base = jnp.where(breakaway_on & breakaway_switch(z_peak), mu_static_i, mu_v_i)
        k_heat = heating_factor(rise, data.reference_temperature)
        mu = jnp.maximum(base * factor_i * (1.0 + asymmetry * z_x) * k_heat, 0.0)
        out = (mu * normal * z, mu, z, z_peak, rise, heat_index, s)
        return (z, z_peak, heat, mu, s), out

    z0 = jnp.zeros(2) if data.biaxial else jnp.zeros(())
    if data.biaxial:
        # Path from the previous sample to this one (none before the first: dts[0] = 0).
        position = jnp.stack([data.ux, data.uy], axis=-1)
        velocity = jnp.stack([data.velocity, data.velocity_y], axis=-1)
        previous = jnp.concatenate([position[:1], position[:-1]])
        previous_velocity = jnp.concatenate([velocity[:1], velocity[:-1]])
        du = (previous, position, previous_velocity * dts[:, None], velocity * dts[:, None])
    else:
        du = data.du
    mu_static = jnp.broadcast_to(mu_static, mu_v.shape)
    init = (z0, jnp.zeros(()), jnp.zeros_like(rates), jnp.zeros(()), jnp.zeros(()))
    xs = (du, dts, flux_speed, data.pressure, mu_v, mu_static, factor, data.normal,
          data.measured_rise)
    _, (force, mu, z, z_peak, rise, heat_index, s) = jax.lax.scan(step, init, xs)
    if data.biaxial:
        force_y, force, z_y, z = force[:, 1], force[:, 0], z[:, 1], z[:, 0]
    else:
        force_y, z_y = jnp.zeros_like(force), jnp.zeros_like(z)
    return {
        "force": force,
        "force_y": force_y,
        "z_y": z_y,
        "coefficient": mu,
        "z": z,
        "z_peak": z_peak,
        "temperature_rise": rise,
        "heat_index": heat_index,
        "gap_position": s,
    }


def planar_exact_update(h: BoucWen, z, displacement_increment):
    """Z = (Zx, Zy) after a straight displacement increment, in closed form (eta = 2).

    Along a straight increment of length s in direction e, write Z = w e + p e_perp. With the
    plane-isotropic form of the biaxial model,
        Y dZ = A du - (gamma |du . Z| + beta du . Z) Z,
    w obeys the uniaxial Riccati equation of Bouc-Wen (so `bouc_wen_exact_update` gives it
    exactly) and p decays as d ln p / dx = -(gamma |w| + beta w), x = s / Y, which integrates to
        p1 / p0 = 1 / (cosh(k+ x) + (w0 / w+) sinh(k+ x))                     (w0 >= 0)
        p1 / p0 = 1 / (cos(k- x) - (w0 / w-) sin(k- x)), then the first form    (w0 < 0)
    with w+- = sqrt(A / (gamma +- beta)), k+- = sqrt(A (gamma +- beta)), continuing on the
    positive branch after w crosses zero. Park, Wen & Ang (1986) write the gamma term as
    |du_x Z_x| + |du_y Z_y|; the two agree in uniaxial motion and while sliding (Z parallel to
    the velocity) and differ only in the short transitions after a change of direction.

    **Arguments:** `h` Bouc-Wen constants (gamma > beta), `z` (2,), `displacement_increment` (2,) [m].

    **Returns:** Z (2,) at the end of the increment.
    """
    du = displacement_increment
    length_sq = du[0] ** 2 + du[1] ** 2
    moving = length_sq > 0
    length = jnp.sqrt(jnp.where(moving, length_sq, 1.0))
    e = jnp.where(moving, du / length, jnp.array([1.0, 0.0]))
    length = jnp.where(moving, length, 0.0)
    e_perp = jnp.array([-e[1], e[0]])
    w0 = jnp.dot(z, e)
    p0 = jnp.dot(z, e_perp)
    w1 = bouc_wen_exact_update(h, w0, length)
    x = length / h.yield_disp
    c_plus, c_minus = h.gamma + h.beta, h.gamma - h.beta
    w_plus, k_plus = jnp.sqrt(h.A / c_plus), jnp.sqrt(h.A * c_plus)
    w_minus, k_minus = jnp.sqrt(h.A / c_minus), jnp.sqrt(h.A * c_minus)
    negative = w0 < 0
    w0_neg = jnp.where(negative, w0, -1.0)
    x_to_zero = jnp.where(negative, -jnp.arctan(w0_neg / w_minus) / k_minus, 0.0)
    x_neg = jnp.minimum(x, x_to_zero)
    ratio_neg = 1.0 / (
        jnp.cos(k_minus * x_neg) - (w0_neg / w_minus) * jnp.sin(k_minus * x_neg)
    )
    ratio_neg = jnp.where(negative, ratio_neg, 1.0)
    w_start = jnp.where(negative, 0.0, w0)
    kx = jnp.minimum(k_plus * jnp.maximum(x - x_to_zero, 0.0), 50.0)
    ratio_pos = 1.0 / (jnp.cosh(kx) + (w_start / w_plus) * jnp.sinh(kx))
    p1 = p0 * ratio_neg * ratio_pos
    return jnp.where(moving, w1 * e + p1 * e_perp, z)
