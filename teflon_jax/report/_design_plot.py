"""Plot of a design sweep and the optimum found by gradients."""

import textwrap
from collections.abc import Mapping

import numpy as np

from ..studies import DesignResult

_WORDS = {"isolation_period": "isolation period Tb", "pressure": "bearing pressure"}


def plot_design(sweep: Mapping, result: DesignResult, path, *, units: Mapping | None = None,
                title: str = "") -> None:
    """Objective over the grid sweep (a curve for one variable, contours for two) with the
    gradient optimum marked, beside the trade-off of mean base shear against mean base
    displacement (PNG). `units` maps a variable name, and "length", to (SI factor, name);
    `title` states the inputs."""
    import matplotlib.pyplot as plt

    fig = design_figure(sweep, result, units=units, title=title)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def design_figure(sweep: Mapping, result: DesignResult, *, units: Mapping | None = None, title: str = ""):
    """The figure of `plot_design` (a matplotlib `Figure`, not closed): the trade-off's legend
    lies below its axes, where it covers none of the grid's designs."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    units = dict(units or {})
    names = list(sweep["grid"])
    scale = {n: units.get(n, (1.0, ""))[0] for n in names}
    label = {n: f"{_WORDS.get(n, n.replace('_', ' '))} [{units.get(n, (1.0, '-'))[1]}]" for n in names}
    length_factor, length_name = units.get("length", (1e-3, "mm"))
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 6))
    if len(names) == 1:
        n = names[0]
        left.plot(sweep["grid"][n] / scale[n], sweep["objective"], "ko-", ms=3, label="grid sweep")
        left.plot(result.optimum[n] / scale[n], result.objective, "k*", ms=14, mfc="w",
                  label="gradient optimum", clip_on=False, zorder=5)
        left.set_xlabel(label[n])
        left.set_ylabel("objective: mean base shear / weight + penalty [-]")
    else:
        a, b = names[:2]
        x, y = sweep["grid"][a] / scale[a], sweep["grid"][b] / scale[b]
        cmap = matplotlib.colormaps["Greys_r"].with_extremes(over="mistyrose")
        contour = left.contourf(x, y, sweep["objective"], _levels(sweep, result), cmap=cmap, extend="max")
        fig.colorbar(contour, ax=left, label="objective [-] (pink: penalised beyond the limit)")
        ox, oy = result.optimum[a] / scale[a], result.optimum[b] / scale[b]
        left.plot(ox, oy, "*", color="w", mec="k", ms=16, label="gradient optimum",
                  clip_on=False, zorder=5)
        _frame(left, np.concatenate([np.ravel(x), [ox]]), np.concatenate([np.ravel(y), [oy]]))
        left.set_xlabel(label[a])
        left.set_ylabel(label[b])
    left.legend(fontsize=8, loc="best")
    statistic = {"p95": "95th-percentile"}.get(getattr(result, "limit_statistic", "mean"), "mean")
    disp = np.asarray(sweep["disp"]) / length_factor
    shear = np.asarray(sweep["shear"])
    feasible = np.asarray(sweep["disp"]) <= result.smooth_disp_limit
    right.scatter(disp[~feasible], shear[~feasible], marker="x", c="0.5", s=18,
                  label="grid designs over the limit on the smoothed mean")
    right.scatter(disp[feasible], shear[feasible], marker="o", facecolors="none", edgecolors="k",
                  s=18, label="grid designs within it")
    right.axvline(result.disp_limit / length_factor, color="k", ls="--", lw=0.8,
                  label=f"displacement limit = {result.disp_limit / length_factor:.3g} {length_name}")
    if result.smooth_disp_limit != result.disp_limit:
        right.axvline(result.smooth_disp_limit / length_factor, color="k", ls=":", lw=0.8,
                      label=f"limit on the smoothed {statistic} that meets it on the true peaks")
    ox, oy = result.limited_smooth_disp / length_factor, result.mean_shear
    right.plot(ox, oy, "k*", ms=14, mfc="w", label="gradient optimum (smoothed)", clip_on=False, zorder=5)
    px, py = result.limited_disp / length_factor, result.peak_shear
    right.plot(px, py, "*", color="C3", ms=14, label=f"gradient optimum: {statistic} of the true peaks",
               clip_on=False, zorder=5)
    _frame(right, np.append(disp, [ox, px]), np.append(shear, [oy, py]))
    right.set_xlabel(f"{statistic} peak base displacement (grid: smoothed) [{length_name}]")
    right.set_ylabel("mean peak base shear / weight (grid: smoothed) [-]")
    # the legend in a band along the figure's foot, below both panels, where it covers no design
    legend = right.legend(fontsize=8, loc="lower right", bbox_to_anchor=(0.99, 0.01), bbox_transform=fig.transFigure,
                          ncol=2, frameon=False)
    legend.set_in_layout(False)
    right.grid(alpha=0.3)
    if title:
        fig.suptitle("\n".join(textwrap.wrap(title, 120)), fontsize=9)
    fig.tight_layout(rect=(0.0, 0.1, 1.0, 1.0))
    return fig


def _levels(sweep: Mapping, result, n: int = 20) -> np.ndarray:
    """Contour levels over the objective of the grid designs within the displacement limit
    (twice their spread above the lowest), so that the penalty of the designs beyond it,
    orders of magnitude larger, does not take the whole colour scale."""
    objective = np.asarray(sweep["objective"], dtype=float)
    finite = objective[np.isfinite(objective)]
    within = objective[np.isfinite(objective) & (np.asarray(sweep["disp"]) <= result.smooth_disp_limit)]
    low = float(finite.min()) if finite.size else 0.0
    top = float(within.max()) if within.size > 1 else float(np.quantile(finite, 0.5)) if finite.size else 1.0
    high = low + 2.0 * (top - low) if top > low else low + max(abs(low), 1.0) * 0.1
    return np.linspace(low, high, n + 1)


def _frame(ax, x, y, margin=0.06):
    """Axis limits that hold every point of x and y with a margin (the optimum stays inside)."""
    for values, setter in ((np.asarray(x, float), ax.set_xlim), (np.asarray(y, float), ax.set_ylim)):
        values = values[np.isfinite(values)]
        if values.size == 0:
            continue
        low, high = values.min(), values.max()
        pad = margin * (high - low) if high > low else max(abs(high), 1.0) * margin
        setter(low - pad, high + pad)
