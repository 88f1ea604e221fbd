"""The imposed-path test of any isolator (`imposed_path_test`): its force along a motion or
along the samples of a record, by the strategy its static structure picks (`path_strategy`):
the structures' balance of a series pendulum's sliders, a sliding bearing's Z exact between
samples (`_imposed_path`), or Eq. 3 integrated by diffrax (`BearingTestSystem`).

Reference: Constantinou, Mokha & Reinhorn (1990), tests No. 62, 75, 191 and Figs. 3-6.
"""

import inspect

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
    SampledPath,
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
                "diffrax solver (the default of imposed_path_test)."
            )
        h = require_riccati_form(self.bearing.hysteresis)
        du = self.motion.displacement(t1)[0] - self.motion.displacement(t0)[0]
        z1 = bouc_wen_exact_update(h, y0["z"], du)
        z_peak1 = jnp.maximum(y0["z_peak"], jnp.abs(z1[0]))
        return {"z": z1, "z_peak": z_peak1}, jnp.array(True)


PATH_STRATEGIES = ("balanced", "sampled", "integrated")
"""How `imposed_path_test` drives an isolator (`path_strategy`): "balanced", the sliders of a
`SeriesPendulum` balanced at each sample by the structures' step (`series_along_path`);
"sampled", a `SlidingBearing` with Z exact between samples (`sliding_along_path`); "integrated",
a `SlidingBearing` whose Eq. 3 a diffrax solver integrates along the path (`BearingTestSystem`)."""

MOTION_OPTIONS = ("normal_load", "duration", "samples_per_cycle", "steps_per_sample")
SOLVE_OPTIONS = ("solver", "rtol", "atol", "max_steps", "adjoint", "throw")
STATE_OPTIONS = ("z0", "z_peak0")
SERIES_OPTIONS = ("heat_kernel", "friction_velocity", "reference_load")
"""The options of `imposed_path_test` by what they shape: the samples of a motion, a diffrax
solve, a sliding bearing's state at the first sample, a series pendulum's test. Their defaults
are the signature's (`_DEFAULTS`)."""


def path_strategy(isolator, path, solver=None) -> str:
    """The `PATH_STRATEGIES` entry that drives `isolator` along `path` (an `AbstractMotion` or a
    `SampledPath`), from static structure only: a `SeriesPendulum` is "balanced"; a
    `SlidingBearing` with optional parts, or with the paper's Bouc-Wen shape (eta = 2,
    gamma > beta) and no solver (or `RiccatiNewmark` along x), is "sampled", except along a
    motion in the plane, which a diffrax solver integrates ("integrated", as any other shape or
    a given diffrax solver)."""
    if isinstance(isolator, SeriesPendulum):
        return "balanced"
    if isolator.effects:
        return "sampled"
    closed_form = _riccati_admitted(isolator.hysteresis)
    if isinstance(path, SampledPath):
        along_x = not path.planar
        return "sampled" if closed_form and (solver is None or along_x and isinstance(solver, RiccatiNewmark)) \
            else "integrated"
    along_x = closed_form and not isinstance(path, AbstractBiaxialMotion)
    return "sampled" if along_x and (solver is None or isinstance(solver, RiccatiNewmark)) else "integrated"


