"""The drivers of every stepped structure, a rigid mass, a building or a slab on flat sliders,
single, double or triple pendulums, under one or two ground components and a vertical record:
one history driver (`simulate_history`, every step's `StructureResponse`) and one peak driver
(`peak_response`, which folds the response's peak quantities, `REDUCERS` written once on one
sample of a `StructureResponse`, along the run, keeping running and smooth maxima and never
the history: the memory per run is that of its record). Each chooses the structure's step by
its type and its isolator's. A stepped engine gives its run as an `EngineRun` (start, inputs,
step, sample at rest): the peak driver folds its samples, and `run_history` keeps them, so a
history and its peaks are the same samples, each step with its `converged`. An adaptive
diffrax solver gives reference histories of flat sliders and single pendulums instead."""

import dataclasses

import jax
import jax.numpy as jnp

from ..solver import RiccatiNewmark, require_riccati_form, solve_on_grid
from ..structures import small_dot
from ..validation import given_options
from ._response import (
    REDUCERS,
    EngineRun,
    Peaks,
    ResponseLayout,
    StructureResponse,
    combined_load_extremes,
    every_kth,
    group_load_extremes,
    group_load_peaks,
    group_uplift_time,
    raise_unbalanced,
    run_history,
    uplift_time,
    uplifted,
)
from ._runs import (
    check_duration,
    check_storey_height,
    planar_run,
    records,
    solved_planar_response,
    solved_structure_response,
    time_grid,
)
from ._series import series_groups_run, series_run
from ._structure import WRITTEN_OUT_PRODUCT, StructureOnSliders, initial_state
from ._vertical import pressure_law_loads, within_pressure_law


def _on_series(system) -> bool:
    """Whether `system` is a structure on series pendulums: one or two components (stepped by
    `series_run`) or a slab on their groups (`series_groups_run`)."""
    return isinstance(system, StructureOnSliders) and system.pendulum is not None


STEPS_PER_LOOP_PASS = 2
"""`peak_response(steps_per_pass=...)` of the Monte Carlo runs (`monte_carlo`): two steps
written out in each pass of the peak loop (`lax.scan`'s `unroll`) halve the loop's fixed cost
per step, several per cent of the step for a batch of 250 motions per core; the rigid-mass and
building Monte Carlo needed 5 % and 4 % less CPU (same peaks), four no less than two. Not for
derivatives: forward-mode gradients through the unrolled loop took 8 times as long (B5)."""

RESPONSE_NAMES = ("base_disp", "base_shear_ratio")
"""The Monte Carlo peaks: |base displacement| [m] and |base shear| / weight above the
isolators [-], as resultants (`REDUCERS` "base_disp_resultant", "base_shear_ratio_resultant")."""

PEAK_REDUCERS = ("base_disp_resultant", "base_shear_ratio_resultant")
"""The peaks `peak_response` keeps unless told: the resultant base displacement and base shear
ratio (with a storey height also "storey_drift_ratio" and "level_acceleration")."""

SURFACE_REDUCERS = ("slider_travel", "surface_temperature_rise")
"""The peaks of the isolator's surfaces a Monte Carlo keeps where it has them: each slider's
travel and each surface's temperature rise."""


def response_layout(system) -> ResponseLayout:
    """The `ResponseLayout` of any structure `systems` builds: a `StructureOnSliders` along x
    (one component: coordinates base, floors), one on series pendulums with `ground_y` (x
    block then y block), and a planar one (`StructureOnSliders.planar`), which carries its
    own `mass` and `influence` (a rigid mass or
    building: x block then y block; a slab on any isolator's groups: x, y, rotation; the
    building on a plan, `building_on_plan`: x block, y block, the slab's rotation). Only shapes
    are read (static under jit)."""
    if isinstance(system, StructureOnSliders) and not system.planar:
        m = system.mass
        n = m.shape[-1]
        if system.components == 1:
            return ResponseLayout((tuple(range(n)),), m, jnp.ones((n, 1), m.dtype))
        blocks = jnp.repeat(jnp.eye(2, dtype=m.dtype), n, axis=0)  # series pendulums, x and y
        return ResponseLayout((tuple(range(n)), tuple(range(n, 2 * n))), jnp.concatenate([m, m]), blocks)
    if isinstance(system, StructureOnSliders):
        count = system.mass.shape[-1]
        n = count // 2  # levels: 1 for a rigid mass or a slab, the base and floors for a building
        levels = (tuple(range(n)), tuple(range(n, 2 * n)))
        if count % 2:  # a slab, alone (x, y, rotation) or under a building (x block, y block, rotation)
            return ResponseLayout(levels, system.mass, system.influence, rotation=2 * n,
                                  overturning=system.supports is not None)
        return ResponseLayout(levels, system.mass, system.influence)
    raise TypeError(f"system: no response layout for a {type(system).__name__}; give a structure built by "
                    "teflon_jax.systems (rigid mass, building or slab on its isolators).")


