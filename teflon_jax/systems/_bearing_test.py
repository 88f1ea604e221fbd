"""Imposed-motion bearing tests: the friction force of a bearing driven along a known path.

Reference: Constantinou, Mokha & Reinhorn (1990), tests No. 62, 75, 191 and Figs. 3-6.
"""

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp

from ..bearing import (
    SeriesPendulum,
    SlidingBearing,
    bouc_wen_exact_update,
    bouc_wen_rate,
    check_bearing,
    check_series_pendulum,
    park_rate,
    sliding_speed,
)
from ..excitation import (
    AbstractBiaxialMotion,
    AbstractMotion,
    Signal,
    TabulatedMotion,
    as_signal,
)
from ..solver import (
    AbstractSteppedSystem,
    RiccatiNewmark,
    require_riccati_form,
    solve_with_controller,
)
from ..validation import given_options, require_positive
from ._imposed_path import (
    sample_velocity,
    sampled_path,
    series_along_path,
    sliding_along_path,
)
from ._response import BearingTestResult


def running_peak_rate(z_abs, z_peak, z_abs_rate):
    """d(max |Z| so far)/dt: follows |Z| while |Z| is at its running maximum and growing.

    This makes the breakaway switch of Eq. 17 part of the ODE state, so each member of a
    vmapped batch switches on its own.
    """
    tracking = z_abs >= z_peak - 1e-12
    return jnp.where(tracking, jnp.maximum(z_abs_rate, 0.0), 0.0)


class BearingTestSystem(AbstractSteppedSystem):
    """Z of a bearing driven by an imposed motion. State: {"z": (1,) along x (Bouc-Wen, Eq. 3)
    or (2,) in the plane (Park, Eqs. 8-9: an `AbstractBiaxialMotion`), "z_peak": ()}."""

    bearing: SlidingBearing
    motion: AbstractMotion

    def __call__(self, t, y, args):
        h = self.bearing.hysteresis
        v = self.motion.velocity(t)
        z = y["z"]
        if isinstance(self.motion, AbstractBiaxialMotion):
            dz = park_rate(h, z, v)
            z_abs = sliding_speed(z[0], z[1])  # |Z|, with a finite derivative at Z = 0
            z_abs_rate = jnp.dot(z, dz) / jnp.where(z_abs > 0, z_abs, 1.0)
        else:
            dz = bouc_wen_rate(h, z, v[0])
            z_abs, z_abs_rate = jnp.abs(z[0]), jnp.sign(z[0]) * dz[0]
        return {"z": dz, "z_peak": running_peak_rate(z_abs, y["z_peak"], z_abs_rate)}

    def advance(self, t0, t1, y0, args):
        if isinstance(self.motion, AbstractBiaxialMotion):
            raise ValueError(
                "solver: RiccatiNewmark handles uniaxial tests; for biaxial motion use a general "
                "diffrax solver (the default of simulate_bearing_test)."
            )
        h = require_riccati_form(self.bearing.hysteresis)
        du = self.motion.displacement(t1)[0] - self.motion.displacement(t0)[0]
        z1 = bouc_wen_exact_update(h, y0["z"], du)
        z_peak1 = jnp.maximum(y0["z_peak"], jnp.abs(z1[0]))
        return {"z": z1, "z_peak": z_peak1}, jnp.array(True)


