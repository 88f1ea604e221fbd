"""`teflon-jax reproduce`: rerun Figs. 3-11 of Constantinou, Mokha & Reinhorn (1990).

Writes, under `out_dir`: one PNG per figure, the numbers behind each as CSV, `report.md`
(each statement of the paper, in our words, beside what we compute) and `summary.json`.
This is the I/O layer: it loads records, runs the simulations (the long ones as vmapped
batches), plots and writes files. Units: SI inside, the paper's inches, kips and psi in the
outputs.
"""

import dataclasses
import json
import pathlib

import jax
import numpy as np

from ..bearing import paper_bearing
from ..excitation import FigureEightMotion, SineMotion, intensity_measures
from ..formats import load_record
from ..systems import imposed_path_test
from ..tables import friction_table
from ..units import INCH, KIP, PSI, STANDARD_GRAVITY
from . import _figures as figures
from ._constants import (
    FULL_PERIODS,
    QUICK_PERIODS,
    SPECIMEN_LOAD,
    STRUCTURE_TIME_STEP,
    _columns,
)
from ._statements import _convergence, _report, _statements
from ._structure_figures import _fig7_9, _fig10, _fig11


def _load_records(missing):
    """The El Centro and SCT records that can be read; `missing` gets key -> reason for the rest."""
    records = {}
    for key in ("elcentro", "sct"):
        try:
            motion = load_record(key, fallback=True)
        except (FileNotFoundError, ValueError, OSError) as error:
            missing[key] = str(error)
            continue
        measures = intensity_measures(motion)
        records[key] = {
            "motion": motion,
            "file": pathlib.Path(str(motion.source)).name,
            "name": motion.name,
            "pga_g": motion.pga / STANDARD_GRAVITY,
            "pgv_in_s": measures.pgv / INCH,
            "pgd_in": measures.pgd / INCH,
            "duration_s": motion.duration,
            "baseline": measures.baseline,
        }
    return records


def _loop_figures(out, results):
    """Figs. 3-4: uniaxial tests 62, 75 (UF, 1000 psi, parallel) and 191 (perpendicular, b = 3)."""
    uf_p, _ = friction_table("UF", "P").at(1000 * PSI)
    uf_t, _ = friction_table("UF", "T").at(1000 * PSI)
    cases = {
        "test62": (paper_bearing(uf_p), SineMotion(1 * INCH, 0.16), SPECIMEN_LOAD),
        "test75": (paper_bearing(uf_p), SineMotion(4 * INCH, 0.6), SPECIMEN_LOAD),
        "test191": (paper_bearing(uf_t, breakaway_ratio=3.0), SineMotion(0.5 * INCH, 0.03), 78.5 * KIP),
    }
    curves, stats = [], {}
    for name, (bearing, motion, load) in cases.items():
        r = imposed_path_test(bearing, motion, load)
        u, f = np.asarray(r.ux) / INCH, np.asarray(r.fx) / np.asarray(r.normal_load)
        z = np.asarray(r.z).reshape(u.size, -1)[:, 0]
        _columns(out / f"fig3_4_{name}.csv", {"time_s": r.time, "u_in": u, "v_in_s": np.asarray(r.vx) / INCH,
                                              "friction_over_load": f, "z": z})
        sliding = np.abs(z) > 0.98
        coefficient = np.abs(f[sliding])
        later = np.asarray(r.time) > motion.duration / 3  # after the first (breakaway) excursion
        du = np.abs(np.gradient(u))
        near_max = np.abs(f) >= 0.9 * np.abs(f[sliding]).max()
        stats[name] = {
            "coefficient_min": float(coefficient.min()),
            "coefficient_max": float(coefficient.max()),
            "coefficient_max_later": float(np.abs(f[sliding & later]).max()),
            "share_near_max": float(du[sliding & near_max].sum() / du[sliding].sum()),
            "f_max": float(bearing.friction.f_max),
            "f_min": float(bearing.friction.f_min),
        }
        amplitude, frequency = float(motion.amplitude) / INCH, float(motion.frequency)
        label = (f"test No. {name[4:]}: {amplitude:g} in at {frequency:g} Hz, "
                 f"{'perpendicular' if name == 'test191' else 'parallel'} to lay"
                 + (", b = 3" if name == "test191" else ""))
        curves.append((label, u, f))
    figures.loops(out / "fig3_4_loops.png", curves,
                  title="Figs. 3-4: uniaxial tests, UF PTFE at 1000 psi (Y = 0.005 in)",
                  stamp=f"Imposed sinusoids; UF PTFE, 1000 psi, Table 1: parallel f_max = "
                  f"{float(uf_p.f_max):.4f}, Df = {float(uf_p.delta_f):.4f}, a = {float(uf_p.rate_a) * INCH:.3g} s/in; "
                  f"perpendicular f_max = {float(uf_t.f_max):.4f}; Bouc-Wen Y = 0.005 in, A = 1, beta = 0.1, "
                  "gamma = 0.9.")
    results["fig3_4"] = stats