def smooth_max(x, width, axis=-1):
    """Smooth maximum of |x| along `axis`: the log-mean-cosh

        M_w(x) = w log( (1/n) sum_t cosh(x_t / w) ),

    with max|x| - w log(2 n) <= M_w(x) <= max|x| and M_w -> max|x| as w -> 0; smooth in x for
    w > 0 (its gradient is a softmax weighting of the samples near the peak). Along a run it is
    kept as a running (top, total) (`smooth_max_update`, `smooth_max_value`).

    **Arguments:** `x` (any shape); `width` w > 0 [units of x]; `axis`: time axis.

    **Returns:** M_w(x) with `axis` removed.
    """
    x = jnp.moveaxis(jnp.asarray(x), axis, 0)
    top = jax.lax.stop_gradient(jnp.max(jnp.abs(x), axis=0))
    total = jnp.sum(_cosh_terms(x, top, width), axis=0)
    return smooth_max_value(top, total, x.shape[0], width)


def _cosh_terms(x, top, width):
    """cosh(x / w) exp(-top / w) [-], written so that no term overflows for |x| <= top."""
    return 0.5 * (jnp.exp((x - top) / width) + jnp.exp((-x - top) / width))


def smooth_max_update(top, total, x, width):
    """The running (top, total) of `smooth_max` with the sample x added (start: (0, 1) for a
    run from rest, x = 0 at t = 0): top = max |x| so far (no gradient), total = sum_t
    cosh(x_t / w) exp(-top / w) [-]."""
    new_top = jnp.maximum(top, jax.lax.stop_gradient(jnp.abs(x)))
    return new_top, total * jnp.exp((top - new_top) / width) + _cosh_terms(x, new_top, width)


def smooth_max_value(top, total, count, width):
    """`smooth_max` M_w = top + w log(total / count) of `count` samples from their running
    (top, total) (`smooth_max_update`)."""
    return top + width * jnp.log(total / count)