def imposed_path_test(
    isolator: SlidingBearing | SeriesPendulum,
    path: AbstractMotion | SampledPath,
    normal_load=None,
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
    z0=None,
    z_peak0=None,
    heat_kernel=None,
    friction_velocity: str | None = None,
    reference_load=None,
) -> BearingTestResult:
    """The imposed-path test of any isolator: its force along a path, the one test that a user,
    the fitters, the posterior and `diagnose` run, with the slider forces the structures run.

    **Arguments:**

    - `isolator`: a `SlidingBearing` (flat sliders; vmap over a batched one to run many) or a
      `SeriesPendulum` (single, double, triple friction pendulum).
    - `path`: an `AbstractMotion` (sine, triangle, figure eight, `tabulated_motion`), sampled
      at `save_times` (`duration` [s], default `motion.duration`; `samples_per_cycle`; a
      tabulated motion at its own samples) under `normal_load` [N] (a constant or a `Signal`
      covering `duration`), or a `SampledPath` (`sampled_path`: the samples of a record, with
      their normal load; the motion's options are then refused by name).

    The isolator's static structure picks the strategy (`path_strategy`, `PATH_STRATEGIES`):

    - "balanced" (a `SeriesPendulum`): its sliders balanced at each sample by the structures'
      step from rest (`series_along_path`); `heat_kernel` (rates, weights) of heated surfaces,
      `friction_velocity` ("mean", the default, or for one surface "end") and
      `reference_load` [N], the load its surfaces' contact pressures are given under.
    - "sampled" (a `SlidingBearing` with optional parts, or with the paper's shape eta = 2,
      gamma > beta, and no solver or `RiccatiNewmark` along x): F = mu(v) k N Z at the path's
      velocity at each sample, Z exact between samples along x, Park's along the Hermite path
      in the plane (`sliding_along_path`); a motion's samples are refined `steps_per_sample`
      times and its own velocity taken.
    - "integrated" (a `SlidingBearing` of another shape, or along a motion in the plane, or
      with a diffrax `solver`, by default `Tsit5` with a PID controller at `rtol`, `atol`):
      Eq. 3 integrated along the motion (a `SampledPath` along x: its samples, linearly
      between them, mu at their `sample_velocity`); `max_steps`, `adjoint`
      (default reverse mode; `diffrax.ForwardMode()` for `jax.jvp`) and `throw` as in
      `diffrax.diffeqsolve`.

    `z0` (Z at the first sample, (2,) in the plane) and `z_peak0` (the running max |Z| before
    it; 1: no breakaway) set a sliding bearing's start (default rest). Options the chosen
    strategy does not take are refused by name (`ValueError`).

    **Returns:** a `BearingTestResult` at the samples (of a series pendulum: each slider's
    displacement and Z, and whether each sample's balance converged).
    """
    arguments = locals()
    options = {name: arguments[name] for name in _DEFAULTS}
    if not isinstance(path, AbstractMotion | SampledPath):
        raise ValueError(f"path: give an imposed motion (an `AbstractMotion`: SineMotion, tabulated_motion, ...) "
                         f"or the samples of a record (`sampled_path`), got {type(path).__name__}.")
    strategy = path_strategy(isolator, path, solver)
    _refuse_options(isolator, path, strategy, options)
    return _STRATEGIES[strategy](isolator, path, options)


_DEFAULTS = {name: parameter.default for name, parameter in inspect.signature(imposed_path_test).parameters.items()
             if parameter.default is not inspect.Parameter.empty}
"""Every option of `imposed_path_test` with its default, read off its signature."""


def _given(options, names) -> list[str]:
    """The options `names` given in `options` other than at their defaults (`given_options`)."""
    return given_options({name: (options[name], _DEFAULTS[name]) for name in names})


def _refuse_options(isolator, path, strategy, options) -> None:
    """`ValueError` naming the options of `imposed_path_test` that `strategy` along `path` does
    not take, or a motion without its normal load."""
    if isinstance(path, SampledPath):
        given = _given(options, MOTION_OPTIONS)
        if given:
            raise ValueError(f"{', '.join(given)}: a SampledPath carries its samples and their normal load "
                             "(`sampled_path`); drop these options, which sample a motion.")
    elif options["normal_load"] is None:
        raise ValueError("normal_load: a test along a motion needs the normal load [N] (a constant or a Signal).")
    if strategy == "balanced":
        _refuse_on_series(isolator, path, options)
        return
    if options["reference_load"] is not None:
        raise ValueError("reference_load: a sliding bearing's test reads the path's normal load itself "
                         "(its pressure dependence and heat flux); drop this option.")
    if options["heat_kernel"] is not None:
        raise ValueError("heat_kernel: a sliding bearing's test takes the path's own kernel "
                         "(`sampled_path`); drop this option.")
    if options["friction_velocity"] not in (None, "end"):
        raise ValueError(f"friction_velocity: a sliding bearing's test takes Eq. 1 at the path's velocity at "
                         f"each sample ('end'), got {options['friction_velocity']!r}.")
    if strategy == "sampled":
        _refuse_solve_options(isolator, path, {name: (options[name], _DEFAULTS[name])
                                               for name in SOLVE_OPTIONS if name != "throw"})
    elif isinstance(path, SampledPath) and path.planar:
        raise ValueError("path: a sliding bearing along a SampledPath in the plane is driven by Park's update, "
                         "with the paper's Bouc-Wen shape (eta = 2, gamma > beta) and no solver; give the path "
                         "as a motion (`tabulated_motion`) for a diffrax solve.")