def simulate_bearing_test(
    bearing: SlidingBearing | SeriesPendulum,
    motion: AbstractMotion,
    normal_load,
    *,
    duration: float | None = None,
    samples_per_cycle: int = 400,
    steps_per_sample: int = 1,
    solver: diffrax.AbstractSolver | None = None,
    rtol: float = 1e-8,
    atol: float = 1e-10,
    max_steps: int = 1_000_000,
    adjoint: diffrax.AbstractAdjoint | None = None,
    throw: bool = True,
    reference_load=None,
) -> BearingTestResult:
    """Simulate a bearing test of any isolator under an imposed motion.

    **Arguments:**

    - `bearing`: the `SlidingBearing` of flat sliders (vmap this function over a batched
      bearing to run many), or a `SeriesPendulum` (triple or double friction pendulum), whose
      sliders are balanced at each sample by the structures' solve (`respond_along_path`;
      the solve's options below are then refused by name).
    - `motion`: an `AbstractMotion` (sine, triangle, figure-eight, tabulated).
    - `normal_load` [N]: a constant or a `Signal` (time-varying normal load), which must cover
      `duration` (a recorded load is not extended past its last sample); a series pendulum
      whose surfaces read their contact pressure (heating, pressure dependence) takes a
      constant one, or with `reference_load` [N], the load its `<slider>_pressure` are given
      under, any (`respond_along_path`).
    - `duration` [s]: defaults to `motion.duration`.
    - `samples_per_cycle`: saved samples per cycle of the motion (tabulated: per input sample
      interval the sample spacing of the table is used instead).
    - `steps_per_sample`: steps between saved samples (the sampled motion's, or a fixed-step
      solver's).
    - `solver`: `None` or `RiccatiNewmark()` along x with eta = 2, gamma > beta: the bearing is
      driven along the sampled motion by `respond_along_path`, Z exact between samples (the
      force a fit of the record evaluates); any diffrax solver integrates Eq. 3 instead, an
      adaptive one (default in the plane and for other shapes: `Tsit5` with a PID controller
      at `rtol`, `atol`) with adaptive steps.
    - `adjoint` (a diffrax solve): diffrax adjoint; default reverse mode
      (`RecursiveCheckpointAdjoint`), or `diffrax.ForwardMode()` for `jax.jvp`/`jax.jacfwd` (the
      sampled motion's scan takes either mode as it is).
    - `throw`: raise on solver failure; with `False` the failure is in `result`.

    A bearing with optional parts (heating, wear, pressure dependence, asymmetry, backlash),
    and any bearing along x with the paper's shape unless a diffrax solver is given, is driven
    along the motion sampled at the save times (refined by `steps_per_sample`), with the
    motion's own velocity, by `respond_along_path` (Z exact between samples along x, Park along
    the Hermite path in the plane); the diffrax solve's options (`solver`, but for
    `RiccatiNewmark` along x, `rtol`, `atol`, `max_steps`, `adjoint`) are then refused by name.

    **Returns:** a `BearingTestResult` (of a series pendulum: the path, the force, each slider's
    displacement and Z, and whether each sample's balance converged).
    """
    if isinstance(bearing, SeriesPendulum):
        options = {"steps_per_sample": (steps_per_sample, 1), "solver": (solver, None), "rtol": (rtol, 1e-8),
                   "atol": (atol, 1e-10), "max_steps": (max_steps, 1_000_000), "adjoint": (adjoint, None),
                   "throw": (throw, True)}
        return _series_test(bearing, motion, normal_load, duration, samples_per_cycle, options, reference_load)
    if reference_load is not None:
        raise ValueError("reference_load: a sliding bearing's test reads the normal load itself; drop this option.")
    check_bearing(bearing)
    motion.check()
    if duration is None:
        duration = motion.duration
    normal_load = _normal_load_signal(normal_load, duration)
    times = save_times(motion, duration, samples_per_cycle)
    along_x = not isinstance(motion, AbstractBiaxialMotion) and _riccati_admitted(bearing.hysteresis)
    if bearing.effects or (along_x and (solver is None or isinstance(solver, RiccatiNewmark))):
        _refuse_solve_options(bearing, motion, {"solver": (solver, None), "rtol": (rtol, 1e-8), "atol": (atol, 1e-10),
                                                "max_steps": (max_steps, 1_000_000), "adjoint": (adjoint, None)})
        return _along_samples(bearing, motion, normal_load, _refine(times, steps_per_sample),
                              steps_per_sample)
    if solver is None:  # in the plane, or another Bouc-Wen shape
        solver = diffrax.Tsit5()
    system = BearingTestSystem(bearing=bearing, motion=motion)
    if isinstance(solver, RiccatiNewmark):
        require_riccati_form(bearing.hysteresis)
        controller = diffrax.StepTo(ts=_refine(times, steps_per_sample))
        dt0 = None
    elif _is_adaptive(solver):
        controller = diffrax.PIDController(rtol=rtol, atol=atol, jump_ts=_jumps(motion, duration))
        dt0 = float(times[1] - times[0]) / 10
    else:
        controller = diffrax.StepTo(ts=_refine(times, steps_per_sample))
        dt0 = None
    adjoint = diffrax.RecursiveCheckpointAdjoint() if adjoint is None else adjoint
    return _solve(system, solver, controller, dt0, times, normal_load, max_steps, adjoint, throw)