def peak_response(system, duration: float, *, reducers=None, smooth=None, disp_width=None, shear_width=None,
                  read_every: int = 1, steps_per_pass: int = 1, storey_height=None) -> "Peaks":
    """Integrate `system` from rest over `duration` [s] with its engine's step and keep only
    the peaks of the `REDUCERS` named in `reducers`, folded step by step in a `lax.scan`.

    The engines are `simulate_history`'s (the same samples), each with its vertical record if
    it has one. jit/vmap/grad-safe.

    **Arguments:**

    - `duration` [s]: end time, rounded down to a multiple of `system.time_step`.
    - `reducers`: names of `REDUCERS` (default `PEAK_REDUCERS`, with `storey_height` also
      "storey_drift_ratio" and "level_acceleration"); those a structure lacks are left out.
    - `smooth`: {reducer name: width w} of the smooth maxima `smooth_max` kept along
      (log-mean-cosh over every step, t = 0 included); default the base displacement's
      (`disp_width` [m]) and the base shear ratio's (`shear_width` [-]), 1e-3 each.
    - `read_every`: the peaks are read every `read_every` steps (at a record's samples, as a
      program that records there reads them; the smooth maxima still see every step).
    - `steps_per_pass`: steps written out in each pass of the loop (the same results,
      `STEPS_PER_LOOP_PASS`; 1 where the run is differentiated).
    - `storey_height` [m]: a building's storey height (scalar or per storey) for the drift ratio.

    **Returns:** `Peaks` {name: peak} of each reducer ((C, ...) per component where the
    reducer is), {"smooth_" + name: M_w}, "converged": every step's balance converged, and with
    a vertical record "uplift_time" [s]: the steps 1..n whose end has N <= 0 times the step;
    where the groups share the weight unevenly (a slab or a building on a plan with its
    overturning loads), "group_normal_load": each group's largest and least N_g [N] (the rest
    included, read as the peaks are) and its uplift time [s] (`group_load_peaks`), and
    "tipped": whether the run's first unbalanced step tipped the slab (else Newton's balance
    missed its tolerance there); with a Table 1 pressure law that does not stop the run
    (`flag_pressure_law`),
    "within_pressure_law": whether the law gave Eq. 1 constants at every load the steps read
    (the record's at t = 0 included), up to the first step that did not balance (where a single
    run stops; the loads after it are never read).
    """
    _check_loop_settings(read_every, steps_per_pass)
    layout = response_layout(system)
    dtype = layout.mass.dtype
    if reducers is None:
        reducers = PEAK_REDUCERS + (() if storey_height is None else ("storey_drift_ratio", "level_acceleration"))
    if smooth is None:
        smooth = {"base_disp_resultant": 1e-3 if disp_width is None else disp_width,
                  "base_shear_ratio_resultant": 1e-3 if shear_width is None else shear_width}
        smooth = {name: width for name, width in smooth.items() if name in reducers}
    _check_reducers(reducers, smooth)
    if storey_height is not None:  # refused for a rigid mass, or unless > 0 (one or one per storey)
        check_storey_height(len(layout.levels[0]), storey_height)
    n_steps, run = _engine_run(system, duration)
    vertical = system.vertical_acceleration is not None
    table = getattr(system, "pressure_table", None)
    flagged = table is not None and not table.stop  # the runs beyond Table 1's law are reported
    widths = {name: jnp.asarray(width, dtype) for name, width in smooth.items()}
    tips = layout.overturning and run.first.tipped is not None  # a slab or building with overturning loads

    def quantities(sample):
        values = {name: REDUCERS[name](layout, sample, storey_height) for name in reducers}
        return {name: value for name, value in values.items() if value is not None}

    def body(carry, step_inputs):
        step, inputs = step_inputs
        state, peaks, tops, totals, lifted, ok, loads, law, tipped = carry
        state, sample, converged = run.step(state, inputs)
        if tips:  # whether the run's first unbalanced step is one on which the slab tipped
            tipped = tipped | (ok & sample.tipped)
        values = quantities(sample)
        read = (step + 1) % read_every == 0
        peaks = {k: jnp.where(read, jnp.maximum(p, values[k]), p) for k, p in peaks.items()}
        updated = {k: smooth_max_update(tops[k], totals[k], values[k], widths[k]) for k in tops}
        if vertical:
            lifted = lifted + uplifted(sample.load_factor)
        if loads is not None:  # the extremes read as the peaks are, uplift counted at every step
            new = combined_load_extremes(loads, group_load_extremes(layout, sample))
            loads = (jnp.where(read, new[0], loads[0]), jnp.where(read, new[1], loads[1]), new[2])
        return (state, peaks, {k: u[0] for k, u in updated.items()}, {k: u[1] for k, u in updated.items()},
                lifted, ok & converged, loads, law if law is None else _law_extremes(system, layout, law, sample, ok),
                tipped), None

    shapes = jax.eval_shape(lambda: quantities(run.step(run.start, jax.tree_util.tree_map(lambda a: a[0],
                                                                                          run.inputs))[1]))
    peaks = {k: jnp.zeros(s.shape, s.dtype) for k, s in shapes.items()}
    tops = {k: jnp.zeros(shapes[k].shape, dtype) for k in widths if k in shapes}
    totals = {k: jnp.ones(shapes[k].shape, dtype) for k in tops}
    loads = None if run.first is None else group_load_extremes(layout, run.first)  # the rest's, none lifted
    loads = None if loads is None else loads[:2] + (jnp.zeros_like(loads[2]),)
    law = _law_start(system, layout, run.first) if flagged else None
    carry = (run.start, peaks, tops, totals, jnp.zeros((), jnp.int32), jnp.array(True), loads, law, jnp.array(False))
    (_, peaks, tops, totals, lifted, ok, loads, law, tipped), _ = jax.lax.scan(
        body, carry, (jnp.arange(n_steps), run.inputs), unroll=steps_per_pass)
    out = Peaks(peaks, layout.components)
    out.update({"smooth_" + k: smooth_max_value(tops[k], totals[k], n_steps + 1, widths[k]) for k in tops})
    out["converged"] = ok
    if vertical:
        out["uplift_time"] = lifted * float(system.time_step)
    if loads is not None:
        out["group_normal_load"] = group_load_peaks(loads, loads[2] * float(system.time_step))
    if tips:
        out["tipped"] = tipped
    if flagged:
        out["within_pressure_law"] = within_pressure_law(system, law)
    return out