def _refuse_on_series(isolator, path, options) -> None:
    """`ValueError` naming what a series pendulum's test does not take."""
    given = _given(options, ("steps_per_sample", *SOLVE_OPTIONS))
    if given:
        raise ValueError(f"{', '.join(given)}: the {isolator.description} balance their sliders at each "
                         "sample (the structures' solve); drop these options.")
    given = _given(options, STATE_OPTIONS)
    if given:
        raise ValueError(f"{', '.join(given)}: the {isolator.description} start from rest at the path's "
                         "first sample; drop these options.")
    if isinstance(path, SampledPath) and path.temperature_rise is not None:
        raise ValueError(f"path.temperature_rise: the {isolator.description} heat by their own flux; "
                         "build the path without a measured temperature rise.")


def _refuse_solve_options(bearing, path, options) -> None:
    """`ValueError` naming the options of the diffrax solve given for a bearing that is driven
    along the samples instead ("sampled": one with optional parts, or along x with the paper's
    shape): they would change nothing. `RiccatiNewmark` along x names that exact update and is
    taken."""
    solver = options["solver"][0]
    planar = path.planar if isinstance(path, SampledPath) else isinstance(path, AbstractBiaxialMotion)
    if isinstance(solver, RiccatiNewmark) and not planar:
        options = {**options, "solver": (None, None)}
    given = given_options(options)
    if given:
        which = (f"a bearing with {', '.join(bearing.effects)}" if bearing.effects else
                 "a bearing along x with the paper's Bouc-Wen shape (eta = 2, gamma > beta)")
        raise ValueError(f"{', '.join(given)}: {which} is driven along the sampled motion, Z exact between "
                         "samples (imposed_path_test), not by a diffrax solve; drop these options "
                         "(steps_per_sample refines a motion's samples)" + ("" if bearing.effects else
                                                                            ", or give a diffrax solver") + ".")


def _motion_samples(motion, options, check):
    """(duration [s], normal load `Signal`, save times) of a test along `motion`, after `check`
    of the isolator and the motion's own check."""
    check()
    motion.check()
    duration = motion.duration if options["duration"] is None else options["duration"]
    signal = _normal_load_signal(options["normal_load"], duration)
    return duration, signal, save_times(motion, duration, options["samples_per_cycle"])


def _balanced(isolator, path, options) -> BearingTestResult:
    """The "balanced" strategy: `series_along_path` along the path (a motion at its save times)."""
    if isinstance(path, AbstractMotion):
        _, signal, time = _motion_samples(path, options, lambda: check_series_pendulum(isolator))
        u = jax.vmap(path.displacement)(time)
        given = options["normal_load"]
        load = jax.vmap(signal)(time) if isinstance(given, Signal) else given
        planar = isinstance(path, AbstractBiaxialMotion)
        path = sampled_path(time, u[:, 0], load, uy=u[:, 1] if planar else None, park_elements=1)
    velocity = options["friction_velocity"]
    return series_along_path(isolator, path, heat_kernel=options["heat_kernel"],
                             friction_velocity="mean" if velocity is None else velocity,
                             reference_load=options["reference_load"])


def _sampled(isolator, path, options) -> BearingTestResult:
    """The "sampled" strategy: `sliding_along_path` along the path (a motion at its refined save
    times, with its own velocity)."""
    z0, z_peak0 = options["z0"], 0.0 if options["z_peak0"] is None else options["z_peak0"]
    if isinstance(path, SampledPath):
        return sliding_along_path(isolator, path, z0=z0, z_peak0=z_peak0)
    _, signal, times = _motion_samples(path, options, lambda: check_bearing(isolator))
    k = options["steps_per_sample"]
    return _along_samples(isolator, path, signal, _refine(times, k), k, z0, z_peak0)