def _series_test(bearing: SeriesPendulum, motion, normal_load, duration, samples_per_cycle, options,
                 reference_load=None):
    """The test of a series pendulum (`simulate_bearing_test`): its balance along the motion
    sampled `samples_per_cycle` times a cycle (a tabulated motion at its own samples), under
    the normal load at each sample (`respond_along_path`); `ValueError` naming the options of
    the flat bearing's solve and a constant of the pendulum out of range."""
    given = given_options(options)
    if given:
        raise ValueError(f"{', '.join(given)}: the {bearing.description} balance their sliders at each "
                         "sample (the structures' solve); drop these options.")
    check_series_pendulum(bearing)
    motion.check()
    duration = motion.duration if duration is None else duration
    time = save_times(motion, duration, samples_per_cycle)
    path = jax.vmap(motion.displacement)(time)
    signal = _normal_load_signal(normal_load, duration)
    load = jax.vmap(signal)(time) if isinstance(normal_load, Signal) else normal_load
    planar = isinstance(motion, AbstractBiaxialMotion)
    return series_along_path(bearing, sampled_path(time, path[:, 0], load, uy=path[:, 1] if planar else None,
                                                   park_elements=1), reference_load=reference_load)


def _refuse_solve_options(bearing, motion, options) -> None:
    """`ValueError` naming the options of the diffrax solve given for a bearing that is driven
    along the sampled motion instead (one with optional parts, or along x with the paper's
    shape; Z exact between samples along x, Park along the Hermite path in the plane;
    `respond_along_path`): they would change nothing. `RiccatiNewmark` along x names that exact
    update and is taken."""
    solver = options["solver"][0]
    if isinstance(solver, RiccatiNewmark) and not isinstance(motion, AbstractBiaxialMotion):
        options = {**options, "solver": (None, None)}
    given = given_options(options)
    if given:
        which = (f"a bearing with {', '.join(bearing.effects)}" if bearing.effects else
                 "a bearing along x with the paper's Bouc-Wen shape (eta = 2, gamma > beta)")
        raise ValueError(f"{', '.join(given)}: {which} is driven along the sampled motion, Z exact between "
                         "samples (respond_along_path), not by a diffrax solve; drop these options "
                         "(steps_per_sample refines the samples)" + ("" if bearing.effects else
                                                                     ", or give a diffrax solver") + ".")


@eqx.filter_jit
def _solve(system, solver, controller, dt0, times, normal_load, max_steps, adjoint, throw):
    y0 = {"z": _z_at_rest(system.motion), "z_peak": jnp.zeros(())}
    solution = solve_with_controller(system, solver, controller, t0=times[0], t1=times[-1], dt0=dt0, y0=y0,
                                     save_times=times, max_steps=max_steps, adjoint=adjoint, throw=throw)
    return _result(system.bearing, system.motion, normal_load, solution)


