"""Plot of a bearing fit: measured and fitted loops with the residual below each."""

import math
import textwrap

import numpy as np

from ..units import INCH, KIP
from ._parameter_units import PARAMETER_SYMBOLS, parameter_unit


def plot_fit(path, fit, *, length=("in", INCH), force=("kip", KIP), title: str = "") -> None:
    """`fit_figure` written to `path` (PNG)."""
    fig = fit_figure(fit, length=length, force=force, title=title)
    import matplotlib.pyplot as plt

    fig.savefig(path, dpi=110)
    plt.close(fig)


def fit_figure(fit, *, length=("in", INCH), force=("kip", KIP), title: str = ""):
    """Measured (grey, solid) and fitted (black, dashed) force-displacement loops of every
    record of `fit` (a `BearingFit` of `identification.bearing_fit`: `records`, `parameters`,
    `std_errors`, `free`, `converged`), with the residual against time below (PNG).

    **Arguments:** `fit`; `length`, `force`: (name, SI factor) of the axes' units;
    `title`: the inputs (records, normal load) to state above the fitted values, each with
    its standard error, or "(not identified)" for a constant the records do not determine
    (`not_identified`).

    **Returns:** the matplotlib figure (open; `plot_fit` saves and closes it).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = []  # (record, displacement, measured, fitted, axis name)
    for rec in fit.records:
        measured, fitted = np.asarray(rec.measured), np.asarray(rec.fitted)
        uy = getattr(rec, "uy", None)
        if uy is None:
            panels.append((rec, np.asarray(rec.ux), measured, fitted, "x"))
            continue
        n = np.size(rec.ux)  # biaxial: the residual stacks fx and fy
        panels.append((rec, np.asarray(rec.ux), measured[:n], fitted[:n], "x"))
        panels.append((rec, np.asarray(uy), measured[n:], fitted[n:], "y"))
    fig, axes = plt.subplots(2, len(panels), figsize=(max(6.0, 5.5 * len(panels)), 7.2),
                             squeeze=False, gridspec_kw=dict(height_ratios=[2.2, 1.0]))
    for k, (rec, u, measured, fitted, axis) in enumerate(panels):
        top, bottom = axes[0, k], axes[1, k]
        top.plot(u / length[1], measured / force[1], color="0.55", lw=1.6, label="measured")
        top.plot(u / length[1], fitted / force[1], color="k", ls="--", lw=1.0, label="fitted model")
        top.set_xlabel(f"displacement u{axis} [{length[0]}]")
        top.set_ylabel(f"friction force F{axis} [{force[0]}]")
        top.set_title(f"{rec.name} ({axis}): normalised RMS error {rec.nrmse:.3g}", fontsize=9)
        top.legend(loc="best", fontsize=8)
        top.grid(alpha=0.3)
        x = rec.time if rec.time is not None else np.arange(np.size(measured))
        bottom.plot(x, (fitted - measured) / force[1], color="k", lw=0.7)
        bottom.axhline(0.0, color="0.5", lw=0.6)
        bottom.set_xlabel("time [s]" if rec.time is not None else "point")
        bottom.set_ylabel(f"model - measured, F{axis} [{force[0]}]")
        bottom.grid(alpha=0.3)
    values = "; ".join(_value(name, fit, length) for name in fit.free)  # a constant not identified is marked
    status = "converged" if fit.converged else "NOT CONVERGED"
    text = (f"{title}\n" if title else "") + f"fitted: {values} ({status})"
    width = int(11 * fig.get_figwidth())  # characters of 9 pt text that fit across the figure
    fig.suptitle("\n".join(line for part in text.split("\n") for line in textwrap.wrap(part, width)),
                 fontsize=9)
    fig.tight_layout()
    return fig


def _value(name, fit, length) -> str:
    symbol = PARAMETER_SYMBOLS.get(name, (name, None))[0]
    unit, factor = parameter_unit(name, length)
    unit = f" {unit}" if unit else ""
    value, error = fit.parameters[name], fit.std_errors.get(name)
    if value is None or not math.isfinite(value):
        return f"{symbol} = n/a"
    shown = f"{symbol} = {value / factor:.4g}"
    if not_identified(name, fit):
        return shown + unit + " (not identified)"
    return shown + f" +- {error / factor:.2g}" + unit


def not_identified(name: str, fit) -> bool:
    """Whether the records do not determine the fitted constant `name` of `fit`: its standard
    error is missing or not finite, or a warning of the fit names it as not identifiable
    ('breakaway_ratio: not identifiable; ...', 'rate_a, delta_f: not identifiable; ...')."""
    error = fit.std_errors.get(name)
    if error is None or not math.isfinite(error):
        return True
    for warning in fit.warnings:
        names, _, reason = warning.partition(": ")
        if "identifiable" in reason.split(";")[0] and name in (n.strip() for n in names.split(",")):
            return True
    return False
