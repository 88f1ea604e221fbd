"""The diagnosis report of a triple or double friction pendulum (`SeriesDiscoveryResult`):
report.md with the sections of the flat slider's report, and the loops and force histories
of the baseline and final models."""

import pathlib

import numpy as np

from ._report import _step_lines
from ._series_discovery import SERIES_EFFECTS


def write_series_plots(result, directory, *, length=("mm", 1e-3)) -> dict:
    """`loops.png` (measured and model F / N against displacement, baseline and final) and
    `history.png` (F / N and the residual against time) in `directory`; name -> file."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    directory = pathlib.Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    p = result.problem
    t, u, measured, load = p.time, np.asarray(p.path), p.force, p.load
    base, final = result.forces["baseline"], result.forces["final"]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
    for ax, model, title in (
            (axes[0], base, f"baseline (series fit): nrmse {result.nrmse_initial:.3f}"),
            (axes[1], final, f"final (+{', '.join(result.effects_added) or 'nothing'}): "
                             f"nrmse {result.nrmse_final:.3f}")):
        ax.plot(u / length[1], measured / load, color="0.6", lw=1.2, label="measured")
        ax.plot(u / length[1], model / load, color="C3", lw=1.0, label="model")
        ax.set(xlabel=f"displacement [{length[0]}]", title=title)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("force / normal load [-]")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(directory / "loops.png", dpi=110)
    plt.close(fig)
    fig, axes = plt.subplots(2, 1, figsize=(11, 5.5), sharex=True)
    axes[0].plot(t, measured / load, color="0.6", lw=1.0, label="measured")
    axes[0].plot(t, base / load, color="C0", lw=0.9, label="baseline")
    axes[0].plot(t, final / load, color="C3", lw=0.9, label="final")
    axes[1].plot(t, (measured - base) / load, color="C0", lw=0.8, label="baseline")
    axes[1].plot(t, (measured - final) / load, color="C3", lw=0.8, label="final")
    axes[0].set_ylabel("F / N [-]")
    axes[1].set(ylabel="(measured - model) / N [-]", xlabel="time [s]")
    for ax in axes:
        ax.legend(fontsize=8, ncol=3)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(directory / "history.png", dpi=110)
    plt.close(fig)
    return {"loops": "loops.png", "history": "history.png"}


def _parameter_lines(result) -> list:
    lines = ["", "## Fitted constants (SI)", "", "| constant | value | standard error |",
             "|---|---|---|"]
    for name, value in result.parameters.items():
        error = result.std_errors.get(name)
        lines.append(f"| {name} | {value:.6g} | "
                     + ("held" if error is None else f"{error:.2g}") + " |")
    lines += ["", "Held constants: " + ("; ".join(f"{k} ({v})" for k, v in result.held.items())
                                          or "none")]
    p = result.problem
    if "heating" in result.effects_added and p.pressure_assumed:
        lines += ["", f"Heating: no contact pressure stated for {', '.join(p.pressure_assumed)} (start "
                      "file or record); 1000 psi assumed, and heat_scale absorbs the difference "
                      "(the temperature rise scales with heat_scale p)."]
    return lines


def write_series_report(result, directory, *, record_name: str = "record",
                        length=("mm", 1e-3)) -> pathlib.Path:
    """Write `directory/report.md` and the figures (`write_series_plots`) of a
    `SeriesDiscoveryResult`."""
    directory = pathlib.Path(directory)
    files = write_series_plots(result, directory, length=length)
    p = result.problem
    lines = [f"# Model discovery: {record_name}", "",
             f"- isolator: {result.isolator}; baseline: the series fit (`{result.baseline}`); "
             f"samples used: {p.time.size}"
             + ("" if p.decimation == 1 else f" (one in {p.decimation})"),
             "- conclusion: **" + (", ".join(result.effects_added) or "no missing effect") + "**",
             f"- nrmse: {result.nrmse_initial:.4f} (baseline) -> {result.nrmse_final:.4f} (final)",
             f"- runtime: {result.runtime_s:.1f} s (including compilation)", "",
             "nrmse = RMS(model - measured force) / RMS(measured force).", "",
             "## Decision rule", "",
             "Each round refits the model with every candidate effect added. A candidate is "
             "accepted when its BIC drop (charged with ln(n_eff) per parameter, n_eff the "
             "effective number of independent residual samples) exceeds the threshold (10, 'very "
             "strong' on the Kass & Raftery scale) and its prediction error on held-out cycles "
             "falls (two-fold blocked cross-validation).", "", "## Steps", ""]
    lines += _step_lines(result, SERIES_EFFECTS.__getitem__, naming=False, always_skipped=True)
    lines += _parameter_lines(result)
    lines += ["", "## Figures", ""] + [f"![{n}]({f})" for n, f in files.items()]
    path = directory / "report.md"
    path.write_text("\n".join(lines) + "\n")
    return path
