"""What `teflon-jax run` writes: the peaks printed in the units of `--units`, the JSON of the
run (finite numbers only), the histories (`--histories`) and the plot (`--plot`: orbit, x and
y loops and displacement histories)."""

import pathlib
import sys

import numpy as np

from ._common import _write_json, output_units
from ._run_histories import write_histories
from ._run_stop import non_finite


def write_run_outputs(args, payload, histories, title, more_lines=(), problem="", *,
                      force_label="friction force") -> int:
    """`run`'s outputs: the peaks (and `more_lines`) printed, the JSON `payload` (finite
    numbers only), the histories and the plot (titled `title: records`, the loops' force
    named `force_label`); returns 0, or 1 after printing `problem` (why the run stopped early,
    `_run_stop`) when there is one."""
    units = output_units(args.units)
    bad = non_finite(payload)
    if bad:
        raise ValueError(f"--json: the results {', '.join(bad)} are not finite numbers; nothing was "
                         "written (try a smaller --time-step).")
    for line in _shown_peaks(payload["peak"], units) + list(more_lines):
        print(line)
    _write_json(args.json, payload, allow_nan=False)
    if args.histories is not None:
        write_histories(args.histories, histories)
    if args.plot is not None:
        names = [pathlib.Path(r).name for r in (args.record_x, args.record_y) if r is not None]
        plot_run(args.plot, histories, f"{title}: {' + '.join(names)}", length=units.length,
                 force=units.force, force_label=force_label)
    if problem:
        print(f"teflon-jax run: error: {problem}", file=sys.stderr)
        return 1
    return 0


def _shown_peaks(peak: dict, units) -> list:
    """Lines 'name: value unit' of the peaks (SI, keys naming their unit) in the family of
    `--units` (lengths in mm or in; ratios, radians and g as they are)."""
    name, factor = units.length
    lines = []
    for key, value in peak.items():
        label, unit, scale = key, "", 1.0
        if key.endswith("_m"):
            label, unit, scale = key[:-2], f" {name}", factor
        elif key.endswith(("_g", "_rad")):
            label, _, unit = key.rpartition("_")
            unit = f" {unit}"
        if isinstance(value, dict):
            shown = ", ".join(f"{k} {v / scale:.4g}{unit}" for k, v in value.items())
        elif isinstance(value, list):
            shown = ", ".join(f"{v / scale:.4g}" for v in value) + unit
        else:
            shown = f"{value / scale:.4g}{unit}"
        lines.append(f"peak {label.replace('_', ' ')}: {shown}")
    return lines


def plot_run(path, histories, title, *, length=("mm", 1e-3), force=("kN", 1e3),
             force_label="friction force") -> None:
    """Orbit, x and y loops and displacement histories (PNG), in the `length` and `force`
    units given as (name, SI factor); `force_label` names the bearing force of the loops (the
    liner's friction beside springs or a pendulum's N u / R, or a series isolator's whole
    force)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    h = histories
    (ln, lf), (fn, ff) = length, force
    x, y = h["base_disp_x_m"] / lf, h["base_disp_y_m"] / lf
    fig, axes = plt.subplots(2, 2, figsize=(10, 8))
    axes[0, 0].plot(x, y, lw=0.8)
    axes[0, 0].set(xlabel=f"base displacement x [{ln}]", ylabel=f"base displacement y [{ln}]", title="orbit")
    axes[0, 0].set_aspect("equal", adjustable="datalim")
    for ax, c, u in ((axes[0, 1], "x", x), (axes[1, 0], "y", y)):
        ax.plot(u, h[f"bearing_force_{c}_N"] / ff, lw=0.8)
        ax.set(xlabel=f"base displacement {c} [{ln}]", ylabel=f"{force_label} {c} [{fn}]", title=f"{c} loop")
    t = h["time_s"]
    axes[1, 1].plot(t, x, lw=0.8, label="x")
    axes[1, 1].plot(t, y, lw=0.8, label="y")
    axes[1, 1].plot(t, np.hypot(x, y), lw=0.8, label="resultant")
    axes[1, 1].set(xlabel="time [s]", ylabel=f"base displacement [{ln}]", title="histories")
    axes[1, 1].legend()
    fig.suptitle(title)
    fig.tight_layout()
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    plt.close(fig)
