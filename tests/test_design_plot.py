"""The design figure (`report._design_plot`): the trade-off's legend covers no grid design.

A 7 x 7 grid whose designs fill the trade-off's axes, as the default design's do; every
design's marker (and the optimum's stars) must lie outside the legend's box on the canvas."""

from types import SimpleNamespace

import numpy as np

from teflon_jax.report._design_plot import design_figure
from teflon_jax.units import PSI


def _sweep_and_result():
    periods, pressures = np.meshgrid(np.linspace(1.0, 4.0, 7), np.linspace(1000, 2000, 7) * PSI, indexing="ij")
    u = (periods - 1.0) / 3.0
    v = (pressures / PSI - 1000.0) / 1000.0
    disp = 0.01 + 0.03 * u + 0.004 * v  # [m]: spread over the whole axis
    shear = 0.2 - 0.1 * u + 0.02 * v + 0.01 * np.sin(7 * v)
    limit = 0.025
    objective = shear + 100 * np.maximum(disp / limit - 1, 0) ** 2
    sweep = {"grid": {"isolation_period": periods, "pressure": pressures}, "objective": objective,
             "shear": shear, "disp": disp, "converged": np.ones_like(disp, bool)}
    result = SimpleNamespace(optimum={"isolation_period": 2.5, "pressure": 1000 * PSI}, objective=0.15,
                             disp_limit=0.0318, smooth_disp_limit=limit, limited_smooth_disp=limit,
                             mean_shear=0.15, limited_disp=0.0317, peak_shear=0.16, limit_statistic="mean")
    return sweep, result


def test_the_trade_off_legend_covers_no_grid_design():
    import matplotlib.pyplot as plt

    sweep, result = _sweep_and_result()
    fig = design_figure(sweep, result, units={"pressure": (PSI, "psi"), "length": (0.0254, "in")})
    try:
        fig.canvas.draw()
        right = next(ax for ax in fig.axes if "peak base displacement" in ax.get_xlabel())
        box = right.get_legend().get_window_extent()
        points = [collection.get_offsets() for collection in right.collections]
        points += [np.column_stack(line.get_data()) for line in right.lines if line.get_marker() == "*"]
        canvas = right.transData.transform(np.concatenate(points))
        assert len(canvas) == 49 + 2
        inside = [p for p in canvas if box.x0 <= p[0] <= box.x1 and box.y0 <= p[1] <= box.y1]
        assert not inside, f"the legend {box} covers {len(inside)} designs"
    finally:
        plt.close(fig)
