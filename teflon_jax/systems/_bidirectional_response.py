"""Histories of a `BidirectionalStructure`: its response over a record, saved step by step.

Reference: Constantinou, Mokha & Reinhorn (1990), Eqs. 1, 8-9, 17.
"""

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp

from ..solver import RiccatiNewmark, solve_on_grid
from ._bidirectional import BidirectionalStructure
from ._bidirectional_build import bidirectional_initial_state
from ._vertical import uplift_steps


class BidirectionalResponse(eqx.Module):
    """Histories of a `BidirectionalStructure` (SI; time along the first axis).

    - `time` (nt,) [s]; `q`, `v` (nt, N) relative coordinates and velocities;
    - `acceleration` (nt, N) relative accelerations; `ground` (nt, 2) [m/s^2];
    - `bearing_displacement` (nt, G, 2) [m]; `friction_force` (nt, G, 2) [N];
    - `z` (nt, G, 2) [-]; `z_peak` (nt, G) [-]; `result`: `diffrax.RESULTS` (0 = successful);
    - `load_factor` (nt,) [-]: N / W, 0 while uplifted, and `uplift_time` [s] (the steps with
      N <= 0 times the step), with a vertical record; else `None`;
    - `normal_load` (nt, G) [N]: each group's N_g, and `group_uplift_time` (G,) [s] (the saved
      steps with N_g <= 0 times the step between them), with overturning (`_overturning.py`);
      else `None`.
    """

    time: jnp.ndarray
    q: jnp.ndarray
    v: jnp.ndarray
    acceleration: jnp.ndarray
    ground: jnp.ndarray
    bearing_displacement: jnp.ndarray
    friction_force: jnp.ndarray
    z: jnp.ndarray
    z_peak: jnp.ndarray
    result: object
    load_factor: jnp.ndarray | None = None
    uplift_time: jnp.ndarray | None = None
    normal_load: jnp.ndarray | None = None
    group_uplift_time: jnp.ndarray | None = None

    @property
    def succeeded(self):
        return self.result == diffrax.RESULTS.successful


def simulate_bidirectional(
    system: BidirectionalStructure,
    duration: float,
    *,
    save_every: int = 1,
    solver=None,
    rtol: float = 1e-8,
    atol: float = 1e-10,
    max_steps: int | None = None,
    throw: bool = True,
) -> BidirectionalResponse:
    """Integrate a `BidirectionalStructure` from rest over `duration` [s].

    **Arguments:** `solver`: `RiccatiNewmark()` (default, fixed step `system.time_step`) or an
    adaptive diffrax solver (e.g. `diffrax.Tsit5()` with `rtol`, `atol`) for reference
    solutions; `save_every`: keep every k-th step; `throw`: raise on solver failure (with
    `False`, e.g. under `vmap`, the outcome of each member is in `result`).
    """
    dt = float(system.time_step)
    n_steps = int(round(duration / dt + 1e-9))
    if n_steps < 1:
        raise ValueError(f"duration: must be at least one time step ({dt} s), got {duration}.")
    if system.vertical_acceleration is not None:
        system.vertical_acceleration.require_covers(n_steps * dt, "duration (vertical record)")
    steps = jnp.arange(n_steps + 1) * dt
    save_times = steps[::save_every]
    solver = RiccatiNewmark() if solver is None else solver
    if system.overturning is not None and not isinstance(solver, RiccatiNewmark):
        raise ValueError("solver: the overturning loads are held over the fixed steps of "
                         "RiccatiNewmark; leave solver out (or give height 0).")
    solution = solve_on_grid(
        system, solver, steps, save_times, bidirectional_initial_state(system),
        jump_times=jnp.concatenate([system.ground_x.times, system.ground_y.times]),
        rtol=rtol, atol=atol, max_steps=max_steps, throw=throw, adaptive_steps_per_step=200,
    )
    ys = solution.ys
    ground = jax.vmap(system.ground)(save_times)
    acceleration = jax.vmap(system._acceleration)(save_times, ys)
    bearing_d = jax.vmap(system.bearing_motion)(ys["q"])
    forces = jax.vmap(lambda t, y: system.at_load(system.load_at(t, y)).bearing_forces(y))(save_times, ys)
    loads = None if system.vertical_acceleration is None else jax.vmap(system.load_factor)(save_times)
    return BidirectionalResponse(
        time=save_times,
        q=ys["q"],
        v=ys["v"],
        acceleration=acceleration,
        ground=ground,
        bearing_displacement=bearing_d,
        friction_force=forces,
        z=ys["z"],
        z_peak=ys["z_peak"],
        result=solution.result,
        load_factor=loads,
        uplift_time=None if loads is None else uplift_steps(system, n_steps) * dt,
        normal_load=ys.get("normal_load"),
        group_uplift_time=None if system.overturning is None else (
            jnp.sum(ys["normal_load"][1:] <= 0, axis=0) * dt * save_every),
    )
