"""What a triple or double friction pendulum's test record can tell: which constants of the
series model (`teflon_jax.bearing.TriplePendulum`, `DoublePendulum`) a fit frees, and why it
holds the others.

Each slider of the series model (the triple's inner pair, bottom and top surface, the double's
bottom and top surface; Fenz & Constantinou 2006, 2008) shows its radius and friction only where it
slides, its restrainer only where the loop reaches its capacity, and the rate dependence of
Eq. 1, mu(v) = f_max - delta_f exp(-a v) (Constantinou, Mokha & Reinhorn 1990), only where
exp(-a v) changes over the sliding speeds v of its surface. The decisions are read from the
simulation of the record's displacement with the start's constants:

- a surface slides when its slider travels more than `SLIDING_TRAVEL` yield displacements;
- a capacity is freed when its slider goes beyond it (the restrainer shows);
- delta_f and rate_a of a surface are freed when exp(-a v) spans more than `RATE_SPREAD` over
  the samples where it slides (with the start's a > 0 and delta_f > 0), else held (Coulomb
  friction at the tested speeds: f_max is then the friction the record shows).
"""

import numpy as np

SURFACES = ("inner", "bottom", "top")
"""The surface groups: inner (2 and 3, alike), bottom (1), top (4)."""

FRICTION_CONSTANTS = ("f_max", "delta_f", "rate_a")
"""Eq. 1's constants of each surface."""



def parameter_names(surfaces=SURFACES) -> tuple:
    """Every constant a fit may free of a pendulum with these `surfaces` (its `slider_names`):
    the effective radii, the Eq. 1 constants of each surface, the effective capacities."""
    return (tuple(f"{s}_radius" for s in surfaces)
            + tuple(f"{s}_{c}" for s in surfaces for c in FRICTION_CONSTANTS)
            + tuple(f"{s}_capacity" for s in surfaces))


def parameter_units(surfaces=SURFACES) -> dict:
    """SI unit of each of `parameter_names(surfaces)`, as the isolator file writes it."""
    return {n: "m" if n.endswith(("radius", "capacity")) else "s/m" if n.endswith("rate_a") else "1"
            for n in parameter_names(surfaces)}


PARAMETER_NAMES = parameter_names(SURFACES)
"""Every constant of a triple pendulum a fit may free (effective radii and capacities [m],
f_max and delta_f [-], rate_a [s/m])."""

PARAMETER_UNITS = parameter_units(SURFACES)
"""SI unit of each parameter of a triple pendulum, as the isolator file writes it."""

DOUBLE_PARAMETER_NAMES = parameter_names(("bottom", "top"))
DOUBLE_PARAMETER_UNITS = parameter_units(("bottom", "top"))
"""The same of a double pendulum (surfaces bottom and top)."""

SLIDING_TRAVEL = 10.0
"""A surface slides in a record when its slider's travel exceeds this many yield
displacements of Bouc-Wen's Z [-]."""

RATE_SPREAD = 0.05
"""Smallest span of exp(-a v) over a surface's sliding samples that frees delta_f and rate_a [-]."""


def surface_of(name: str) -> str:
    return name.split("_", 1)[0]


def check_free(free, known=PARAMETER_NAMES) -> tuple:
    """The names of `free` (a comma-separated text or a sequence), each one of `known`, once;
    `ValueError` naming an unknown one."""
    names = [n.strip() for n in (free.split(",") if isinstance(free, str) else free) if n.strip()]
    unknown = [n for n in names if n not in known]
    if unknown or not names:
        raise ValueError(f"free: unknown parameter(s) {unknown}; the pendulum's are "
                         f"{', '.join(known)}." if unknown else
                         "free: give at least one parameter to fit.")
    return tuple(n for n in known if n in names)


def triple_fit_plan(start, response, time, *, full_model: bool = False) -> tuple[tuple, dict]:
    """(free names, {held name: reason}) for a record whose simulation with the `start`
    constants (`TriplePendulum` or `DoublePendulum`) is `response` (`BearingTestResult`) at the sample `time` [s]
    (module docstring). `full_model`: free delta_f and rate_a of every sliding surface
    whatever the speeds."""
    slider = np.asarray(response.slider)
    if slider.ndim == 2:
        slider = slider[..., None]
    reach = np.sqrt(np.sum(slider**2, axis=-1))  # (nt, S)
    travel = np.sum(np.sqrt(np.sum(np.diff(slider, axis=0) ** 2, axis=-1)), axis=0)
    capacities = np.asarray(start.series_capacities())
    dt = np.diff(np.asarray(time, float))[:, None]
    speed = np.sqrt(np.sum(np.diff(slider, axis=0) ** 2, axis=-1)) / dt * np.asarray(start.velocity_factors())
    yield_disp = float(np.asarray(start.hysteresis.yield_disp))
    held = {}
    for i, surface in enumerate(start.slider_names):
        if not travel[i] > SLIDING_TRAVEL * yield_disp:
            why = (f"the {surface} surface does not slide in this record (its slider travels "
                   f"{travel[i]:.3g} m): its radius and friction are held at the start's values")
            held.update({n: why for n in (f"{surface}_radius",) + tuple(
                f"{surface}_{c}" for c in FRICTION_CONSTANTS)})
        elif not full_model:
            reason = _rate_hidden(start, surface, speed[:, i])
            if reason:
                held.update({f"{surface}_delta_f": reason, f"{surface}_rate_a": reason})
        if not np.max(reach[:, i]) > capacities[i]:
            held[f"{surface}_capacity"] = (
                f"the loop does not reach the {surface} restrainer (slider at "
                f"{np.max(reach[:, i]):.3g} m of {capacities[i]:.3g} m): capacity held")
    free = tuple(n for n in parameter_names(start.slider_names) if n not in held)
    return free, held


def _rate_hidden(start, surface: str, speed) -> str:
    """Why delta_f and rate_a of `surface` cannot be seen at its sliding `speed` [m/s] (""
    when they can)."""
    friction = getattr(start, f"{surface}_friction")
    rate, delta = float(np.asarray(friction.rate_a)), float(np.asarray(friction.delta_f))
    if not (rate > 0 and delta > 0):
        return (f"the start's {surface} friction is Coulomb's (delta_f or rate_a zero): "
                "delta_f and rate_a held; give a rate-dependent start to fit them")
    sliding = speed[speed > 1e-3 * np.max(speed)]
    shape = np.exp(-rate * sliding)
    if sliding.size < 2 or not float(np.ptp(shape)) > RATE_SPREAD:
        return (f"the {surface} surface's friction does not change over its sliding speeds "
                f"({np.min(sliding, initial=0):.3g}-{np.max(sliding, initial=0):.3g} m/s; "
                f"exp(-a v) spans {float(np.ptp(shape)) if sliding.size else 0:.3g}): delta_f "
                "and rate_a held (f_max is the friction it shows)")
    return ""

TRIPLE_PARAMETER_NAMES = PARAMETER_NAMES
TRIPLE_PARAMETER_UNITS = PARAMETER_UNITS
"""`PARAMETER_NAMES`, `PARAMETER_UNITS` under the names the package exports."""

series_fit_plan = triple_fit_plan
"""`triple_fit_plan`, which takes any series pendulum."""
