"""Plot of Monte Carlo peak responses."""

import textwrap

import numpy as np

from ..studies import SURFACE_VARIABLES, MonteCarloResult

_PERCENTILES = ((50, "median", "-"), (84, "84th percentile", "--"), (95, "95th percentile", ":"))


def plot_montecarlo(result: MonteCarloResult, path, *, title: str = "", length=("mm", 1e-3)) -> None:
    """`montecarlo_figure` written to `path` (PNG)."""
    fig = montecarlo_figure(result, title=title, length=length)
    import matplotlib.pyplot as plt

    fig.savefig(path, dpi=110)
    plt.close(fig)


def montecarlo_figure(result: MonteCarloResult, *, title: str = "", length=("mm", 1e-3)):
    """Histogram and exceedance curve of the peak base displacement and base shear ratio over
    the runs whose solve converged (one design), the percentiles in the legends with their
    units; where the result keeps its isolator's surfaces, a third column of their exceedance
    curves (`surface_panels`). `title` states the inputs; `length` is the (name, SI factor) of
    the displacement.

    **Returns:** the matplotlib figure (open; `plot_montecarlo` saves and closes it)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    converged = np.asarray(result.converged, bool).reshape(-1)
    n = int(converged.sum())
    surfaces = result.surfaces
    fig, axes = plt.subplots(2, 3 if surfaces else 2, figsize=(15 if surfaces else 10, 7.5))
    resultant = "resultant " if result.attrs.get("components") == 2 else ""
    for column, (name, label, factor, unit) in enumerate((
        ("base_disp", f"peak {resultant}base displacement [{length[0]}]", length[1], length[0]),
        ("base_shear_ratio", f"peak {resultant}base shear / weight [-]", 1.0, "[-]"),
    )):
        values = np.asarray(getattr(result, name)).reshape(-1)[converged] / factor
        top, bottom = axes[0, column], axes[1, column]
        top.hist(values, bins=min(50, max(5, n // 10)), color="0.75", edgecolor="k", lw=0.4,
                 label=f"{n} converged runs")
        for q, text, style in _PERCENTILES:
            level = np.percentile(values, q) if n else np.nan
            top.axvline(level, color="k", lw=1.0, ls=style, label=f"{text} = {level:.3g} {unit}")
            bottom.axvline(level, color="k", lw=0.6, ls=style)
        top.set_xlabel(label)
        top.set_ylabel("number of motions")
        top.legend(fontsize=8)
        levels = np.sort(values)
        probability = (n - np.arange(1, n + 1)) / max(n, 1)
        bottom.semilogy(levels, np.maximum(probability, 0.5 / max(n, 1)), color="k", lw=1.2,
                        label=f"empirical, {n} runs (floor at 1/(2n))")
        bottom.set_xlabel(label)
        bottom.set_ylabel("probability of exceedance [-]")
        bottom.grid(True, which="both", alpha=0.3)
        bottom.legend(fontsize=8)
    if surfaces:
        surface_panels(result, axes[:, 2], converged, length)
    failed = converged.size - n
    heading = title or f"Monte Carlo, {result.n_motions} motions"
    if failed:
        heading += f" ({failed} runs did not converge and are left out)"
    fig.suptitle("\n".join(textwrap.wrap(heading, 110)), fontsize=9)
    fig.tight_layout()
    return fig


def surface_panels(result: MonteCarloResult, axes, converged, length) -> None:
    """On `axes` (top, bottom): the exceedance curve of each series-pendulum slider's peak
    travel over the `converged` runs, in `length` (name, SI factor), with its capacity where
    the result keeps them (`attrs["slider_capacities_m"]`, (G, S)) drawn as a vertical line of
    the curve's colour and the runs beyond it in the legend; below, each heated surface's peak
    temperature rise. A panel without such surfaces is left blank."""
    n = int(converged.sum())
    floor = 0.5 / max(n, 1)
    capacities = result.attrs.get("slider_capacities_m")
    groups = result.group_names
    for ax, name in zip(axes, ("slider_travel", "surface_temperature_rise")):
        if name not in result.surfaces:
            ax.axis("off")
            continue
        labels = result.surfaces[name][1]
        si_unit = SURFACE_VARIABLES[name][1]
        factor, unit = (length[1], length[0]) if si_unit == "m" else (1.0, si_unit)
        values = np.asarray(getattr(result, name)).reshape((-1, len(groups), len(labels)))[converged]
        for j, group in enumerate(groups):
            for e, label in enumerate(labels):
                series = np.sort(values[:, j, e]) / factor
                text = label if len(groups) == 1 else f"{group}: {label}"
                if name == "slider_travel" and capacities is not None:
                    capacity = float(np.asarray(capacities)[j, e]) / factor
                    text += f" (capacity {capacity:.3g} {unit}, {int(np.sum(series > capacity))} runs beyond)"
                (line,) = ax.semilogy(series, np.maximum((n - np.arange(1, n + 1)) / max(n, 1), floor), lw=1.2,
                                      label=text)
                if name == "slider_travel" and capacities is not None:
                    ax.axvline(capacity, color=line.get_color(), lw=0.8, ls="--")
        ax.set_xlabel(f"peak {name.replace('_', ' ')} [{unit}]")
        ax.set_ylabel("probability of exceedance [-]")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
