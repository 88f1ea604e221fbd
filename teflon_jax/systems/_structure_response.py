"""Response histories of a `StructureOnSliders`: `simulate_structure` and its `StructureResponse`."""

import equinox as eqx
import jax
import jax.numpy as jnp

from ..solver import require_riccati_form
from ._structure import StructureOnSliders, initial_state
from ._vertical import uplift_steps


class StructureResponse(eqx.Module):
    """Response histories of a `StructureOnSliders` (SI; time along the first axis).

    - `time` [s]; `displacement`, `velocity` (nt, n) relative to the ground [m, m/s];
    - `total_acceleration` (nt, n) [m/s^2] (relative + ground);
    - `friction_force` (nt,) [N] on the isolator; `z`, `z_peak` (nt,) [-];
    - `ground_acceleration` (nt,) [m/s^2]; `result`: `diffrax.RESULTS` (0 = successful).
    - `load_factor` (nt,) [-]: N / W on the isolators, 0 while uplifted (with a vertical
      record, else `None`); `uplift_time` [s]: time steps with N <= 0 times the step.
    """

    time: jnp.ndarray
    displacement: jnp.ndarray
    velocity: jnp.ndarray
    total_acceleration: jnp.ndarray
    friction_force: jnp.ndarray
    z: jnp.ndarray
    z_peak: jnp.ndarray
    ground_acceleration: jnp.ndarray
    result: object
    load_factor: jnp.ndarray | None = None
    uplift_time: jnp.ndarray | None = None

    @property
    def succeeded(self):
        import diffrax

        return self.result == diffrax.RESULTS.successful


def check_duration(system: StructureOnSliders, duration: float) -> int:
    """Number of `time_step`s in `duration` [s] (rounded down), after checking that it is at
    least one step and that the ground-acceleration record lasts that long (a `Signal` is zero
    past its last sample; ask for a shorter duration or append zeros on purpose)."""
    dt = float(system.time_step)
    n_steps = int(round(duration / dt + 1e-9))
    if n_steps < 1:
        raise ValueError(f"duration: must be at least one time step ({dt} s), got {duration}.")
    system.ground_acceleration.require_covers(n_steps * dt, "duration")
    if system.vertical_acceleration is not None:
        system.vertical_acceleration.require_covers(n_steps * dt, "duration (vertical record)")
    return n_steps


def simulate_structure(
    system: StructureOnSliders,
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
    """Integrate a structure on sliders from rest over `duration` [s].

    **Arguments:**

    - `system`: from `structure_on_sliders` or the model builders (rigid mass, building).
    - `duration` [s]: end time; a multiple of `system.time_step` is used (rounded down). It
      may not exceed the ground-acceleration record (see `check_duration`).
    - `save_every`: keep every k-th step.
    - `solver`: `RiccatiNewmark()` (default; fixed step `system.time_step`; Bouc-Wen with
      eta = 2 and gamma > beta only) or an adaptive diffrax solver (e.g. `diffrax.Tsit5()` with
      `rtol`, `atol`), for converged reference solutions and for any other Bouc-Wen shape.
    - `adjoint`: a diffrax adjoint; default `RecursiveCheckpointAdjoint()` (reverse mode);
      pass `diffrax.ForwardMode()` for `jax.jvp`/`jax.jacfwd` (cheaper with few parameters).
    - `throw`: raise on solver failure; with `False` (e.g. under vmap) the code is in `result`.

    **Returns:** a `StructureResponse` sampled every `save_every` steps.
    """

    from ..solver import RiccatiNewmark, solve_on_grid

    n_steps = check_duration(system, duration)
    dt = float(system.time_step)
    steps = jnp.arange(n_steps + 1) * dt
    save_times = steps[::save_every]
    solver = RiccatiNewmark() if solver is None else solver
    if isinstance(solver, RiccatiNewmark) and system.friction_model == "hysteretic":
        require_riccati_form(system.bearing.hysteresis)
    solution = solve_on_grid(
        system, solver, steps, save_times, initial_state(system),
        jump_times=system.ground_acceleration.times, rtol=rtol, atol=atol, max_steps=max_steps,
        adjoint=adjoint, throw=throw,
    )
    ys = solution.ys
    ag = jax.vmap(system.ground_acceleration)(save_times)
    relative = jax.vmap(system._acceleration)(save_times, ys)
    loads = None if system.vertical_acceleration is None else jax.vmap(system.load_factor)(save_times)
    friction = jax.vmap(lambda y, s: system.at_state(y).friction_force(y["v"][0], y["z"], y["z_peak"], s))(
        ys, loads)
    return StructureResponse(
        time=save_times,
        displacement=ys["u"],
        velocity=ys["v"],
        total_acceleration=relative + ag[:, None],
        friction_force=friction,
        z=ys["z"],
        z_peak=ys["z_peak"],
        ground_acceleration=ag,
        result=solution.result,
        load_factor=loads,
        uplift_time=None if loads is None else uplift_steps(system, n_steps) * dt,
    )