def _along_samples(bearing, motion, normal_load, times, steps_per_sample):
    u = jax.vmap(motion.displacement)(times)
    v = jax.vmap(motion.velocity)(times)
    load = jax.vmap(normal_load)(times)
    if isinstance(motion, AbstractBiaxialMotion):
        path = sampled_path(times, u[:, 0], load, uy=u[:, 1], velocity=v[:, 0],
                            velocity_y=v[:, 1])
    else:
        path = sampled_path(times, u[:, 0], load, velocity=v[:, 0])
    r = sliding_along_path(bearing, path)
    keep = slice(None, None, steps_per_sample)
    return BearingTestResult(
        time=times[keep], ux=u[keep, 0], uy=u[keep, 1], vx=v[keep, 0], vy=v[keep, 1],
        fx=r.fx[keep], fy=r.fy[keep], normal_load=load[keep], z=r.z[keep], coefficient=r.coefficient[keep],
        z_peak=r.z_peak[keep], result=diffrax.RESULTS.successful,
    )


def _z_at_rest(motion) -> jnp.ndarray:
    """Z = 0 with one component along x, two in the plane."""
    return jnp.zeros(2 if isinstance(motion, AbstractBiaxialMotion) else 1)


def _normal_load_signal(normal_load, duration) -> Signal:
    """The normal load as a `Signal` over [0, duration]: a constant load is constant over the
    test; a recorded one must last as long as the test (`Signal` is zero past its end)."""
    if isinstance(normal_load, Signal):
        require_positive(normal_load.values, "normal_load", " [N] (compression positive)")
        normal_load.require_covers(duration, "normal_load")
        return normal_load
    value = jnp.asarray(normal_load, dtype=float)
    require_positive(value, "normal_load", " [N] (compression positive)")
    return as_signal(value, duration=duration)


def _riccati_admitted(h) -> bool:
    """False when concrete Bouc-Wen constants rule out the closed-form update."""
    try:
        require_riccati_form(h)
    except ValueError:
        return False
    return True


def _is_adaptive(solver) -> bool:
    try:
        return solver.error_order(None) is not None or isinstance(solver, diffrax.AbstractAdaptiveSolver)
    except Exception:
        return isinstance(solver, diffrax.AbstractAdaptiveSolver)


def save_times(motion, duration, samples_per_cycle):
    """Sample times [s] of a bearing test: a tabulated motion's own samples up to `duration`,
    else `samples_per_cycle` per cycle of the motion, evenly from 0 to `duration`."""
    import numpy as np

    if not duration > 0:
        raise ValueError(f"duration: must be > 0 s, got {duration}.")
    if hasattr(motion, "times"):
        times = np.asarray(motion.times)
        return jnp.asarray(times[times <= duration + 1e-12])
    period = _period(motion)
    n = max(int(round(duration / period * samples_per_cycle)), 2)
    return jnp.linspace(0.0, duration, n + 1)


def _period(motion) -> float:
    if hasattr(motion, "frequency"):
        return 1.0 / float(motion.frequency)
    return 2 * float(jnp.pi) / float(motion.angular_frequency)


def _refine(times, k):
    if k == 1:
        return times
    fractions = jnp.arange(k) / k
    inner = (times[:-1, None] + fractions[None, :] * jnp.diff(times)[:, None]).reshape(-1)
    return jnp.concatenate([inner, times[-1:]])


def _jumps(motion, duration):
    jumps = [t for t in motion.reversal_times() if 0 < t < duration]
    return jnp.asarray(jumps) if jumps else None


def _result(bearing, motion, normal_load: Signal, solution) -> BearingTestResult:
    t = solution.ts
    u = jax.vmap(motion.displacement)(t)
    v = jax.vmap(motion.velocity)(t)
    z = solution.ys["z"]
    if z.shape[-1] == 1:
        z = jnp.concatenate([z, jnp.zeros_like(z)], axis=-1)
    z_peak = solution.ys["z_peak"]
    mu = bearing.coefficient(v[:, 0], v[:, 1], z_peak)
    load = jax.vmap(normal_load)(t)
    return BearingTestResult(
        time=t,
        ux=u[:, 0],
        uy=u[:, 1],
        vx=v[:, 0],
        vy=v[:, 1],
        fx=mu * load * z[:, 0],
        fy=mu * load * z[:, 1],
        normal_load=load,
        z=z,
        coefficient=mu,
        z_peak=z_peak,
        result=solution.result,
    )


