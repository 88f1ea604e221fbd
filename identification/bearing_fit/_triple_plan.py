"""What a triple friction pendulum's test record can tell: which constants of the series model
(`teflon_jax.bearing.TriplePendulum`) a fit frees, and why it holds the others.

Each of the three sliders of the series model (the inner pair, the bottom and the top surface;
Fenz & Constantinou 2008, Earthquake Spectra 24(4)) shows its radius and friction only where it
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

RADII = tuple(f"{s}_radius" for s in SURFACES)
CAPACITIES = tuple(f"{s}_capacity" for s in SURFACES)
FRICTIONS = tuple(f"{s}_{c}" for s in SURFACES for c in FRICTION_CONSTANTS)
PARAMETER_NAMES = RADII + FRICTIONS + CAPACITIES
"""Every constant of a triple pendulum a fit may free (effective radii and capacities [m],
f_max and delta_f [-], rate_a [s/m])."""

PARAMETER_UNITS = {**{n: "m" for n in RADII + CAPACITIES},
                   **{f"{s}_{c}": ("s/m" if c == "rate_a" else "1")
                      for s in SURFACES for c in FRICTION_CONSTANTS}}
"""SI unit of each parameter, as the isolator file writes it."""

SLIDING_TRAVEL = 10.0
"""A surface slides in a record when its slider's travel exceeds this many yield
displacements of Bouc-Wen's Z [-]."""

RATE_SPREAD = 0.05
"""Smallest span of exp(-a v) over a surface's sliding samples that frees delta_f and rate_a [-]."""


def surface_of(name: str) -> str:
    return name.split("_", 1)[0]


def check_free(free) -> tuple:
    """The names of `free` (a comma-separated text or a sequence), each known, once;
    `ValueError` naming an unknown one."""
    names = [n.strip() for n in (free.split(",") if isinstance(free, str) else free) if n.strip()]
    unknown = [n for n in names if n not in PARAMETER_NAMES]
    if unknown or not names:
        raise ValueError(f"free: unknown parameter(s) {unknown}; the triple pendulum's are "
                         f"{', '.join(PARAMETER_NAMES)}." if unknown else
                         "free: give at least one parameter to fit.")
    return tuple(n for n in PARAMETER_NAMES if n in names)


def triple_fit_plan(start, response, time, *, full_model: bool = False) -> tuple[tuple, dict]:
    """(free names, {held name: reason}) for a record whose simulation with the `start`
    constants (`TriplePendulum`) is `response` (`TripleResponse`) at the sample `time` [s]
    (module docstring). `full_model`: free delta_f and rate_a of every sliding surface
    whatever the speeds."""
    slider = np.asarray(response.slider)
    if slider.ndim == 2:
        slider = slider[..., None]
    reach = np.sqrt(np.sum(slider**2, axis=-1))  # (nt, 3)
    travel = np.sum(np.sqrt(np.sum(np.diff(slider, axis=0) ** 2, axis=-1)), axis=0)
    capacities = np.asarray(start.series_capacities())
    dt = float(time[1] - time[0])
    speed = np.sqrt(np.sum(np.diff(slider, axis=0) ** 2, axis=-1)) / dt * np.asarray(start.velocity_factors())
    yield_disp = float(np.asarray(start.hysteresis.yield_disp))
    held = {}
    for i, surface in enumerate(SURFACES):
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
    free = tuple(n for n in PARAMETER_NAMES if n not in held)
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
