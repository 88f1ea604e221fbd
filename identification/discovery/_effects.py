"""Candidate effects for model discovery: named, documented extensions of the 1990 model.

The friction coefficient of the augmented model is built from a base law and factors:

    mu(t) = mu_base(|v|, theta, z_peak) * k_pressure * k_heat * k_asym(Z) * k_wear

- `mu_base` is constant friction `f_max` (Coulomb baseline), Eq. 1 when `velocity_dependence`
  is on, evaluated at |v| / n when `interfaces` is on, with its three constants interpolated
  between the parallel and perpendicular values in the sliding angle theta when `anisotropy` is
  on, and replaced by Eq. 17 before the first full mobilisation when `breakaway` is on.
- Each factor is exactly 1 while its effect is off, so effects compose freely.
- `backlash` changes the hysteretic variable Z instead (a gap in series, see
  `identification.discovery.backlash_update`).

Each `Effect` lists its parameters with bounds, the value it starts a fit from and its
*neutral* value (the value for which the effect vanishes, or nearly so). The functions in this
module are pure and jit/vmap/grad-safe; `heat_kernel_exponentials` runs once at set-up (numpy).

References: Constantinou, Mokha & Reinhorn (1990), Eqs. 1, 17 and Section on multiple
interfaces; Carslaw & Jaeger (1959), "Conduction of Heat in Solids", Section 2.9 (surface
temperature of a semi-infinite body under a surface heat flux); Kumar, Whittaker &
Constantinou (2015), "Characterizing friction in sliding isolation bearings", Earthquake Eng.
Struct. Dyn. 44(9) (k_T factor); Mokha, Constantinou & Reinhorn (1990), "Teflon bearings in
base isolation I: Testing" (pressure, wear and direction effects).
"""

import dataclasses

import jax.numpy as jnp
import numpy as np

from teflon_jax import BREAKAWAY_THRESHOLD
from teflon_jax.units import INCH

# Stainless steel (AISI 304/316) near room temperature, as in Kumar et al. (2015).
STEEL_CONDUCTIVITY = 16.2
"""Thermal conductivity of stainless steel k [W/(m K)]."""


STEEL_DIFFUSIVITY = 4.4e-6
"""Thermal diffusivity of stainless steel kappa [m^2/s]."""


AMBIENT_TEMPERATURE = 20.0
"""Temperature at which the k_T factor of Kumar et al. (2015) equals 1 [degC]."""


@dataclasses.dataclass(frozen=True)
class EffectParameter:
    """One parameter of an effect (SI units).

    - `name`: engineer's name, e.g. `delta_f`, `breakaway_ratio`.
    - `initial`: value a fit starts from when the effect is switched on.
    - `neutral`: value for which the effect vanishes (or nearly so).
    - `lower`, `upper`: bounds of the fit.
    - `log_scale`: fit in log space (positive quantities spanning decades).
    - `unit`: unit in brackets for reports.
    - `neutral_of`: name of the parameter whose value is neutral for this one (the effect
      vanishes when they are equal, e.g. `f_max_perpendicular` = `f_max`); a fit adding the
      effect starts there. `None`: `neutral` is the neutral value.
    """

    name: str
    initial: float
    neutral: float
    lower: float
    upper: float
    log_scale: bool = False
    unit: str = "-"
    neutral_of: str | None = None


@dataclasses.dataclass(frozen=True)
class Effect:
    """A candidate physical effect missing from a model.

    - `name`: from the vocabulary `EFFECT_NAMES`.
    - `parameters`: its `EffectParameter`s (empty for none).
    - `equation`: the law it adds, in one line.
    - `regressor`: the measured or simulated quantity its signature follows (diagnostics).
    - `requires`: what the record must contain for the effect to be identifiable:
      `"varying_normal_load"`, `"biaxial"`, `"uniaxial"` or `None`.
    - `reference`: where the law comes from.
    """

    name: str
    parameters: tuple[EffectParameter, ...]
    equation: str
    regressor: str
    requires: str | None = None
    reference: str = ""


