"""The diagnosis report: plots of residuals and candidate effects, and report.md."""

import pathlib

import numpy as np

from teflon_jax.report import residual_maps

from ._diagnostics import (
    REGRESSOR_LABELS,
    friction_residual,
    half_cycle_index,
    locate_residual,
    noise_estimate,
    regressors,
)
from ._effects import EFFECTS
from ._result import gain_text


def write_plots(result, directory, *, length=("mm", 1e-3)) -> dict:
    """Write the diagnostic figures of a `DiscoveryResult` into `directory`, displacements in
    `length` = (unit name, its size in m).

    **Returns:** figure name -> file name (relative to `directory`).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt


    directory = pathlib.Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    data = result.data
    t = np.asarray(data.time)
    ux = np.asarray(data.ux)
    measured = np.asarray(data.force)
    normal = np.asarray(data.normal)
    base, final = result.forces["baseline"], result.forces["final"]
    files = {}

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
    for ax, model, title in (
        (axes[0], base, f"baseline ({result.baseline}): nrmse {result.nrmse_initial:.3f}"),
        (
            axes[1],
            final,
            (
                f"final (+{', '.join(result.effects_added) or 'nothing'}): "
                f"nrmse {result.nrmse_final:.3f}"
            ),
        ),
    ):
        ax.plot(ux / length[1], measured / normal, color="0.6", lw=1.2, label="measured")
        ax.plot(ux / length[1], model / normal, color="C3", lw=1.0, label="model")
        ax.set_xlabel(f"displacement ux [{length[0]}]")
        ax.set_title(title, fontsize=9)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("friction force / normal load [-]")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(directory / "loops.png", dpi=110)
    plt.close(fig)
    files["loops"] = "loops.png"

    fig, axes = plt.subplots(2, 1, figsize=(11, 5.5), sharex=True)
    axes[0].plot(t, measured / normal, color="0.6", lw=1.0, label="measured")
    axes[0].plot(t, base / normal, color="C0", lw=0.9, label="baseline")
    axes[0].plot(t, final / normal, color="C3", lw=0.9, label="final")
    axes[0].set_ylabel("F / N [-]")
    axes[0].legend(fontsize=8, ncol=3)
    axes[1].plot(t, (measured - base) / normal, color="C0", lw=0.8, label="baseline")
    axes[1].plot(t, (measured - final) / normal, color="C3", lw=0.8, label="final")
    axes[1].set_ylabel("(measured - model) / N [-]")
    axes[1].set_xlabel("time [s]")
    axes[1].legend(fontsize=8)
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(directory / "history.png", dpi=110)
    plt.close(fig)
    files["history"] = "history.png"

    sim = _baseline_simulation(result)
    hc = half_cycle_index(ux)
    reg = regressors(data, sim, hc)
    d_mu, sliding = friction_residual(data, sim, base)
    keys = ["speed", "load", "heat", "travel", "time", "half_cycle"]
    if np.ptp(reg["load"]) == 0:  # constant normal load: show the sliding direction instead
        keys[1] = "direction"
        jitter = np.random.default_rng(0).uniform(-0.15, 0.15, reg["direction"].size)
        reg = dict(reg, direction=reg["direction"] + jitter)
    v = np.asarray(data.velocity)
    fig = residual_maps(
        [(REGRESSOR_LABELS[key], reg[key]) for key in keys], d_mu,
        [(sliding & (v > 0), "C0", "+x"), (sliding & (v < 0), "C1", "-x")],
        ylabel="friction residual d_mu (baseline) [-]",
        title="Baseline friction residual (measured - model) / (N Z) while sliding, "
        "against the regressors of the candidate effects", length=length)
    fig.savefig(directory / "residual_maps.png", dpi=110)
    files["residual_maps"] = "residual_maps.png"
    return files


def _baseline_simulation(result) -> dict:
    """The baseline model's histories (numpy) at the fitted baseline parameters."""
    from ._augmented import PARAMETERS, active_mask, simulate_augmented

    params = {p.name: result.baseline_parameters.get(p.name, p.initial) for p in PARAMETERS}
    simulated = simulate_augmented(params, result.data, active_mask(result.baseline_effects))
    return {k: np.asarray(v) for k, v in simulated.items()}


