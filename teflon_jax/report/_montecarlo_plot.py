"""Plot of Monte Carlo peak responses."""

import textwrap

import numpy as np

from ..studies import MonteCarloResult

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
    units. `title` states the inputs; `length` is the (name, SI factor) of the displacement.

    **Returns:** the matplotlib figure (open; `plot_montecarlo` saves and closes it)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    converged = np.asarray(result.converged, bool).reshape(-1)
    n = int(converged.sum())
    fig, axes = plt.subplots(2, 2, figsize=(10, 7.5))
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
    failed = converged.size - n
    heading = title or f"Monte Carlo, {result.n_motions} motions"
    if failed:
        heading += f" ({failed} runs did not converge and are left out)"
    fig.suptitle("\n".join(textwrap.wrap(heading, 110)), fontsize=9)
    fig.tight_layout()
    return fig