def force_along_path(
    bearing: SlidingBearing,
    time,
    ux,
    normal_load,
    *,
    z0=0.0,
    z_peak0=0.0,
    solver: diffrax.AbstractSolver | None = None,
    rtol: float = 1e-8,
    atol: float = 1e-10,
    max_steps: int = 1_000_000,
):
    """Friction force [N] of a bearing driven along sampled displacements along x.

    The bearing of `simulate_bearing_test`, with the velocity at each sample from the samples
    (`sample_velocity`, second-order central differences) and the running max |Z| switching
    Eq. 17 to Eq. 1; `time`, `ux` and `normal_load` may be traced (batches of records under
    `vmap`, fits under `optimistix`). `z0` and `z_peak0` set the initial state for records
    that do not start from rest.

    With eta = 2 and gamma > beta (the paper's shape) this is `respond_along_path`: Z exact
    between samples, with every optional part of the bearing (traced constants of another shape
    are a runtime error). Any other A, beta, gamma, eta (or an explicit `solver`, e.g.
    `diffrax.Tsit5()`) integrates Eq. 3 along the path with that diffrax solver, adaptive steps
    at `rtol`, `atol`, stopping at every sample (a bearing without optional parts only).

    **Arguments:** `bearing` (uniaxial), `time` [s] (n,), `ux` [m] (n,),
    `normal_load` [N] scalar or (n,).

    **Returns:** `(force [N], z [-], z_peak [-])`, each of shape (n,).
    """
    time, ux = jnp.asarray(time), jnp.asarray(ux)
    z0 = jnp.asarray(z0, dtype=ux.dtype)
    z_peak0 = jnp.asarray(z_peak0, dtype=ux.dtype)
    if solver is None and _riccati_admitted(bearing.hysteresis):
        path = sampled_path(time, ux, normal_load)
        response = sliding_along_path(bearing, path, z0=z0, z_peak0=z_peak0)
        return response.fx, response.z[:, 0], response.z_peak
    if bearing.effects:
        raise ValueError(
            f"bearing: its optional parts ({', '.join(bearing.effects)}) are driven along a path "
            "with the closed-form Z (eta = 2, gamma > beta, no solver given).")
    z, z_peak = _z_along_path(bearing, time, ux, z0, z_peak0, solver, rtol, atol, max_steps)
    mu = bearing.coefficient(sample_velocity(time, ux), 0.0, z_peak)
    return mu * normal_load * z, z, z_peak


def _z_along_path(bearing, time, ux, z0, z_peak0, solver, rtol, atol, max_steps):
    """Z and its running peak at the samples, integrating Eq. 3 with a diffrax solver."""
    solver = diffrax.Tsit5() if solver is None else solver
    motion = TabulatedMotion(times=time, ux=ux)
    system = BearingTestSystem(bearing=bearing, motion=motion)
    adaptive = _is_adaptive(solver)
    solution = diffrax.diffeqsolve(
        diffrax.ODETerm(system),
        solver,
        t0=time[0],
        t1=time[-1],
        dt0=(time[1] - time[0]) / 10 if adaptive else None,
        y0={"z": z0[None], "z_peak": z_peak0},
        saveat=diffrax.SaveAt(ts=time),
        stepsize_controller=(
            diffrax.PIDController(rtol=rtol, atol=atol, jump_ts=time)
            if adaptive
            else diffrax.StepTo(ts=time)
        ),
        max_steps=max_steps,
    )
    return solution.ys["z"][:, 0], solution.ys["z_peak"]