def _law_extremes(system, layout, law, sample, reached):
    """Table 1's law's extremes `law` (largest, least positive load factor) with the loads of
    `sample` where the run `reached` it (every earlier step balanced, so this step read them)
    and they are finite, as the history's check reads them (`pressure_law_valid`)."""
    high, low = pressure_law_loads(system, layout, sample)
    read = reached & jnp.all(jnp.isfinite(high))
    return jnp.where(read, jnp.maximum(law[0], high), law[0]), jnp.where(read, jnp.minimum(law[1], low), law[1])


def _law_start(system, layout, first):
    """(largest, least positive) load factor of a run's start: s = 1 at rest (one per group
    under overturning) with the load its first step reads as its start's, the record's at
    t = 0 (a record need not start at a_v = 0) or the groups' first sample's
    (`pressure_law_loads`)."""
    at_rest = jnp.ones(system.bearing_load.shape if layout.overturning else (), layout.mass.dtype)
    if layout.overturning and first is not None and first.normal_load is not None:
        high, low = pressure_law_loads(system, layout, first)
    elif system.vertical_acceleration is not None:
        high = system.load_factor(jnp.zeros((), layout.mass.dtype))
        low = jnp.where(high > 0, high, jnp.inf)
    else:
        return at_rest, at_rest
    return jnp.maximum(at_rest, high), jnp.minimum(at_rest, low)


def _check_reducers(reducers, smooth) -> None:
    unknown = [name for name in reducers if name not in REDUCERS]
    if unknown:
        raise ValueError(f"reducers: unknown {', '.join(map(repr, unknown))}; accepted: {', '.join(REDUCERS)}.")
    unread = [name for name in smooth if name not in reducers]
    if unread:
        raise ValueError(f"smooth: {', '.join(map(repr, unread))} not among the reducers kept ({', '.join(reducers)}).")


def _check_loop_settings(read_every, steps_per_pass) -> None:
    if isinstance(read_every, bool) or not isinstance(read_every, int) or read_every < 1:
        raise ValueError(f"read_every: must be a positive integer number of steps, got {read_every!r}.")
    if isinstance(steps_per_pass, bool) or not isinstance(steps_per_pass, int) or steps_per_pass < 1:
        raise ValueError(f"steps_per_pass: must be a positive integer, got {steps_per_pass!r}.")


def _engine_run(system, duration):
    """(n_steps, `EngineRun`) of `system`'s engine over `duration` [s] (checked): its step
    chosen by the isolator (series pendulums balance their sliders) and by the structure (one
    isolator in one component: the scalar Newton; bearing groups: the planar step)."""
    if not isinstance(system, StructureOnSliders):
        raise TypeError(f"system: no peak driver for a {type(system).__name__}; give a structure built by "
                        "teflon_jax.systems (rigid mass, building or slab on its isolators).")
    n_steps = check_duration(system, duration)
    one = not system.planar
    if _on_series(system):
        return n_steps, (series_run if one else series_groups_run)(system, n_steps)
    return n_steps, (_uniaxial_run if one else planar_run)(system, n_steps)


def _sample(time, x, total_acceleration, ground, load, **parts):
    """One sample of a `StructureResponse` from the state x = (u, v) (2N,)."""
    count = x.shape[-1] // 2
    return StructureResponse(time=time, displacement=x[:count], velocity=x[count:],
                             total_acceleration=total_acceleration, ground=ground, load_factor=load, **parts)


def _total_acceleration(system, x, force):
    """a^total = -(K u + C v + F e_0) / m (n,) [m/s^2] of a structure on one isolator (DOF 0)
    whose force beyond K u is F [N]: the equation of motion with the ground's inertia moved
    to the left, M (a + 1 a_g) + C v + K u + F e_0 = 0."""
    n = system.mass.shape[-1]
    inner = small_dot(system.stiffness, x[:n], WRITTEN_OUT_PRODUCT) + small_dot(system.damping, x[n:],
                                                                                WRITTEN_OUT_PRODUCT)
    return -inner.at[0].add(force) / system.mass


