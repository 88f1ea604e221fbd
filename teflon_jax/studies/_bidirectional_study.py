"""The rigid mass and the building of the studies under two ground components, and their peaks.

`BidirectionalIsolatedStructure` is `IsolatedStructure` (Table 1 friction at a pressure,
springs and dampers of period T_b and ratio zeta_b, Eq. 17 breakaway) built as a
`BidirectionalStructure` (`bidirectional_rigid_mass`, `bidirectional_building`): one group
of isotropic bearings with Park's biaxial Z (Eqs. 8-9) and Eq. 1 at the resultant sliding
speed. `bidirectional_peak_response` keeps only the peaks of a run (a `PeakResponse`), as
`peak_response` does for one component, with the displacement and the shear taken as resultants:

    base_disp        = max_t |d(t)|,          d = (d_x, d_y) the bearings' displacement,
    base_shear_ratio = max_t |V(t)| / W,      V = sum_n m_n a_n^total R_n,

V being the total horizontal force on the structure above the bearings (every mass, the
base's included) and W its weight. For the rigid mass this is the uniaxial `peak_response`'s
ratio; for the building the uniaxial one is the first-storey shear over the floors' weight.
Reference: Constantinou, Mokha & Reinhorn (1990), J. Struct. Eng. 116(2), Eqs. 1, 8-9, 17.
"""

import dataclasses
from collections.abc import Mapping

import equinox as eqx
import jax
import jax.numpy as jnp

from ..systems import (
    BIDIRECTIONAL_TIME_STEP,
    BiaxialStructureOnTriple,
    BidirectionalStructure,
    IsolatedStructure,
    PeakResponse,
    TripleIsolatedStructure,
    biaxial_peaks,
    bidirectional_building,
    bidirectional_initial_state,
    bidirectional_rigid_mass,
    directional_storeys,
    isolated_structure,
    series_uplift_time,
    smooth_max_update,
    smooth_max_value,
)
from ..units import STANDARD_GRAVITY


class BidirectionalIsolatedStructure(eqx.Module):
    """Builds the two-component rigid mass or building for one motion and one design.

    Call as `structure((ground_x, ground_y), design)` with two `Signal`s [m/s^2] and `design`
    a dict of some of the `IsolatedStructure` design variables. **Fields:** `uniaxial`, the
    `IsolatedStructure` whose kind, Table 1 row, pressure, springs, dampers, breakaway,
    weight and time step it takes; `newton_iterations` (static): the most Newton iterations of
    the bearing solve per step (`None`: `BidirectionalStructure`'s default).
    """

    uniaxial: IsolatedStructure
    newton_iterations: int | None = eqx.field(static=True, default=None)

    @property
    def time_step(self) -> float:
        """Step of the structure solver [s]."""
        return self.uniaxial.time_step

    def __call__(self, ground, design: Mapping | None = None) -> BidirectionalStructure:
        ground_x, ground_y = ground
        s = self.uniaxial
        bearing, period, damping = s.isolation(design)
        law = {"friction_model": s.friction_model,
               "surface": None if s.surface is None else s.designed_surface(design)}
        if s.kind == "rigid":
            system = bidirectional_rigid_mass(
                weight=s.weight, bearing=bearing, ground_x=ground_x, ground_y=ground_y,
                time_step=s.time_step, isolation_period=period,
                damping_ratio=damping if period is not None else 0.0,
                contact_pressure=s.contact_pressure(design), **law,
            )
        else:
            system = bidirectional_building(
                bearing=bearing, ground_x=ground_x, ground_y=ground_y, time_step=s.time_step,
                isolation_period=period, isolation_damping=damping,
                contact_pressure=s.contact_pressure(design), **law,
            )
        if self.newton_iterations is not None:
            system = dataclasses.replace(system, newton_iterations=self.newton_iterations)
        return system


def bidirectional_isolated_structure(kind: str = "rigid", **options) -> BidirectionalIsolatedStructure:
    """A `BidirectionalIsolatedStructure` with the inputs of `isolated_structure(kind,
    **options)` (checked there, `ValueError` naming the parameter), stepped at
    `BIDIRECTIONAL_TIME_STEP` unless `time_step` is given. The friction models of one
    component run in two (Park's Z, Coulomb, none), and so do a pendulum's restrainer and
    large-displacement form. On a triple or double friction pendulum the
    `TripleIsolatedStructure` of `isolated_structure`, which takes both components itself."""
    if isinstance(structure := isolated_structure(kind, **options), TripleIsolatedStructure):
        return structure  # the series engine builds both: called with (ground_x, ground_y)
    if options.get("time_step") is None:  # the uniaxial default steps are not the bidirectional one
        options = {**options, "time_step": BIDIRECTIONAL_TIME_STEP}
    newton_iterations = options.get("newton_iterations")
    return BidirectionalIsolatedStructure(isolated_structure(kind, **options), newton_iterations)