BASELINE_PARAMETERS = (
    EffectParameter("f_max", 0.1, 0.1, 0.002, 0.5, unit="-"),
    EffectParameter(
        "yield_disp",
        0.005 * INCH,
        0.005 * INCH,
        0.0002 * INCH,
        0.2 * INCH,
        log_scale=True,
        unit="m",
    ),
)
"""Parameters every model has: friction at large velocity (or the constant friction) and the
Bouc-Wen yield displacement Y of Eq. 3."""

EFFECTS: dict[str, Effect] = {
    effect.name: effect
    for effect in (
        Effect(
            "velocity_dependence",
            (
                EffectParameter("delta_f", 0.05, 0.0, 0.0, 0.45),
                EffectParameter(
                    "rate_a",
                    1.0 / INCH,
                    1.0 / INCH,
                    0.005 / INCH,
                    50.0 / INCH,
                    log_scale=True,
                    unit="s/m",
                ),
            ),
            "mu = f_max - delta_f exp(-rate_a |v|)  (Eq. 1)",
            "speed |v| [m/s]",
            reference="Constantinou, Mokha & Reinhorn (1990), Eq. 1",
        ),
        Effect(
            "breakaway",
            (EffectParameter("breakaway_ratio", 2.0, 1.0, 1.0, 8.0),),
            "mu = breakaway_ratio (f_max - delta_f) until max|Z| first reaches 0.999  (Eq. 17)",
            "first excursion from rest (indicator)",
            reference="Constantinou, Mokha & Reinhorn (1990), Eq. 17",
        ),
        Effect(
            "pressure_dependence",
            (EffectParameter("pressure_exponent", 0.3, 0.0, -1.0, 2.0),),
            "mu *= (N / N_ref)^(-pressure_exponent), N_ref = mean normal load",
            "log(N / N_ref) [-]",
            requires="varying_normal_load",
            reference="Mokha, Constantinou & Reinhorn (1990), friction falls with contact pressure",
        ),
        Effect(
            "heating",
            (EffectParameter("heat_scale", 1.0, 0.0, 0.0, 20.0),),
            "mu *= k_T(T0 + heat_scale dT) / k_T(T0), k_T(T) = 0.79 (0.70^(T/50) + 0.40); "
            "dT = T_measured - T_measured(0) and T0 = T_measured(0) when the record has a "
            "'temperature' column, else dT = sqrt(kappa/pi)/k int q(s) (t-s)^(-1/2) ds with "
            "q = mu p |v| / n_series (heat flux into each sliding surface) and T0 = 20 degC",
            "temperature rise dT [K] (measured, or from the heat-flux history)",
            reference="Kumar, Whittaker & Constantinou (2015), k_T; Carslaw & Jaeger (1959) "
            "Sec. 2.9 when no temperature is measured",
        ),
        Effect(
            "anisotropy",
            (
                EffectParameter("f_max_perpendicular", 0.1, 0.1, 0.002, 0.5, neutral_of="f_max"),
                EffectParameter("delta_f_perpendicular", 0.05, 0.05, 0.0, 0.45,
                                neutral_of="delta_f"),
                EffectParameter(
                    "rate_a_perpendicular",
                    1.0 / INCH,
                    1.0 / INCH,
                    0.005 / INCH,
                    50.0 / INCH,
                    log_scale=True,
                    unit="s/m",
                    neutral_of="rate_a",
                ),
            ),
            "c(w) = (1 - w) c_P + w c_T for c = f_max, delta_f, rate_a; mu = f_max(w) - delta_f(w) "
            "exp(-rate_a(w) |v|); w = |theta| / (pi/2), theta the sliding angle to the lay (x); "
            "f_max, delta_f, rate_a are the parallel (P) constants, *_perpendicular the T ones",
            "sliding angle weight |theta| / (pi/2) [-]",
            requires="biaxial",
            reference="Constantinou, Mokha & Reinhorn (1990), anisotropic biaxial model "
            "(linear interpolation of all three constants of Eq. 1 between P and T)",
        ),
        Effect(
            "asymmetry",
            (EffectParameter("asymmetry", 0.05, 0.0, -0.6, 0.6),),
            "mu *= 1 + asymmetry Z_x: +asymmetry while sliding in +x (Z = 1), -asymmetry in -x "
            "(Z = -1), passing through 1 with Z at a reversal, so the force has no step",
            "hysteretic variable Z_x [-] (the sliding direction, smoothed)",
            reference="direction-dependent friction, e.g. a tilted or misaligned specimen or a "
            "self-energising band brake; tied to Z so that F = mu N Z stays continuous",
        ),
        Effect(
            "wear",
            (EffectParameter("wear_change", 0.0, 0.0, -0.8, 3.0),),
            "mu *= 1 + wear_change travel / travel_total (no recovery)",
            "accumulated travel [m]",
            reference="Mokha, Constantinou & Reinhorn (1990), friction changing with travel",
        ),
        Effect(
            "interfaces",
            (EffectParameter("n_interfaces", 4.0, 1.0, 1.0, 60.0, log_scale=True),),
            "Eq. 1 evaluated at |v| / n_interfaces (n interfaces in series share the motion); "
            "only rate_a / n enters Eq. 1, so n is separable only with rate_a known",
            "speed |v| [m/s]",
            reference="Constantinou, Mokha & Reinhorn (1990), R-FBI stack (n = 24)",
        ),
        Effect(
            "backlash",
            (
                EffectParameter(
                    "backlash_gap", 0.02 * INCH, 1e-6, 1e-6, 0.1, log_scale=True, unit="m"
                ),
            ),
            "a gap g in series: after each reversal Z unloads to 0 along Bouc-Wen, stays at 0 "
            "(F = 0) while the drive crosses the gap g, then loads again (Z continuous in u and g)",
            "force near zero after reversals (indicator of |Z| < 0.5) [-]",
            requires="uniaxial",
            reference="play (backlash) operator in series with the friction element, as in bolted "
            "friction dampers with oversized holes; Krasnosel'skii & Pokrovskii (1989) play operator",
        ),
    )
}
"""The candidate effects by name."""