def _uniaxial_run(system, n_steps) -> EngineRun:
    """A `StructureOnSliders` on flat sliders or single pendulums stepped by its step matrices
    (one product per step) with the record at every step's end evaluated outside the loop."""
    dt = float(system.time_step)
    times = jnp.arange(n_steps + 1) * dt
    ground = jax.vmap(system.ground_acceleration)(times)
    loads = None if system.vertical_acceleration is None else jax.vmap(system.load_factor)(times)
    matrices = system.step_matrices()

    def step(state, inputs):
        time1, ground1, load1 = inputs
        state, x1, converged, force, part = _sliders_advance(system, matrices, state, ground1, load1)
        sample = _sample(time1, x1, _total_acceleration(system, x1, force), ground1[None], load1, **part)
        return state, sample, converged

    start = _uniaxial_start(system, ground[0], None if loads is None else loads[0])
    x0, z0, z_peak0, factors0, _, _, load0 = start
    friction0 = factors0[0] * z0 * system.asymmetry_factor(z0)
    force0 = friction0
    if system.surface is not None or load0 is not None:
        force0 = force0 + system.surface_force(x0[0], load0)
    first = _sample(times[0], x0, _total_acceleration(system, x0, force0), ground[:1], load0,
                    friction_force=friction0, z=z0, z_peak=z_peak0, **_temperature_rise(system, start[5]))
    return EngineRun(start, (times[1:], ground[1:], None if loads is None else loads[1:]), step, first)


def _sliders_advance(system, matrices, state, ground1, load1):
    """One step of flat sliders or single pendulums (`StructureOnSliders.history_step`):
    (state, x1, converged, bearing force F = mu W Z plus the pendulum's force beyond K u [N],
    the sample's friction force mu W Z).

    The state (u, v), the bearing force per unit Z and its slope of the stored state
    (`friction_factors`) and the ground acceleration at the start of the step; a bearing with
    history (heating, wear) steps with its friction at the start of the step (`at_history`)
    and carries its heat states and travel; with a vertical record the load factor N / W."""
    n = system.mass.shape[-1]
    x, z, z_peak, start_factors, ground0, history, load0 = state
    x1, z1, z_peak1, converged, history = system.history_step(x, z, z_peak, start_factors, ground0, ground1,
                                                              history, load0, load1, matrices)
    stepped = system.at_history(*history) if history else system  # the step's end, as the next starts from it
    factors1 = stepped.friction_factors(x1[n], z_peak1, load1)  # of the stored state: F = mu W Z
    friction = factors1[0] * z1 * system.asymmetry_factor(z1)
    force = friction
    if system.surface is not None or load1 is not None:  # the pendulum's force beyond W u / R
        force = force + system.surface_force(x1[0], load1)
    return ((x1, z1, z_peak1, factors1, ground1, history, load1), x1, converged, force,
            {"friction_force": friction, "z": z1, "z_peak": z_peak1, **_temperature_rise(system, history)})


def _temperature_rise(system, history) -> dict:
    """{"surface_temperature_rise": (1, 1) [K]} of a heated bearing (one group, one surface) at
    the history (heat states, travel); {} without heating."""
    if system.bearing.heating is None:
        return {}
    return {"surface_temperature_rise": system.bearing.surface_temperature_rise(history[0], system.heat_weights)[None, None]}


def _uniaxial_start(system, ground0, load0):
    """The state at rest of `_uniaxial_run`."""
    y0 = initial_state(system)
    start_factors = system.friction_factors(y0["v"][0], y0["z_peak"], load0)
    history = (y0["heat"], y0["travel"]) if system.history else ()
    return (jnp.concatenate([y0["u"], y0["v"]]), y0["z"], y0["z_peak"], start_factors, ground0, history, load0)


