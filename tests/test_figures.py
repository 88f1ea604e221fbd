"""What a reader must see in the figures: the legend covers no data, the full model is drawn
over the Coulomb traces, and one outlier does not set the residual maps' scale."""

import numpy as np

from teflon_jax.paper._figures import figure_eight_figure, histories_figure
from teflon_jax.report import residual_maps, robust_limits


def _legend_box(figure):
    figure.draw_without_rendering()
    legends = [*figure.legends, *(ax.get_legend() for ax in figure.axes if ax.get_legend())]
    assert len(legends) == 1
    return legends[0].get_window_extent()


def _data_axes(figure):
    return [ax for ax in figure.axes if ax.lines]


def _figure_eight_rows():
    t = np.linspace(0.0, 2 * np.pi, 400)
    rows = []
    for amplitude in (1.0, 4.0):
        cases = []
        for label, f_max in (("isotropic", 0.10), ("anisotropic", 0.13)):
            ux, uy = amplitude * np.sin(t), amplitude * np.sin(2 * t)
            cases.append((label, ux, uy, f_max * np.tanh(5 * np.cos(t)),
                          f_max * np.tanh(5 * np.cos(2 * t)) * (1 + 0.3 * (uy > 0))))
        rows.append((f"U0 = {amplitude:g} in", cases))
    return rows


def test_fig6_legend_leaves_the_cited_anisotropic_peak_visible():
    # The report cites the anisotropic max |Fy|/N of the U0 = 4 in row (Fig. 6, y panel).
    rows = _figure_eight_rows()
    figure = figure_eight_figure(rows, title="Figs. 5-6")
    box = _legend_box(figure)
    for ax in _data_axes(figure):
        assert not box.overlaps(ax.get_window_extent()), ax.get_title()
    _, ux, uy, fx, fy = rows[1][1][1]
    k = int(np.argmax(np.abs(fy)))
    y_panel = figure.axes[5]
    assert y_panel.get_title().endswith("y direction")
    peak = y_panel.transData.transform((uy[k], fy[k]))
    assert not box.contains(*peak)
    assert y_panel.get_window_extent().contains(*peak)


def test_fig8_full_model_is_drawn_over_the_coulomb_traces_and_the_legend_over_none():
    time = np.linspace(0.0, 15.0, 3000)
    series = [("full model", np.sin(3 * time) * np.exp(-0.1 * time)),
              ("Coulomb, minimum", 0.9 * np.sin(3 * time)),
              ("Coulomb, maximum", 1.1 * np.sin(3 * time))]
    figure = histories_figure(time, series, title="Fig. 8", ylabel="a / PGA [-]")
    (ax,) = _data_axes(figure)
    full, *coulomb = ax.lines
    assert full.get_label() == "full model"
    assert all(full.get_zorder() > line.get_zorder() for line in coulomb)
    assert not _legend_box(figure).overlaps(ax.get_window_extent())


def test_residual_axis_is_set_by_percentiles_not_by_an_outlier():
    rng = np.random.default_rng(0)
    residual = 0.01 * rng.standard_normal(2000)
    residual[7] = 5.0  # one sample at the edge of a stick phase, where N Z is near zero
    x = rng.uniform(size=residual.size)
    everything = np.ones(residual.size, dtype=bool)
    figure = residual_maps([("speed", x), ("load", x)], residual, [(everything, "C0", "all")],
                           ylabel="d_mu [-]", title="residual")
    ax = figure.axes[0]
    low, high = ax.get_ylim()
    p1, p99 = np.percentile(residual, [1, 99])
    assert (low, high) == robust_limits(residual)
    assert low < p1 < p99 < high < 2 * p99 - p1
    beyond = int(np.count_nonzero((residual < low) | (residual > high)))
    assert 1 <= beyond <= 0.02 * residual.size
    assert f"axis: 1st-99th percentile; {beyond} beyond" in ax.get_ylabel()
