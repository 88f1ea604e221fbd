"""Matplotlib figures of `reproduce` (Figs. 3-11 of Constantinou, Mokha & Reinhorn 1990).

Plotting only: every function takes NumPy arrays in the paper's units and writes one PNG.
Uses `matplotlib.figure.Figure` directly (no pyplot state, no display needed). Lines are black
and grey with distinct dash patterns, so that a figure survives black-and-white print; legends
are in words with the values; `stamp` (the inputs: record, PTFE, pressure, Tb) is written at the
foot of every figure.
"""

import pathlib
import textwrap

import numpy as np

STYLES = (
    {"color": "k", "ls": "-", "lw": 1.2},
    {"color": "k", "ls": "--", "lw": 1.2},
    {"color": "0.45", "ls": "-", "lw": 1.2},
    {"color": "k", "ls": ":", "lw": 1.4},
    {"color": "0.45", "ls": "-.", "lw": 1.2},
    {"color": "0.45", "ls": "--", "lw": 1.2},
)
"""Line styles in order of use: told apart by dash pattern and grey level, not by colour."""


def style(i: int) -> dict:
    return dict(STYLES[i % len(STYLES)])


def _figure(rows=1, cols=1, size=(6.4, 4.2)):
    from matplotlib.figure import Figure

    figure = Figure(figsize=size, layout="constrained")
    axes = figure.subplots(rows, cols, squeeze=False)
    return figure, axes


def _figure_with_legend_row(rows, cols, size, legend_height):
    """`_figure` with a row of height `legend_height` (a fraction of a panel's) under the
    panels for the legend, so that the legend covers no data and no label."""
    from matplotlib.figure import Figure

    figure = Figure(figsize=size, layout="constrained")
    grid = figure.add_gridspec(rows + 1, cols, height_ratios=[1.0] * rows + [legend_height])
    axes = np.array([[figure.add_subplot(grid[r, c]) for c in range(cols)] for r in range(rows)])
    legend_axes = figure.add_subplot(grid[rows, :])
    legend_axes.axis("off")
    return figure, axes, legend_axes


def _save(figure, path, stamp: str = "") -> pathlib.Path:
    if stamp:
        width = int(figure.get_figwidth() * 14)
        figure.get_layout_engine().set(h_pad=0.06)
        figure.supxlabel("\n".join(textwrap.wrap(stamp, width)), fontsize=7, color="0.25")
    path = pathlib.Path(path)
    figure.savefig(path, dpi=110)
    return path


def _title(figure, title, cols):
    figure.suptitle("\n".join(textwrap.wrap(title, int(55 * cols))), fontsize=10)


def loops(path, curves, *, title, stamp="", xlabel="displacement [in]",
          ylabel="friction force / normal load [-]"):
    """Force-displacement loops, one panel each; `curves`: list of (label, x, y)."""
    figure, axes = _figure(1, len(curves), size=(4.2 * len(curves), 4.0))
    for ax, (label, x, y) in zip(axes[0], curves):
        ax.plot(x, y, **style(0))
        ax.set_title("\n".join(textwrap.wrap(label, 42)), fontsize=9)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.grid(alpha=0.3)
    _title(figure, title, len(curves))
    return _save(figure, path, stamp)


def figure_eight(path, rows, *, title, stamp=""):
    """Figs. 5-6: one row per motion, the isotropic (solid) and anisotropic (dashed) bearings on
    the same axes. `rows`: list of (row title, [(label, ux, uy, fx, fy)]) [in, -]. The legend
    sits below the panels, clear of the loops' peaks."""
    return _save(figure_eight_figure(rows, title=title), path, stamp)