def simulate_history(
    system,
    duration: float,
    *,
    save_every: int = 1,
    solver=None,
    rtol: float = 1e-8,
    atol: float = 1e-10,
    max_steps: int | None = None,
    adjoint=None,
    throw: bool = True,
) -> StructureResponse:
    """Integrate any structure `systems` builds from rest over `duration` [s] and return its
    `StructureResponse`.

    By default every structure is stepped by its own engine at its `time_step` (the
    `EngineRun` whose samples the peak driver folds: a history and its peaks are the same
    samples), each step's balance judged: the response's `converged` says which steps balanced
    and `tipped` (a slab or building on bearing groups with overturning loads) on which the
    slab could not rest on its groups; with `throw` a step that did not balance raises. An
    adaptive diffrax `solver` gives converged reference solutions of flat sliders and single
    pendulums instead (one or two components; no overturning loads, no series pendulums):

    - `duration` [s]: rounded down to a whole number of `system.time_step`s (as in
      `peak_response`); the records must last that long (`ValueError` naming the one that
      does not);
    - `save_every`: keep every k-th step (t = 0 included); a kept step's `converged` is whether
      every step since the previous kept one converged (the last also covers any steps after
      it), and the uplift times count every step;
    - `solver`: `None` or `RiccatiNewmark()`: the fixed steps (Bouc-Wen with eta = 2 and
      gamma > beta on the flat sliders of one component); an adaptive diffrax solver (e.g.
      `diffrax.Tsit5()`) with `rtol`, `atol`, `max_steps` and `adjoint` (default
      `RecursiveCheckpointAdjoint()`; `diffrax.ForwardMode()` for `jax.jvp`/`jax.jacfwd`),
      which are refused by name with the fixed steps (a `lax.scan`, differentiated directly:
      forward mode always, reverse mode in one component); the solve's outcome is then the
      response's `result`;
    - `throw`: raise on an unbalanced step or solver failure; with `False` (e.g. under `vmap`)
      the outcome is in the response (`succeeded`).
    """
    if not isinstance(system, StructureOnSliders):
        raise TypeError(f"system: no history driver for a {type(system).__name__}; give a structure built by "
                        "teflon_jax.systems (rigid mass, building or slab on its isolators).")
    if isinstance(save_every, bool) or not isinstance(save_every, int) or save_every < 1:
        raise ValueError(f"save_every: must be a positive integer number of steps, got {save_every!r}.")
    if solver is None or isinstance(solver, RiccatiNewmark):
        given = given_options({"rtol": (rtol, 1e-8), "atol": (atol, 1e-10), "max_steps": (max_steps, None),
                               "adjoint": (adjoint, None)})
        if given:
            raise ValueError(f"{', '.join(given)}: the fixed steps take no tolerances, step limit or adjoint "
                             "(they are a lax.scan, differentiated directly); drop these options, or give "
                             "an adaptive diffrax solver.")
        _check_solver(system, RiccatiNewmark())
        return _stepped_history(system, duration, save_every, throw)
    if _on_series(system):
        raise ValueError("solver: a structure on series pendulums steps only at its time_step; leave solver out.")
    _check_solver(system, solver)
    planar = system.planar
    n_steps, steps, save_times = time_grid(system.time_step, duration, save_every, records(system))
    if planar:
        y0, jumps = initial_state(system), jnp.concatenate([system.ground_acceleration.times,
                                                            system.ground_y.times])
    else:
        y0, jumps = initial_state(system), system.ground_acceleration.times
    solution = solve_on_grid(system, solver, steps, save_times, y0, jump_times=jumps, rtol=rtol, atol=atol,
                             max_steps=max_steps, adjoint=adjoint, throw=throw,
                             adaptive_steps_per_step=200 if planar else 100)
    if planar:
        return solved_planar_response(system, save_times, solution, n_steps)
    return solved_structure_response(system, save_times, solution, n_steps)


def _stepped_history(system, duration, save_every, throw) -> StructureResponse:
    """`simulate_history` by the structure's engine: every step's sample (`run_history`), the
    uplift times over every step, then every `save_every`-th sample kept (`every_kth`)."""
    _, run = _engine_run(system, duration)
    response = run_history(run)
    dt = float(system.time_step)
    changes = {}
    if response.normal_load is not None:  # a slab or building on groups: the steps each group is lifted
        changes["group_uplift_time"] = group_uplift_time(response.normal_load, dt)
    if response.load_factor is not None:  # a vertical record: N / W at every step's end
        changes["uplift_time"] = uplift_time(response.load_factor, dt)
    response = every_kth(dataclasses.replace(response, **changes), save_every)
    return raise_unbalanced(response) if throw else response


def _check_solver(system, solver) -> None:
    """`ValueError` naming `solver` where the structure's step needs `RiccatiNewmark`: the
    slab's overturning loads (held over its fixed steps) and a hysteresis outside its form."""
    fixed = isinstance(solver, RiccatiNewmark)
    if isinstance(system, StructureOnSliders) and system.overturning is not None and not fixed:
        raise ValueError("solver: the overturning loads are held over the fixed steps of "
                         "RiccatiNewmark; leave solver out (or give height 0).")
    if isinstance(system, StructureOnSliders) and not system.planar and fixed and system.friction_model == "hysteretic":
        require_riccati_form(system.bearing.hysteresis)
