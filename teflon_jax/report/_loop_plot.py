"""Force-displacement loop plot of a bearing test."""

import textwrap

import numpy as np

from ..units import INCH


def plot_loop(result, path, *, title="", length=("in", INCH)):
    """Friction force over normal load against displacement (PNG); a biaxial test also shows
    its path and the y loop. `title` states the inputs (PTFE, pressure, motion); `length` is
    the (name, SI factor) of the displacement axis."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    name, factor = length
    in_plane = bool(np.any(np.asarray(result.uy) != 0))
    load = np.asarray(result.normal_load)
    ux, uy = np.asarray(result.ux) / factor, np.asarray(result.uy) / factor
    panels = [("x", ux, np.asarray(result.fx) / load)]
    if in_plane:
        panels.append(("y", uy, np.asarray(result.fy) / load))
    columns = len(panels) + int(in_plane)
    fig, axes = plt.subplots(1, columns, figsize=(4.2 * columns, 4.2), squeeze=False)
    for ax, (axis, u, mu) in zip(axes[0], panels):
        ax.plot(u, mu, color="k", lw=1.2)
        ax.set_xlabel(f"displacement u{axis} [{name}]")
        ax.set_ylabel(f"friction force F{axis} / normal load N [-]")
        if in_plane:
            ax.set_title(f"{axis} loop", fontsize=9)
        ax.grid(alpha=0.3)
    if in_plane:
        ax = axes[0, -1]
        ax.plot(ux, uy, color="k", lw=1.2)
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel(f"ux [{name}]")
        ax.set_ylabel(f"uy [{name}]")
        ax.set_title("imposed path", fontsize=9)
        ax.grid(alpha=0.3)
    fig.suptitle("\n".join(textwrap.wrap(title, 40 * columns)), fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
