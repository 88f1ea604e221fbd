"""Plot of a bearing fit: measured and fitted loops with the residual below each."""

import math
import textwrap

import numpy as np

from ..units import INCH, KIP
from ._parameter_units import PARAMETER_SYMBOLS, parameter_unit


def plot_fit(path, fit, *, length=("in", INCH), force=("kip", KIP), title: str = "") -> None:
    """Measured (grey, solid) and fitted (black, dashed) force-displacement loops of every
    record of `fit` (a `BearingFit` of `identification.bearing_fit`: `records`, `parameters`,
    `std_errors`, `free`, `converged`), with the residual against time below (PNG).

    **Arguments:** `path`; `fit`; `length`, `force`: (name, SI factor) of the axes' units;
    `title`: the inputs (records, normal load) to state above the fitted values.
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
    values = "; ".join(_value(name, fit, length) for name in fit.free)
    status = "converged" if fit.converged else "NOT CONVERGED"
    text = (f"{title}\n" if title else "") + f"fitted: {values} ({status})"
    width = int(11 * fig.get_figwidth())  # characters of 9 pt text that fit across the figure
    fig.suptitle("\n".join(line for part in text.split("\n") for line in textwrap.wrap(part, width)),
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _value(name, fit, length) -> str:
    symbol = PARAMETER_SYMBOLS.get(name, (name, None))[0]
    unit, factor = parameter_unit(name, length)
    unit = f" {unit}" if unit else ""
    value, error = fit.parameters[name], fit.std_errors.get(name)
    if value is None or not math.isfinite(value):
        return f"{symbol} = n/a"
    shown = f"{symbol} = {value / factor:.4g}"
    if error is not None and math.isfinite(error):
        shown += f" +- {error / factor:.2g}"
    return shown + unit
