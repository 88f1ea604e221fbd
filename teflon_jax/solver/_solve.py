"""One call that integrates a stepped system on its time grid, with RiccatiNewmark or any solver."""

import diffrax
import jax.numpy as jnp

from ._riccati_newmark import RiccatiNewmark


def solve_on_grid(system, solver, steps, save_times, y0, *, jump_times, rtol: float, atol: float,
                  max_steps: int | None = None, adjoint=None, throw: bool = True,
                  adaptive_steps_per_step: int = 100):
    """`diffrax.diffeqsolve` of `system` from `steps[0]` to `steps[-1]`, saved at `save_times`.

    `RiccatiNewmark` steps exactly on `steps` [s] (one `advance` per interval, `max_steps`
    defaults to their number); any other diffrax solver runs adaptively (`PIDController` with
    `rtol`, `atol`, stopping at `jump_times` [s], the record samples, with a first step of a
    tenth of the grid's and up to `adaptive_steps_per_step` steps per grid step).

    **Returns:** the diffrax `Solution` (its `result` says whether every step converged).
    """
    n_steps = steps.shape[0] - 1
    if isinstance(solver, RiccatiNewmark):
        controller, dt0 = diffrax.StepTo(ts=steps), None
        max_steps = n_steps if max_steps is None else max_steps
    else:
        controller = diffrax.PIDController(rtol=rtol, atol=atol, jump_ts=jnp.unique(jump_times))
        dt0 = (steps[1] - steps[0]) / 10
        max_steps = adaptive_steps_per_step * n_steps + 100_000 if max_steps is None else max_steps
    return solve_with_controller(system, solver, controller, t0=steps[0], t1=steps[-1], dt0=dt0, y0=y0,
                                 save_times=save_times, max_steps=max_steps, adjoint=adjoint, throw=throw)


def solve_with_controller(system, solver, controller, *, t0, t1, dt0, y0, save_times, max_steps: int,
                          adjoint=None, throw: bool = True):
    """`diffrax.diffeqsolve` of the vector field `system` (`ODETerm`) with `solver` and the
    step-size `controller` from `t0` to `t1` [s] (first step `dt0`, None with `StepTo`), saved
    at `save_times` [s]; `adjoint` defaults to reverse mode (`RecursiveCheckpointAdjoint`).

    **Returns:** the diffrax `Solution` (its `result` says whether every step converged).
    """
    return diffrax.diffeqsolve(
        diffrax.ODETerm(system),
        solver,
        t0=t0,
        t1=t1,
        dt0=dt0,
        y0=y0,
        saveat=diffrax.SaveAt(ts=save_times),
        stepsize_controller=controller,
        max_steps=max_steps,
        adjoint=diffrax.RecursiveCheckpointAdjoint() if adjoint is None else adjoint,
        throw=throw,
    )