def write_report(result, directory, *, record_name: str = "record",
                 length=("mm", 1e-3), mixture=None) -> pathlib.Path:
    """Write `directory/report.md` (with the figures of `write_plots`, displacements in
    `length` = (unit name, its size in m)) for a `DiscoveryResult`, with the table of the
    compositions' weights of a `DiscoveryMixture` when given."""
    directory = pathlib.Path(directory)
    files = write_plots(result, directory, length=length)
    data = result.data
    sim = _baseline_simulation(result)
    where = locate_residual(
        data, sim, result.forces["baseline"], half_cycle_index(np.asarray(data.ux))
    )
    lines = _summary_lines(result, record_name)
    lines += _step_lines(result)
    lines += _parameter_lines(result)
    lines += _residual_location_lines(where)
    lines += _mixture_lines(mixture)
    lines += ["", "## Figures", ""]
    lines += [f"![{name}]({fname})" for name, fname in files.items()]
    lines += _heating_note(result.info)
    path = directory / "report.md"
    path.write_text("\n".join(lines) + "\n")
    return path


def _mixture_lines(mixture) -> list:
    """The compositions weighed by BIC (`DiscoveryMixture`), heaviest first; none without one."""
    if mixture is None:
        return []
    lines = ["", "## Compositions weighed by their evidence", "",
             f"Every composition the search fitted, with w = exp(-dBIC / 2) normalised over all of "
             f"them (BIC = n_eff ln(SSR / n) + p ln(n_eff), n_eff = {mixture.effective_samples:.1f} "
             f"of the chosen model's residual); those of weight {mixture.min_weight:g} or more, with "
             "draws of their constants, make the bearing file's mixture.", "",
             "| composition | p | nrmse | dBIC | weight | in the mixture |", "|---|---|---|---|---|---|"]
    for row in mixture.table:
        name = " + ".join(row["effects"]) or "baseline"
        lines.append(f"| {'**' + name + '**' if row['selected'] else name} | {row['free_parameters']} "
                     f"| {row['nrmse']:.4f} | {row['delta_bic']:.2f} | {row['weight']:.3g} | "
                     f"{'yes' if row['in_mixture'] else 'no'}{': ' + row['note'] if row['note'] else ''} |")
    return lines


def _summary_lines(result, record_name: str) -> list:
    """Title, conclusion, nrmse and the decision rule, up to the Steps heading."""
    data = result.data
    lines = [f"# Model discovery: {record_name}", ""]
    lines += [
        f"- baseline: `{result.baseline}`; samples used: {data.n_samples} "
        + (
            "(all samples)"
            if result.info.decimation == 1
            else f"(one in {result.info.decimation} of the record's samples)"
        ),
        f"- conclusion: **{'no missing effect' if not result.effects_added else ', '.join(result.effects_added)}**",
        f"- nrmse: {result.nrmse_initial:.4f} (baseline) -> {result.nrmse_final:.4f} (final)",
        f"- runtime: {result.runtime_s:.1f} s (including compilation)",
        "",
        "nrmse = RMS(model - measured force) / RMS(measured force).",
        "",
        _remaining_residual_note(result),
        "",
        "## Decision rule",
        "",
        (
            "Each round refits the model with every candidate effect added. A candidate is "
            "accepted when its BIC drop (charged with ln(n_eff) per parameter, n_eff the "
            "effective number of independent residual samples) exceeds 10 ('very strong' on the "
            "Kass & Raftery scale) and its prediction error on held-out cycles falls (two-fold "
            "blocked cross-validation)."
        ),
        "",
        "## Steps",
        "",
    ]
    return lines


def _step_lines(result, equation=lambda effect: EFFECTS[effect].equation, naming: bool = True,
                always_skipped: bool = False) -> list:
    """Each added effect of a discovery `result` with its evidence (`equation(effect)` its law;
    with `naming`, the evidence that it is this effect rather than the runner-up), the refused
    candidates and those not considered (a line even when none, with `always_skipped`)."""
    lines = []
    if not result.steps:
        lines.append("No candidate earned its parameters: no missing effect.")
    for k, step in enumerate(result.steps, start=1):
        e = step.evidence
        lines += [
            f"### {k}. {step.effect} — {e['confidence']} evidence",
            "",
            f"{equation(step.effect)}",
            "",
            (
                f"nrmse {step.nrmse_before:.4f} -> {step.nrmse_after:.4f}; "
                f"delta_bic {e['delta_bic']:.1f} (n_eff {e['n_eff']:.0f}); "
                f"held-out gain {gain_text(e, '.1f')}; "
                f"residual correlation with its regressor {e['residual_correlation']:+.2f}"
            ),
            "",
        ]
        if naming:
            lines += [
                (
                    f"Naming: {e['naming_confidence']} evidence that it is {step.effect} rather "
                    f"than {e['runner_up'] or 'nothing'} "
                    f"(delta_bic margin {e['margin_over_runner_up']:.1f})."
                ),
                "",
            ]
        lines += _candidate_table(step.candidates)
    if result.final_round:
        lines += ["", "### Candidates refused in the last round", ""]
        lines += _candidate_table(result.final_round)
    if result.skipped or always_skipped:
        lines += [
            "",
            "Not considered: " + "; ".join(f"{k} ({v})" for k, v in result.skipped.items()),
        ]
    return lines


