"""Matplotlib figures of `reproduce` (Figs. 3-11 of Constantinou, Mokha & Reinhorn 1990).

Plotting only: every function takes NumPy arrays in the paper's units and writes one PNG.
Uses `matplotlib.figure.Figure` directly (no pyplot state, no display needed).
"""

import pathlib

import numpy as np


def _figure(rows=1, cols=1, size=(6.4, 4.2)):
    from matplotlib.figure import Figure

    figure = Figure(figsize=size, layout="constrained")
    axes = figure.subplots(rows, cols, squeeze=False)
    return figure, axes


def _save(figure, path) -> pathlib.Path:
    path = pathlib.Path(path)
    figure.savefig(path, dpi=110)
    return path


def loops(path, curves, *, title, xlabel="displacement [in]", ylabel="friction force / normal load"):
    """Force-displacement loops; `curves`: list of (label, x, y)."""
    figure, axes = _figure(1, len(curves), size=(4.2 * len(curves), 3.8))
    for ax, (label, x, y) in zip(axes[0], curves):
        ax.plot(x, y, lw=1.0)
        ax.set_title(label, fontsize=9)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.grid(alpha=0.3)
    figure.suptitle(title, fontsize=10)
    return _save(figure, path)


def biaxial_loops(path, cases, *, title):
    """Figure-eight tests; `cases`: list of (label, ux, uy, fx, fy) [in, -]."""
    figure, axes = _figure(len(cases), 3, size=(11.5, 3.2 * len(cases)))
    for row, (label, ux, uy, fx, fy) in zip(axes, cases):
        row[0].plot(ux, uy, lw=1.0)
        row[0].set_xlabel("ux [in]")
        row[0].set_ylabel("uy [in]")
        row[0].set_title(f"{label}: path", fontsize=9)
        row[1].plot(ux, fx, lw=1.0)
        row[1].set_xlabel("ux [in]")
        row[1].set_ylabel("Fx / N")
        row[1].set_title(f"{label}: x loop", fontsize=9)
        row[2].plot(uy, fy, lw=1.0)
        row[2].set_xlabel("uy [in]")
        row[2].set_ylabel("Fy / N")
        row[2].set_title(f"{label}: y loop", fontsize=9)
        for ax in row:
            ax.grid(alpha=0.3)
    figure.suptitle(title, fontsize=10)
    return _save(figure, path)


def histories(path, time, series, *, title, ylabel, xlabel="time [s]"):
    """Time histories; `series`: list of (label, values)."""
    figure, axes = _figure(size=(7.5, 4.0))
    ax = axes[0, 0]
    for label, values in series:
        ax.plot(time, values, lw=1.0, label=label)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return _save(figure, path)


def spectra_panels(path, periods, panels, *, title):
    """Fig. 11 panels; `panels`: list of (panel title, ylabel, [(label, values)])."""
    cols = 2
    rows = (len(panels) + 1) // 2
    figure, axes = _figure(rows, cols, size=(10, 3.6 * rows))
    for ax, (panel, ylabel, series) in zip(axes.ravel(), panels):
        for label, values in series:
            ax.plot(periods, values, marker=".", lw=1.0, label=label)
        ax.set_xlabel("isolation period Tb [s]")
        ax.set_ylabel(ylabel)
        ax.set_title(panel, fontsize=9)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    figure.suptitle(title, fontsize=10)
    return _save(figure, path)


def breakaway_grid(path, time, cases, *, title):
    """Fig. 10; `cases`: list of (case title, [(label, acceleration / PGA)])."""
    figure, axes = _figure(2, 2, size=(10, 7))
    for ax, (case, series) in zip(axes.ravel(), cases):
        for label, values in series:
            ax.plot(time, values, lw=1.0, label=label)
        ax.set_title(case, fontsize=9)
        ax.set_xlabel("time [s]")
        ax.set_ylabel("total acceleration / peak ground acc.")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    figure.suptitle(title, fontsize=10)
    return _save(figure, path)


def fourier(path, series, *, title, max_frequency=25.0):
    """Fourier amplitudes; `series`: list of (label, frequency [Hz], amplitude)."""
    figure, axes = _figure(size=(7.5, 4.0))
    ax = axes[0, 0]
    for label, frequency, amplitude in series:
        keep = frequency <= max_frequency
        ax.plot(frequency[keep], amplitude[keep], lw=1.0, label=label)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("Fourier amplitude [in/s]")
    ax.set_yscale("log")
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return _save(figure, path)


def as_numpy(x):
    return np.asarray(x, dtype=float)
