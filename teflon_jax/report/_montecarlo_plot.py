"""Plot of Monte Carlo peak responses."""

import numpy as np

from ..studies import MonteCarloResult


def plot_montecarlo(result: MonteCarloResult, path, *, title: str = "") -> None:
    """Histogram and exceedance curves of base displacement and base shear ratio (PNG)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(10, 7))
    for column, (name, label, factor) in enumerate(
        (("base_disp", "peak base displacement [mm]", 1e3), ("base_shear_ratio", "peak base shear / weight [-]", 1.0))
    ):
        values = getattr(result, name).reshape(-1, result.n_motions) * factor
        levels, probability = result.exceedance(name)
        levels = levels.reshape(-1, result.n_motions) * factor
        for d in range(values.shape[0]):
            axes[0, column].hist(values[d], bins=min(50, max(5, result.n_motions // 10)), alpha=0.6)
            axes[1, column].semilogy(levels[d], np.maximum(probability, 0.5 / result.n_motions))
        for q in (50, 84, 95):
            axes[0, column].axvline(np.percentile(values, q), color="k", lw=0.8, ls="--")
        axes[0, column].set_xlabel(label)
        axes[0, column].set_ylabel("motions")
        axes[1, column].set_xlabel(label)
        axes[1, column].set_ylabel("P[exceedance]")
        axes[1, column].grid(True, which="both", alpha=0.3)
    fig.suptitle(title or f"Monte Carlo, {result.n_motions} motions, {result.n_devices} device(s)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