def figure_eight_figure(rows, *, title):
    """The `matplotlib.figure.Figure` of `figure_eight`, not yet saved."""
    figure, axes, legend_axes = _figure_with_legend_row(len(rows), 3, (12, 3.6 * len(rows) + 0.5),
                                                        0.1)
    for row, (heading, cases) in zip(axes, rows):
        for i, (label, ux, uy, fx, fy) in enumerate(cases):
            if i == 0:
                row[0].plot(ux, uy, **style(0))
            row[1].plot(ux, fx, label=label, **style(i))
            row[2].plot(uy, fy, label=label, **style(i))
        row[0].set_aspect("equal", adjustable="datalim")
        for ax, (xlabel, ylabel, panel) in zip(row, (
            ("ux [in]", "uy [in]", "imposed path"),
            ("ux [in]", "Fx / N [-]", "x direction"),
            ("uy [in]", "Fy / N [-]", "y direction"),
        )):
            ax.set_xlabel(xlabel)
            ax.set_ylabel(ylabel)
            ax.set_title(f"{heading}: {panel}", fontsize=9)
            ax.grid(alpha=0.3)
    _title(figure, title, 3)
    legend_axes.legend(*axes[0, 1].get_legend_handles_labels(), loc="center", ncols=2,
                       fontsize=8)
    return figure


def histories(path, time, series, *, title, ylabel, stamp="", xlabel="time [s]"):
    """Time histories on one axes; `series`: list of (label in words, values), the first (the
    full model) drawn over the others; the legend below the axes, clear of the peaks."""
    return _save(histories_figure(time, series, title=title, ylabel=ylabel, xlabel=xlabel),
                 path, stamp)


def histories_figure(time, series, *, title, ylabel, xlabel="time [s]"):
    """The `matplotlib.figure.Figure` of `histories`, not yet saved."""
    figure, axes, legend_axes = _figure_with_legend_row(1, 1, (7.5, 5.0), 0.14)
    ax = axes[0, 0]
    for i, (label, values) in enumerate(series):
        ax.plot(time, values, label=label, zorder=2 + len(series) - i, **style(i))
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title("\n".join(textwrap.wrap(title, 80)), fontsize=10)
    ax.grid(alpha=0.3)
    legend_axes.legend(*ax.get_legend_handles_labels(), loc="center", ncols=2, fontsize=7)
    return figure


def spectra_panels(path, periods, panels, *, title, stamp=""):
    """Fig. 11 panels; `panels`: list of (panel title, ylabel, [(label, values)])."""
    cols = 2
    rows = (len(panels) + 1) // 2
    figure, axes = _figure(rows, cols, size=(10, 3.8 * rows))
    markers = ("o", "s", "^", None)
    for ax, (panel, ylabel, series) in zip(axes.ravel(), panels):
        for i, (label, values) in enumerate(series):
            ax.plot(periods, values, marker=markers[i % len(markers)], ms=3, mfc="w", label=label,
                    **style(i))
        ax.set_xlabel("isolation period Tb [s]")
        ax.set_ylabel(ylabel)
        ax.set_title(panel, fontsize=9)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    _title(figure, title, cols)
    return _save(figure, path, stamp)


def breakaway_grid(path, time, cases, *, title, stamp=""):
    """Fig. 10; `cases`: list of (case title, [(label, acceleration / PGA)])."""
    figure, axes = _figure(2, 2, size=(10, 7.4))
    for ax, (case, series) in zip(axes.ravel(), cases):
        for i, (label, values) in enumerate(series):
            ax.plot(time, values, label=label, **style(i))
        ax.set_title("\n".join(textwrap.wrap(case, 60)), fontsize=9)
        ax.set_xlabel("time [s]")
        ax.set_ylabel("total acceleration / peak ground acc. [-]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    _title(figure, title, 2)
    return _save(figure, path, stamp)


def fourier(path, series, *, title, stamp="", max_frequency=25.0,
            ylabel="Fourier amplitude / PGA [s]"):
    """Fourier amplitudes; `series`: list of (label, frequency [Hz], amplitude)."""
    figure, axes = _figure(size=(7.5, 4.4))
    ax = axes[0, 0]
    for i, (label, frequency, amplitude) in enumerate(series):
        keep = frequency <= max_frequency
        ax.plot(frequency[keep], amplitude[keep], label=label, **style(i))
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel(ylabel)
    ax.set_yscale("log")
    ax.set_title("\n".join(textwrap.wrap(title, 80)), fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    return _save(figure, path, stamp)


def smooth(values, width: int):
    """Running mean over `width` samples (odd), same length; the ends average what they have."""
    values = np.asarray(values, dtype=float)
    kernel = np.ones(width)
    return np.convolve(values, kernel, "same") / np.convolve(np.ones_like(values), kernel, "same")


def as_numpy(x):
    return np.asarray(x, dtype=float)
