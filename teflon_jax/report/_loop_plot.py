"""Force-displacement loop plot of a bearing test."""

import numpy as np

from ..units import INCH


def plot_loop(result, path, *, title=""):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    biaxial = bool(np.any(np.asarray(result.uy) != 0))
    fig, axes = plt.subplots(1, 2 if biaxial else 1, figsize=(10 if biaxial else 5.5, 4.2), squeeze=False)
    mu_x = np.asarray(result.fx) / np.asarray(result.normal_load)
    axes[0, 0].plot(np.asarray(result.ux) / INCH, mu_x, lw=1.2)
    axes[0, 0].set_xlabel("ux [in]")
    axes[0, 0].set_ylabel("fx / N")
    axes[0, 0].grid(alpha=0.3)
    if biaxial:
        mu_y = np.asarray(result.fy) / np.asarray(result.normal_load)
        axes[0, 1].plot(np.asarray(result.uy) / INCH, mu_y, lw=1.2, color="C1")
        axes[0, 1].set_xlabel("uy [in]")
        axes[0, 1].set_ylabel("fy / N")
        axes[0, 1].grid(alpha=0.3)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