def _parameter_lines(result) -> list:
    """The table of fitted parameters with their standard errors and units."""
    from ._augmented import PARAMETERS

    units = {p.name: p.unit for p in PARAMETERS}
    lines = [
        "",
        "## Fitted parameters (SI)",
        "",
        "| parameter | value | standard error | unit |",
        "|---|---|---|---|",
    ]
    lines += [
        f"| {k} | {v:.6g} | {result.std_errors.get(k, float('nan')):.2g} | "
        f"{units.get(k, '-')} |"
        for k, v in result.parameters.items()
    ]
    lines += [
        "",
        (
            "Standard errors: asymptotic, sigma^2 (J^T J)^-1 inflated by n / n_eff for "
            "correlated residuals; 0 marks a parameter held at a known value."
        ),
    ]
    return lines


def _residual_location_lines(where: dict) -> list:
    """The table of where the baseline residual sits (`locate_residual`)."""
    lines = [
        "",
        "## Where the baseline residual sits",
        "",
        "| region | share of samples | share of residual energy | concentration |",
        "|---|---|---|---|",
    ]
    lines += [
        f"| {k} | {v['share_of_samples']:.2f} | {v['share_of_residual']:.2f} | "
        f"{v['concentration']:.2f} |"
        for k, v in where.items()
    ]
    return lines


def _heating_note(info) -> list:
    """How the heating candidate got its temperature: measured, or an assumed contact area."""
    if info.measured_temperature:
        return [
            "",
            (
                "Heating: the record has a temperature column; the heating candidate uses the "
                "measured temperature (k_T of Kumar et al. 2015 relative to its first value) "
                "instead of the heat-flux model."
            ),
        ]
    if info.contact_area_assumed:
        return [
            "",
            (
                "Note: the record states no contact area; the heating candidate assumed a "
                "contact pressure of 1000 psi (its heat_scale absorbs the difference)."
            ),
        ]
    return []


def _candidate_table(evidence: dict) -> list:
    lines = [
        "| candidate | delta_bic | confidence | held-out gain | nrmse after | corr |",
        "|---|---|---|---|---|---|",
    ]
    for name, e in sorted(evidence.items(), key=lambda kv: -kv[1]["delta_bic"]):
        lines.append(
            f"| {name} | {e['delta_bic']:.1f} | {e['confidence']} | {gain_text(e, '.1f')} | "
            f"{e['nrmse_after']:.4f} | {e['residual_correlation']:+.2f} |"
        )
    return lines


def _remaining_residual_note(result) -> str:
    from ._diagnostics import ljung_box

    residual = np.asarray(result.data.force) - result.forces["final"]
    scale = float(np.sqrt(np.mean(np.asarray(result.data.force) ** 2)))
    noise = noise_estimate(residual) / scale
    test = ljung_box(residual)
    status = getattr(result, "fit_convergence", {}) or {}
    fits_note = ""
    if status.get("unconverged"):
        fits_note = (f" {status['unconverged']} of {status['fits']} inner fits did not converge "
                     f"within {status['iteration_limit']} iterations; their evidence is weaker.")
    stated = (f"Ljung-Box test of the residual over {test['lags']} lags: Q = {test['q']:.1f}, "
              f"p = {test['p_value']:.3g}")
    if test["white"]:
        return (
            f"Remaining residual: nrmse {result.nrmse_final:.4f} against a scatter of "
            f"{noise:.4f} from sample to sample; {stated} (>= 0.01): no evidence of structure, "
            "it is consistent with white measurement noise." + fits_note
        )
    return (
        f"Remaining residual: nrmse {result.nrmse_final:.4f} against a sample-to-sample scatter "
        f"of {noise:.4f}; {stated} (< 0.01): the residual is structured (correlated in time), "
        "so the final model still misses something that no candidate describes (see the "
        "residual maps)." + fits_note
    )