EFFECT_NAMES = tuple(EFFECTS)

BASELINES = {
    "paper1990": ("velocity_dependence",),
    "coulomb": (),
}
"""Effects each baseline starts with: `paper1990` is Eq. 1 with Bouc-Wen (no breakaway,
isotropic, constant parameters); `coulomb` is constant friction with Bouc-Wen."""


def kumar_temperature_factor(temperature):
    """k_T = 0.79 (0.70^(T/50) + 0.40) of Kumar, Whittaker & Constantinou (2015).

    **Arguments:** `temperature` T of the sliding surface [degC].

    **Returns:** the factor on the friction coefficient [-]; 1.00 at 20 degC.
    """
    return 0.79 * (jnp.power(0.70, temperature / 50.0) + 0.40)


def heating_factor(temperature_rise, ambient=AMBIENT_TEMPERATURE):
    """Friction factor k_T(T0 + dT) / k_T(T0) for a surface temperature rise `dT` [K]; 1 at dT = 0."""
    return kumar_temperature_factor(ambient + temperature_rise) / kumar_temperature_factor(
        ambient
    )


def heat_kernel_exponentials(t_min: float, t_max: float, *, per_decade: float = 3.0):
    """Rates and weights of a sum of exponentials approximating 1/sqrt(t) on [t_min, t_max].

    1/sqrt(t) = pi^(-1/2) int_R exp(x/2) exp(-exp(x) t) dx (substituting s = e^x in the Laplace
    representation); the trapezoidal rule in x on a uniform grid converges geometrically, so
        1/sqrt(t) ~ sum_j w_j exp(-lambda_j t),  lambda_j = e^(x_j),  w_j = h e^(x_j/2) / sqrt(pi).
    The grid spans lambda from 1e-6 / t_max (the neglected slow tail adds about
    2 sqrt(lambda_min t / pi) < 1.2e-3 relative error at t_max) to 1e4 / t_min (the fastest term resolves the
    integrable singularity within a step to about 1 %); with 3 nodes per decade the
    quadrature error is of order exp(-pi^2 / h) ~ 1e-5. With it, the convolution with the
    1/sqrt(t) kernel becomes a set of first-order states (O(n) in time, differentiable).

    **Arguments:** `t_min`, `t_max` [s]: shortest (a time step) and longest (the record) time.

    **Returns:** numpy arrays `(rates [1/s], weights [s^-1/2])` such that
    `sum(weights * exp(-rates * t))` approximates `t**-0.5` [s^-1/2].
    """
    if not 0 < t_min < t_max:
        raise ValueError(f"heat kernel: need 0 < t_min < t_max, got {t_min}, {t_max}.")
    h = np.log(10.0) / per_decade
    x = np.arange(np.log(1e-6 / t_max), np.log(1e4 / t_min) + h, h)
    return np.exp(x), h * np.exp(x / 2) / np.sqrt(np.pi)