def _integrated(isolator, path, options) -> BearingTestResult:
    """The "integrated" strategy: Eq. 3 by a diffrax solver along the motion, or along a
    `SampledPath`'s samples (`_z_along_path`)."""
    solver = diffrax.Tsit5() if options["solver"] is None else options["solver"]
    adjoint = diffrax.RecursiveCheckpointAdjoint() if options["adjoint"] is None else options["adjoint"]
    if isinstance(solver, RiccatiNewmark):
        require_riccati_form(isolator.hysteresis)
    if isinstance(path, SampledPath):
        return _integrated_samples(isolator, path, solver, adjoint, options)
    duration, signal, times = _motion_samples(path, options, lambda: check_bearing(isolator))
    refined = _refine(times, options["steps_per_sample"])
    if _is_adaptive(solver) and not isinstance(solver, RiccatiNewmark):
        controller = diffrax.PIDController(rtol=options["rtol"], atol=options["atol"], jump_ts=_jumps(path, duration))
        dt0 = float(times[1] - times[0]) / 10
    else:
        controller, dt0 = diffrax.StepTo(ts=refined), None
    z = _z_at_rest(path)
    y0 = {"z": z if options["z0"] is None else jnp.broadcast_to(jnp.asarray(options["z0"], z.dtype), z.shape),
          "z_peak": jnp.asarray(0.0 if options["z_peak0"] is None else options["z_peak0"], z.dtype)}
    system = BearingTestSystem(bearing=isolator, motion=path)
    return _solve(system, solver, controller, dt0, times, signal, y0, options["max_steps"], adjoint,
                  options["throw"])


def _integrated_samples(isolator, path, solver, adjoint, options) -> BearingTestResult:
    """Eq. 3 integrated along the samples of a `SampledPath` along x, mu at their velocity."""
    dtype = path.ux.dtype
    z0 = jnp.asarray(0.0 if options["z0"] is None else options["z0"], dtype)
    z_peak0 = jnp.asarray(0.0 if options["z_peak0"] is None else options["z_peak0"], dtype)
    z, z_peak, result = _z_along_path(isolator, path.time, path.ux, z0, z_peak0, solver, options, adjoint)
    mu = isolator.coefficient(path.velocity_x, 0.0, z_peak)
    force = mu * path.normal_load * z
    return BearingTestResult(time=path.time, fx=force, fy=jnp.zeros_like(force),
                             z=jnp.stack([z, jnp.zeros_like(z)], axis=-1), normal_load=path.normal_load,
                             ux=path.ux, vx=path.velocity_x, coefficient=mu, z_peak=z_peak, result=result)


_STRATEGIES = {"balanced": _balanced, "sampled": _sampled, "integrated": _integrated}


@eqx.filter_jit
def _solve(system, solver, controller, dt0, times, normal_load, y0, max_steps, adjoint, throw):
    solution = solve_with_controller(system, solver, controller, t0=times[0], t1=times[-1], dt0=dt0, y0=y0,
                                     save_times=times, max_steps=max_steps, adjoint=adjoint, throw=throw)
    return _result(system.bearing, system.motion, normal_load, solution)


def _along_samples(bearing, motion, normal_load, times, steps_per_sample, z0=None, z_peak0=0.0):
    u = jax.vmap(motion.displacement)(times)
    v = jax.vmap(motion.velocity)(times)
    load = jax.vmap(normal_load)(times)
    if isinstance(motion, AbstractBiaxialMotion):
        path = sampled_path(times, u[:, 0], load, uy=u[:, 1], velocity=v[:, 0],
                            velocity_y=v[:, 1])
    else:
        path = sampled_path(times, u[:, 0], load, velocity=v[:, 0])
    r = sliding_along_path(bearing, path, z0=z0, z_peak0=z_peak0)
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


def _z_along_path(bearing, time, ux, z0, z_peak0, solver, options, adjoint):
    """Z, its running peak at the samples and the solve's result, integrating Eq. 3 with a
    diffrax solver along the samples (linear between them)."""
    system = BearingTestSystem(bearing=bearing, motion=TabulatedMotion(times=time, ux=ux))
    adaptive = _is_adaptive(solver)
    controller = (diffrax.PIDController(rtol=options["rtol"], atol=options["atol"], jump_ts=time) if adaptive
                  else diffrax.StepTo(ts=time))
    solution = diffrax.diffeqsolve(
        diffrax.ODETerm(system), solver, t0=time[0], t1=time[-1], dt0=(time[1] - time[0]) / 10 if adaptive else None,
        y0={"z": z0[None], "z_peak": z_peak0}, saveat=diffrax.SaveAt(ts=time), stepsize_controller=controller,
        max_steps=options["max_steps"], adjoint=adjoint, throw=options["throw"])
    return solution.ys["z"][:, 0], solution.ys["z_peak"], solution.result
