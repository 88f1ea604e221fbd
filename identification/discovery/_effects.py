"""Candidate effects for model discovery: named, documented extensions of the 1990 model.

Each effect is an optional part of the one bearing model (`teflon_jax.bearing`: its laws,
equations and references are there); this table says, for discovery, which constants each
effect adds (their bounds are the search ranges of `teflon_jax.bearing.PARAMETER_BOUNDS`), the
value a fit starts from and the *neutral* value for which the
effect vanishes, what the record must contain to identify it and the regressor its signature
follows in the residual.

References: Constantinou, Mokha & Reinhorn (1990), Eqs. 1, 17 and Section on multiple
interfaces; Carslaw & Jaeger (1959), "Conduction of Heat in Solids", Section 2.9 (surface
temperature of a semi-infinite body under a surface heat flux); Kumar, Whittaker &
Constantinou (2015), "Characterizing friction in sliding isolation bearings", Earthquake Eng.
Struct. Dyn. 44(9) (k_T factor); Mokha, Constantinou & Reinhorn (1990), "Teflon bearings in
base isolation I: Testing" (pressure, wear and direction effects).
"""

import dataclasses

from teflon_jax.bearing import PARAMETER_BOUNDS
from teflon_jax.units import INCH


@dataclasses.dataclass(frozen=True)
class EffectParameter:
    """One parameter of an effect (SI units).

    - `name`: engineer's name, e.g. `delta_f`, `breakaway_ratio`: a key of
      `teflon_jax.bearing.PARAMETER_BOUNDS`, whose search range gives `lower`, `upper`,
      `log_scale` (fit in log space) and `unit`.
    - `initial`: value a fit starts from when the effect is switched on.
    - `neutral`: value for which the effect vanishes (or nearly so).
    - `neutral_of`: name of the parameter whose value is neutral for this one (the effect
      vanishes when they are equal, e.g. `f_max_perpendicular` = `f_max`); a fit adding the
      effect starts there. `None`: `neutral` is the neutral value.
    """

    name: str
    initial: float
    neutral: float
    neutral_of: str | None = None

    @property
    def lower(self) -> float:
        return PARAMETER_BOUNDS[self.name].search[0]

    @property
    def upper(self) -> float:
        return PARAMETER_BOUNDS[self.name].search[1]

    @property
    def log_scale(self) -> bool:
        return PARAMETER_BOUNDS[self.name].log_scale

    @property
    def unit(self) -> str:
        return PARAMETER_BOUNDS[self.name].unit


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
    EffectParameter("f_max", 0.1, 0.1),
    EffectParameter("yield_disp", 0.005 * INCH, 0.005 * INCH),
)
"""Parameters every model has: friction at large velocity (or the constant friction) and the
Bouc-Wen yield displacement Y of Eq. 3."""

EFFECTS: dict[str, Effect] = {
    effect.name: effect
    for effect in (
        Effect(
            "velocity_dependence",
            (
                EffectParameter("delta_f", 0.05, 0.0),
                EffectParameter("rate_a", 1.0 / INCH, 1.0 / INCH),
            ),
            "mu = f_max - delta_f exp(-rate_a |v|)  (Eq. 1)",
            "speed |v| [m/s]",
            reference="Constantinou, Mokha & Reinhorn (1990), Eq. 1",
        ),
        Effect(
            "breakaway",
            (EffectParameter("breakaway_ratio", 2.0, 1.0),),
            "mu = breakaway_ratio (f_max - delta_f) until max|Z| first reaches 0.999  (Eq. 17)",
            "first excursion from rest (indicator)",
            reference="Constantinou, Mokha & Reinhorn (1990), Eq. 17",
        ),
        Effect(
            "pressure_dependence",
            (EffectParameter("pressure_exponent", 0.3, 0.0),),
            "mu *= (N / N_ref)^(-pressure_exponent), N_ref = mean normal load",
            "log(N / N_ref) [-]",
            requires="varying_normal_load",
            reference="Mokha, Constantinou & Reinhorn (1990), friction falls with contact pressure",
        ),
        Effect(
            "heating",
            (EffectParameter("heat_scale", 1.0, 0.0),),
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
                EffectParameter("f_max_perpendicular", 0.1, 0.1, neutral_of="f_max"),
                EffectParameter("delta_f_perpendicular", 0.05, 0.05, neutral_of="delta_f"),
                EffectParameter("rate_a_perpendicular", 1.0 / INCH, 1.0 / INCH,
                                neutral_of="rate_a"),
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
            (EffectParameter("asymmetry", 0.05, 0.0),),
            "mu *= 1 + asymmetry Z_x: +asymmetry while sliding in +x (Z = 1), -asymmetry in -x "
            "(Z = -1), passing through 1 with Z at a reversal, so the force has no step",
            "hysteretic variable Z_x [-] (the sliding direction, smoothed)",
            reference="direction-dependent friction, e.g. a tilted or misaligned specimen or a "
            "self-energising band brake; tied to Z so that F = mu N Z stays continuous",
        ),
        Effect(
            "wear",
            (EffectParameter("wear_change", 0.0, 0.0),),
            "mu *= 1 + wear_change travel / travel_total (no recovery)",
            "accumulated travel [m]",
            reference="Mokha, Constantinou & Reinhorn (1990), friction changing with travel",
        ),
        Effect(
            "interfaces",
            (EffectParameter("n_interfaces", 4.0, 1.0),),
            "Eq. 1 evaluated at |v| / n_interfaces (n interfaces in series share the motion); "
            "only rate_a / n enters Eq. 1, so n is separable only with rate_a known",
            "speed |v| [m/s]",
            reference="Constantinou, Mokha & Reinhorn (1990), R-FBI stack (n = 24)",
        ),
        Effect(
            "backlash",
            (
                EffectParameter("backlash_gap", 0.02 * INCH, 1e-6),
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