def _biaxial_figures(out, results):
    """Figs. 5-6: figure-eight motion, isotropic and anisotropic UF at 1000 psi."""
    uf_p, _ = friction_table("UF", "P").at(1000 * PSI)
    uf_t, _ = friction_table("UF", "T").at(1000 * PSI)
    stats, rows = {}, []
    for amplitude, omega in ((1.0, 1.0), (4.0, 2.77)):
        cases = []
        for tag, perpendicular in (("isotropic", None), ("anisotropic", uf_t)):
            bearing = paper_bearing(uf_p, friction_perpendicular=perpendicular)
            r = imposed_path_test(bearing, FigureEightMotion(amplitude * INCH, omega), 1.0)
            ux, uy = np.asarray(r.ux) / INCH, np.asarray(r.uy) / INCH
            fx, fy = np.asarray(r.fx), np.asarray(r.fy)
            label = ("isotropic (parallel constants in every direction)" if perpendicular is None else
                     "anisotropic (parallel along x, perpendicular along y)")
            cases.append((label, ux, uy, fx, fy))
            key = f"{tag}_U0_{amplitude:g}in"
            _columns(out / f"fig5_6_{key}.csv", {"time_s": r.time, "ux_in": ux, "uy_in": uy,
                                                 "fx_over_load": fx, "fy_over_load": fy})
            stats[key] = {
                "max_resultant_coefficient": float(np.max(np.hypot(fx, fy))),
                "max_fx": float(np.max(np.abs(fx))),
                "max_fy": float(np.max(np.abs(fy))),
            }
        figure = "Fig. 5" if amplitude == 1.0 else "Fig. 6"
        rows.append((f"{figure}, U0 = {amplitude:g} in, w = {omega:g} rad/s", cases))
    figures.figure_eight(out / "fig5_6_figure_eight.png", rows,
                         title="Figs. 5-6: figure-eight motion ux = U0 sin wt, uy = U0 sin 2wt; isotropic "
                         "(solid) and anisotropic (dashed) UF PTFE bearing at 1000 psi",
                         stamp=f"UF PTFE, 1000 psi; Table 1 parallel f_max = {float(uf_p.f_max):.4f}, "
                         f"perpendicular f_max = {float(uf_t.f_max):.4f}; Y = 0.005 in, A = 1, beta = 0.1, "
                         "gamma = 0.9; anisotropy interpolated linearly in the sliding angle.")
    stats["f_max_parallel"] = float(uf_p.f_max)
    stats["f_max_perpendicular"] = float(uf_t.f_max)
    results["fig5_6"] = stats


def skipped_figures(missing: dict, *, quick: bool) -> list[dict]:
    """The figures (or parts) that cannot be made without the records in `missing` (key ->
    reason): [{"figure": ..., "record": ..., "reason": ...}], in the order of the paper."""
    parts = {"elcentro": ["Figs. 7-9", "Fig. 11 (El Centro)"], "sct": ["Fig. 11 (SCT)"]}
    if not quick:
        parts["elcentro"].append("time-step convergence check (El Centro)")
        parts["sct"].append("time-step convergence check (SCT)")
    return [{"figure": figure, "record": key, "reason": reason}
            for key, reason in missing.items() for figure in parts[key]]


def reproduce(out_dir, *, progress=None, quick: bool = False, header: dict | None = None) -> dict:
    """Regenerate Figs. 3-11 of the paper as PNG + CSV, `report.md` and `summary.json`.

    **Arguments:**

    - `out_dir`: folder to write to (created if missing).
    - `progress`: `None`, or a callable `progress(stage, done, total)` told after each of the
      8 stages (the command line draws a bar with it).
    - `quick`: coarse T_b grid for Fig. 11 and no time-step convergence check (for tests).
    - `header`: entries `summary.json` starts with (the command line gives its version, command
      line and inputs); none by default.

    **Returns:** the summary dict written to `summary.json`; its `"skipped"` lists each figure
    (or part) that could not be made, with the reason (a record that could not be read).
    """
    out = pathlib.Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    missing: dict[str, str] = {}
    results: dict = {}
    stages = iter(range(1, 9))

    def steps(text):
        done = next(stages)
        if progress is not None:
            progress(text, done, 8)

    records = _load_records(missing)
    skipped = skipped_figures(missing, quick=quick)
    notes = [f"{s['figure']} skipped: {s['reason']}" for s in skipped]
    steps("records")
    _loop_figures(out, results)
    steps("Figs. 3-4")
    _biaxial_figures(out, results)
    steps("Figs. 5-6")
    if "elcentro" in records:
        _fig7_9(out, results, records["elcentro"])
    steps("Figs. 7-9")
    _fig10(out, results)
    steps("Fig. 10")
    if records:
        _fig11(out, results, records, QUICK_PERIODS if quick else FULL_PERIODS)
    steps("Fig. 11")
    if not quick:
        _convergence(results, records)
    steps("convergence")
    statements = _statements(results, records)
    _report(out, results, records, statements, notes, quick)
    steps("report")
    summary = {
        "records": {k: {c: v for c, v in r.items() if c != "motion"} for k, r in records.items()},
        "fig3_4": results.get("fig3_4"),
        "fig5_6": results.get("fig5_6"),
        "fig7": results.get("fig7"),
        "fig10": results.get("fig10", []),
        "fig11": results.get("fig11", []),
        "convergence": results.get("convergence"),
        "statements": statements,
        "time_step_s": STRUCTURE_TIME_STEP,
        "quick": quick,
        "skipped": skipped,
        "notes": notes,
    }
    (out / "summary.json").write_text(json.dumps({**(header or {}), **summary}, indent=1, default=_json_default))
    return summary


def _json_default(value):
    if isinstance(value, (np.floating, np.integer)):
        return value.item()
    if isinstance(value, np.bool_):
        return bool(value)
    if isinstance(value, (np.ndarray, jax.Array)):
        return np.asarray(value).tolist()
    if dataclasses.is_dataclass(value):
        return dataclasses.asdict(value)
    raise TypeError(f"not JSON serialisable: {type(value)}")
