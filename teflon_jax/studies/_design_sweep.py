"""Sweeps of the design variables over a grid, for plots and starting points."""

from collections.abc import Mapping

import jax
import jax.numpy as jnp
import numpy as np

from ..systems import IsolatedStructure, check_design
from ._design import Bounds, _records_array, expected_response, penalised_objective


def design_sweep(
    structure: IsolatedStructure,
    records,
    record_time_step: float,
    *,
    grid: Mapping,
    disp_limit: float,
    penalty: float = 100.0,
    duration: float | None = None,
    disp_width=1e-3,
    shear_width=1e-3,
    batch_size: int = 16,
) -> dict:
    """The same objective on the tensor grid of `grid` (name -> 1-D values), vmapped over
    design points in batches of `batch_size` (one compilation).

    **Returns:** {"grid": {name: (G...) mesh}, "objective", "shear", "disp": (G...) arrays,
    "converged": (G...) bool, every motion's solve converged at that point, "n_failed": (G...)
    motions with a failed step, "n_motions"}. `sweep_start` skips points that did not converge.
    """
    names = list(grid)
    axes = [np.asarray(grid[n], dtype=float) for n in names]
    check_design(structure, dict(zip(names, axes)))
    mesh = np.meshgrid(*axes, indexing="ij")
    flat = {n: m.reshape(-1) for n, m in zip(names, mesh)}
    records = _records_array(records, record_time_step)

    @jax.jit
    def evaluate(points):
        def one(point):
            r = expected_response(
                structure, point, records, record_time_step, duration=duration,
                disp_width=disp_width, shear_width=shear_width,
            )
            return penalised_objective(r, disp_limit, penalty), r["shear"], r["disp"], r["n_failed"]

        return jax.vmap(one)(points)

    total = mesh[0].size
    batch = min(batch_size, total)
    outputs = []
    for begin in range(0, total, batch):
        index = np.minimum(np.arange(begin, begin + batch), total - 1)
        outputs.append(jax.device_get(evaluate({n: jnp.asarray(v[index]) for n, v in flat.items()})))
    objective, shear, disp, failed = (
        np.concatenate(parts)[:total].reshape(mesh[0].shape) for parts in zip(*outputs)
    )
    return {"grid": dict(zip(names, mesh)), "objective": objective, "shear": shear, "disp": disp,
            "converged": failed == 0, "n_failed": failed.astype(int), "n_motions": int(records.shape[0])}


def sweep_start(sweep: Mapping, bounds: Bounds, *, margin: float = 1e-3) -> dict:
    """The converged grid point of `sweep` with the lowest objective, moved inside `bounds` by
    `margin` of each range (the bijection needs interior points): a start for BFGS on a
    non-convex objective (global look by the grid, local refinement by the gradient)."""
    objective = np.asarray(sweep["objective"], dtype=float).reshape(-1)
    if "converged" in sweep:
        objective = np.where(np.asarray(sweep["converged"]).reshape(-1), objective, np.inf)
    if not np.any(np.isfinite(objective)):
        raise ValueError("sweep: no grid point converged for every motion; no start can be chosen "
                         "(try a smaller structure time step).")
    best = int(np.argmin(objective))
    start = {}
    for name, (lo, hi) in bounds.ranges.items():
        value = float(sweep["grid"][name].reshape(-1)[best])
        start[name] = min(max(value, lo + margin * (hi - lo)), hi - margin * (hi - lo))
    return start