def surface_temperature_coefficient(
    conductivity=STEEL_CONDUCTIVITY, diffusivity=STEEL_DIFFUSIVITY
):
    """C in dT(t) = C int q(s) (t - s)^(-1/2) ds, C = sqrt(kappa / pi) / k [K m^2 / (W s^1/2)].

    Surface temperature of a semi-infinite solid heated by a surface flux q(t) [W/m^2]
    (Carslaw & Jaeger 1959, Sec. 2.9). A constant flux q0 gives dT = 2 q0 sqrt(kappa t / pi) / k.
    """
    return float(np.sqrt(diffusivity / np.pi) / conductivity)


def breakaway_switch(z_peak):
    """True while the interface has not yet been fully mobilised (Eq. 17)."""
    return z_peak < BREAKAWAY_THRESHOLD


def backlash_update(h, z0, gap_position, displacement_increment, gap):
    """Z and the gap position after a monotone increment of a gap in series with Bouc-Wen.

    The drive moves by du = sigma |du|. The friction element (Bouc-Wen, Eq. 3) and a gap of
    width g [m] act in series, and the force through an open gap is zero: so after a reversal
    Z first unloads to 0 along Bouc-Wen (travel Y x0, x0 = `bouc_wen_reversal_length`), then the
    drive crosses the gap with Z = 0 (the gap position s [m] moves from -sigma g/2 towards
    sigma g/2; F = mu N Z = 0 over that travel), then Z loads again from 0 with the travel
    left. Invariant: s = sign(Z) g/2 whenever Z != 0 (the gap is closed on the loaded side);
    a record starts with Z = 0 and s = 0 (centred in the gap). With g = 0 this is
    `bouc_wen_exact_update`. Z is continuous in the displacement and in g, so the force is
    continuous and a fit can differentiate in g.

    **Arguments:** `h` Bouc-Wen constants, `z0` [-], `gap_position` s [m],
    `displacement_increment` du [m], `gap` g [m] (>= 0).

    **Returns:** `(z1, s1)`.

    Reference: the play operator of Krasnosel'skii & Pokrovskii (1989), "Systems with
    Hysteresis", here placed where the transmitted force vanishes.
    """
    from teflon_jax import bouc_wen_exact_update, bouc_wen_reversal_length

    du = displacement_increment
    sigma = jnp.where(du >= 0, 1.0, -1.0)
    travel = jnp.abs(du)
    unloading = sigma * z0 < 0
    to_zero = jnp.where(unloading, bouc_wen_reversal_length(h, z0) * h.yield_disp, 0.0)
    reached = travel >= to_zero
    z_part = bouc_wen_exact_update(h, z0, sigma * jnp.minimum(travel, to_zero))
    left = jnp.maximum(travel - to_zero, 0.0)
    available = jnp.maximum(0.5 * gap - sigma * gap_position, 0.0)
    in_gap = jnp.minimum(left, available)
    s1 = jnp.where(reached, gap_position + sigma * in_gap, gap_position)
    z_start = jnp.where(reached & unloading, 0.0, z_part)
    z1 = jnp.where(reached, bouc_wen_exact_update(h, z_start, sigma * (left - in_gap)), z_part)
    return z1, s1