def bidirectional_peak_response(
    system: BidirectionalStructure,
    duration: float,
    *,
    disp_width=None,
    shear_width=None,
    read_every: int = 1,
    storey_height=None,
) -> PeakResponse:
    """Integrate `system` from rest over `duration` [s] with `RiccatiNewmark`'s step
    (`newmark_step`) in a `lax.scan` and keep the peaks of the resultant bearing displacement
    of group 0 and of the resultant base shear ratio (module docstring), and their smooth
    maxima `w log(mean cosh(x / w))` (`smooth_max`, widths `disp_width` [m] and `shear_width`
    [-], default 1e-3 each). The accelerations are the equation of motion's (the system's
    vector field) at the end of each step, as `simulate_bidirectional` saves them.
    `read_every`: peaks read every k-th step (the smooth maxima see every step). jit/vmap-safe.
    `storey_height` [m] (the building): also the peak drift ratio per storey and total
    acceleration per level in x and y (`directional_storeys`; on triple or double friction
    pendulums, a `BiaxialStructureOnTriple`, `biaxial_peaks`).

    **Returns:** a `PeakResponse` (`storey_drift` (2, S), `floor_acceleration` (2, S + 1)).
    """
    if isinstance(system, BiaxialStructureOnTriple):  # triple or double friction pendulums
        widths = (1e-3 if disp_width is None else disp_width, 1e-3 if shear_width is None else shear_width)
        uplift = series_uplift_time(system, duration)  # with the uniaxial structure's vertical record
        return PeakResponse(*biaxial_peaks(system, duration, widths, read_every, storey_height),
                            **({} if uplift is None else {"uplift_time": uplift}))
    if system.overturning is not None:
        raise ValueError("system: the peaks in a scan do not carry the slab's overturning loads; "
                         "run it with simulate_bidirectional (teflon-jax run without --suite).")
    dt = float(system.time_step)
    n_steps = int(duration / dt + 1e-9)
    if n_steps < 1:
        raise ValueError(f"duration: must be at least one time step ({dt} s), got {duration}.")
    if isinstance(read_every, bool) or not isinstance(read_every, int) or read_every < 1:
        raise ValueError(f"read_every: must be a positive integer number of steps, got {read_every!r}.")
    dtype = system.mass.dtype
    widths = (jnp.asarray(1e-3 if disp_width is None else disp_width, dtype),
              jnp.asarray(1e-3 if shear_width is None else shear_width, dtype))
    mass, influence = system.mass, system.influence
    weight = jnp.sum(mass * influence[:, 0]) * STANDARD_GRAVITY

    def values(ground, y, a):
        disp = system.bearing_motion(y["q"])[0]
        total = a + jnp.sum(influence * ground, axis=-1)
        force = jnp.sum((total * mass)[:, None] * influence, axis=0)
        return jnp.sqrt(jnp.sum(disp**2)), jnp.sqrt(jnp.sum(force**2)) / weight

    def storeys(ground, y, a):
        if storey_height is None:
            return ()
        drift, acc = directional_storeys(y["q"], a + influence @ ground, storey_height)
        return jnp.abs(drift), jnp.abs(acc)

    def body(carry, step_and_ground):
        step, ground1, load1 = step_and_ground
        y, a, peaks, tops, totals, ok = carry
        loaded = system.at_load(load1)  # the normal load at the step's end (vertical record)
        y1, converged = loaded.newmark_update(y, a, ground1)
        a1 = loaded.acceleration_at(ground1, y1)
        now = values(ground1, y1, a1) + storeys(ground1, y1, a1)  # smooth maxima: the first two
        read = (step + 1) % read_every == 0
        peaks = tuple(jnp.where(read, jnp.maximum(p, v), p) for p, v in zip(peaks, now))
        updated = [smooth_max_update(*args) for args in zip(tops, totals, now, widths)]
        return (y1, a1, peaks, tuple(u[0] for u in updated), tuple(u[1] for u in updated),
                ok & converged), None

    y0 = bidirectional_initial_state(system)
    # the record at every step's end, evaluated at once outside the loop
    times = jnp.arange(n_steps + 1) * dt
    ground = jax.vmap(system.ground)(times)
    loads = None if system.vertical_acceleration is None else jax.vmap(system.load_factor)(times)
    if loads is not None:
        system.vertical_acceleration.require_covers(n_steps * dt, "duration (vertical record)")
    a0 = system.at_load(None if loads is None else loads[0]).acceleration_at(ground[0], y0)
    zero, one = jnp.zeros((), dtype), jnp.ones((), dtype)
    floors = tuple(jnp.zeros_like(v) for v in storeys(ground[0], y0, a0))
    carry = (y0, a0, (zero, zero) + floors, (zero, zero), (one, one), jnp.array(True))
    (_, _, peaks, tops, totals, ok), _ = jax.lax.scan(
        body, carry, (jnp.arange(n_steps), ground[1:], None if loads is None else loads[1:]))
    smooth = [smooth_max_value(top, s, n_steps + 1, w) for top, s, w in zip(tops, totals, widths)]
    return PeakResponse(base_disp=peaks[0], base_shear_ratio=peaks[1], smooth_base_disp=smooth[0],
                        smooth_base_shear_ratio=smooth[1], converged=ok,
                        **({} if storey_height is None else {"storey_drift": peaks[2],
                                                             "floor_acceleration": peaks[3]}),
                        **({} if loads is None else {"uplift_time": uplift_time(system, loads, dt)}))


def uplift_time(system, loads, dt):
    """Time [s] of the steps 1.. whose end has N <= 0 (a_v <= -g), from the load factors."""
    ends = jnp.arange(1, loads.shape[0]) * dt
    return jnp.sum(1 + jax.vmap(system.vertical_acceleration)(ends) / STANDARD_GRAVITY <= 0) * dt
