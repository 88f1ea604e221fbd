"""Plot of fitted fragility curves with the fraction of runs exceeding at each level."""

import math
import textwrap

import numpy as np


def plot_fragility(curves: dict, path, *, unit: str = "g", factor: float = 1.0, title: str = "") -> None:
    """One panel: for each limit (name -> `FragilityFit`, a `FragilityBand`, or (intensities,
    n_runs, n_exceed) when no curve could be fitted), the fraction k_j / n_j exceeding at each
    level (markers), the fitted lognormal P(exceed | x) = Phi(ln(x / theta) / beta) (line) and
    the median's confidence interval (bar at P = 0.5). A `FragilityBand` draws the fit of all
    runs, the pointwise band of the bearing draws' curves (shaded) and the median's band over
    the draws (a second bar). `unit`, `factor`: the intensity axis's unit and its size in the
    fits' unit (intensities are divided by it)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 5.5))
    top = 0.0
    for index, (name, curve) in enumerate(curves.items()):
        color = f"C{index}"
        band, curve = (curve, curve.pooled) if hasattr(curve, "pooled") else (None, curve)
        fitted = hasattr(curve, "median")
        x, n, k = ((curve.intensities, curve.n_runs, curve.n_exceed) if fitted else curve)
        x = np.asarray(x, float) / factor
        top = max(top, float(x[-1]))
        label = f"{name}: fraction of runs exceeding"
        ax.plot(x, np.asarray(k) / np.asarray(n), "o", color=color, mfc="none", label=label)
        if not fitted:
            ax.lines[-1].set_label(f"{label} (no fit: see the JSON's error)")
            continue
        grid = np.linspace(x[0] * 0.5, x[-1] * 1.5, 400)
        median = curve.median / factor
        ax.plot(grid, curve.probability(grid * factor), "-", color=color,
                label=f"{name}: lognormal fit, median {median:.3g} {unit}, dispersion {curve.dispersion:.3g}")
        low, high = (v / factor for v in curve.median_interval)
        high_shown = min(high, grid[-1]) if math.isfinite(high) else grid[-1]
        ax.plot([low, high_shown], [0.5, 0.5], "-", color=color, lw=4, alpha=0.35,
                label=f"{name}: median, {100 * curve.confidence:g} % interval")
        if band is not None:
            _draw_band(ax, band, grid, factor, color, name)
        top = max(top, float(grid[-1]))
    ax.set_xlim(0, top)
    ax.set_ylim(-0.02, 1.02)
    ax.set_xlabel(f"intensity: expected peak ground acceleration [{unit}]")
    ax.set_ylabel("P(exceed)")
    ax.grid(True, lw=0.3)
    ax.legend(fontsize=7, loc="lower right")
    if title:
        ax.set_title("\n".join(textwrap.wrap(title, 100)), fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _draw_band(ax, band, grid, factor: float, color: str, name: str) -> None:
    """The pointwise band of the draws' curves (shaded) and the median's band over the draws
    (a thin bar just below P = 0.5) of a `FragilityBand`."""
    below, above = band.probability_band(grid * factor)
    share = f"{100 * band.band:g} %"
    fitted = len(band.draw_fits)
    ax.fill_between(grid, below, above, color=color, alpha=0.18, lw=0,
                    label=f"{name}: {share} band of the {fitted} bearing draws' curves")
    low, high = (v / factor for v in band.median_band)
    ax.plot([low, high], [0.47, 0.47], "-", color=color, lw=2, alpha=0.8,
            label=f"{name}: median over the draws, {share} band {low:.3g}-{high:.3g}")
    low, high = (v / factor for v in band.median_interval)
    high = min(high, grid[-1]) if math.isfinite(high) else grid[-1]
    ax.plot([low, high], [0.44, 0.44], ":", color=color, lw=2, alpha=0.8,
            label=f"{name}: median, the draws' and the motions' spread together")
