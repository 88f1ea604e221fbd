"""Reports of a bearing fit: the JSON summary (SI) and a plot of measured and fitted loops.

The plot shows, for each record, the measured loop (force against displacement) with the fitted
model over it, and below it the residual (model - measured) against time (or against the point
index for a digitised loop), so that systematic misfit -- asymmetry, backlash, a wrong
breakaway -- is visible rather than averaged away in one number.
"""

import json
import math
import pathlib
import textwrap

import numpy as np

from ._plan import BearingFit


def write_fit_json(path, fit: BearingFit) -> None:
    """Write `fit.to_json_dict()` to `path` (SI units; non-finite numbers as `null`)."""
    path = pathlib.Path(path)
    path.write_text(json.dumps(fit.to_json_dict(), indent=2) + "\n", encoding="utf-8")


def plot_fit(path, fit: BearingFit, *, force_unit: str = "kN", length_unit: str = "mm") -> None:
    """Save a figure of measured and fitted loops with the residual below each.

    **Arguments:** `path` of the image (PNG, PDF, ...), the `fit`, and the display units of
    force (`N`, `kN`, `kip`) and length (`m`, `mm`, `in`).
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    from teflon_jax.units import unit_factor

    f_scale = unit_factor(force_unit, "force", where="force_unit")
    u_scale = unit_factor(length_unit, "length", where="length_unit")
    n = len(fit.records)
    fig, axes = plt.subplots(2, n, figsize=(5.5 * n, 6.5), squeeze=False,
                             gridspec_kw=dict(height_ratios=[2.2, 1.0]))
    for k, rec in enumerate(fit.records):
        top, bottom = axes[0, k], axes[1, k]
        style = "-" if rec.time is not None else "o"
        top.plot(rec.ux / u_scale, rec.measured / f_scale, style, color="0.55", lw=0.8, ms=3,
                 label="measured")
        top.plot(rec.ux / u_scale, rec.fitted / f_scale, style, color="C3", lw=1.0, ms=2,
                 label="fitted model")
        top.set_xlabel(f"displacement [{length_unit}]")
        top.set_ylabel(f"force [{force_unit}]")
        top.set_title(f"{rec.name}: nrmse {rec.nrmse:.3f}", fontsize=10)
        top.legend(loc="best", fontsize=8)
        top.grid(alpha=0.3)
        x = rec.time if rec.time is not None else np.arange(rec.measured.size)
        bottom.plot(x, (rec.fitted - rec.measured) / f_scale, style, color="C0", lw=0.6, ms=2)
        bottom.axhline(0.0, color="k", lw=0.6)
        bottom.set_xlabel("time [s]" if rec.time is not None else "point")
        bottom.set_ylabel(f"model - measured [{force_unit}]")
        bottom.grid(alpha=0.3)
    text = ", ".join(
        f"{name} = {_fmt(fit.parameters[name])}" for name in fit.free
    )
    status = "converged" if fit.converged else "NOT CONVERGED"
    fig.suptitle(textwrap.fill(f"{text}  ({status})", width=int(90 * n)), fontsize=9)
    fig.tight_layout()
    fig.savefig(pathlib.Path(path), dpi=110)
    plt.close(fig)


def _fmt(x) -> str:
    if x is None or not math.isfinite(x):
        return "n/a"
    return f"{x:.4g}"
