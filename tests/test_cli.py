"""The `teflon-jax` command end to end: simulate a test, write the CSV, fit it back."""

import json

import numpy as np
import pytest

import teflon_jax as tj
from teflon_jax.cli._main import _parser, main
from teflon_jax.units import KIP


def test_all_subcommands_are_wired():
    parser = _parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    assert set(sub.choices) == {"simulate-test", "reproduce", "fit", "diagnose", "montecarlo", "design"}


def test_simulate_then_fit_round_trip(tmp_path):
    csv = tmp_path / "t191.csv"
    status = main([
        "simulate-test", "--ptfe", "UF", "--pressure", "1000psi", "--direction", "T",
        "--amplitude", "0.5in", "--frequency", "0.03Hz", "--cycles", "3",
        "--normal-load", "78.5kip", "--breakaway", "3", "--out", str(csv),
        "--samples-per-cycle", "600",
    ])
    assert status == 0
    record = tj.read_test_record(csv)
    assert record.normal_load[0] == pytest.approx(78.5 * KIP, rel=1e-8)
    assert record.metadata["direction"] == "T"
    mu = np.abs(record.fx) / record.normal_load
    assert mu.max() == pytest.approx(3 * (0.1420 - 0.1181), rel=0.02)  # breakaway peak of No. 191
    out = tmp_path / "fit.json"
    status = main(["fit", str(csv), "--json", str(out)])
    fitted = json.loads(out.read_text())
    assert status == 0 and fitted["converged"]
    p = fitted["parameters"]
    # At 0.09 in/s the test never reaches the high-speed plateau: only f_min = f_max - Df and b
    # are identifiable, and the fitter must say that f_max and Df are not separated.
    assert p["f_max"] - p["delta_f"] == pytest.approx(0.1420 - 0.1181, rel=0.02)
    assert p["breakaway_ratio"] == pytest.approx(3.0, rel=0.02)
    assert any("f_max" in w and "delta_f" in w for w in fitted["warnings"])


@pytest.mark.parametrize(
    "argv, message",
    [
        (["simulate-test", "--amplitude", "4Hz"], "--amplitude: 'Hz' is a unit of frequency"),
        (["simulate-test", "--ptfe", "PEEK"], "--ptfe: unknown PTFE type 'PEEK'"),
        (["simulate-test", "--pressure", "9000psi"], "--pressure: 9000 psi is outside"),
        (["simulate-test", "--yield-disp", "0in"], "--yield-disp: must be > 0"),
        (["simulate-test", "--breakaway", "0.8"], "--breakaway: must be >= 1"),
        (["simulate-test", "--frequency", "0Hz"], "--frequency: must be > 0"),
        (["simulate-test", "--normal-load=-2kip"], "--normal-load: must be > 0"),
        (["simulate-test", "--normal-load", "5in"], "--normal-load: 'in' is a unit of length"),
        (["simulate-test", "--pattern", "circle"], "--pattern: unknown pattern 'circle'"),
    ],
)
def test_bad_options_exit_with_a_message_naming_the_option(argv, message, capsys, tmp_path):
    status = main(argv + ["--out", str(tmp_path / "x.csv")])
    assert status == 2
    assert message in capsys.readouterr().err


def test_cpu_devices_option_is_checked(capsys):
    with pytest.raises(SystemExit):
        main(["--cpu-devices", "0", "montecarlo", "--motions", "2"])
    assert "--cpu-devices: must be >= 1" in capsys.readouterr().err
    # JAX already runs in this process: an explicit device count can no longer be applied,
    # and the command says so instead of running on a different layout than asked for.
    import jax

    jax.devices()
    assert main(["--cpu-devices", "2", "montecarlo", "--motions", "2"]) == 2
    assert "--cpu-devices" in capsys.readouterr().err


def test_montecarlo_command_uses_one_device_per_core(tmp_path):
    import os
    import subprocess
    import sys

    env = {k: v for k, v in os.environ.items() if k != "XLA_FLAGS"}
    out = subprocess.run(
        [sys.executable, "-m", "teflon_jax.cli", "--cpu-devices", "2", "montecarlo", "--motions", "4",
         "--duration", "4", "--strong-motion", "1", "--no-progress", "--json", str(tmp_path / "mc.json")],
        env=dict(env, JAX_PLATFORMS="cpu"), capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-2000:]
    payload = json.loads((tmp_path / "mc.json").read_text())
    assert payload["devices"] == 2
    assert payload["n_motions"] == 4


def test_montecarlo_command_reports_runs_that_did_not_converge(tmp_path, capsys, monkeypatch):
    # A run with a step whose Newton solve failed must make the command fail (status 1) with
    # a message, not print its untrustworthy peaks as a success; the results are still written.
    # The failure is real: the structure the command builds gets one Newton iteration per
    # step (isolated_structure's newton_iterations option), too few for any sliding step.
    import functools

    import teflon_jax.systems as systems

    monkeypatch.setattr(systems, "isolated_structure",
                        functools.partial(systems.isolated_structure, newton_iterations=1))
    status = main(["montecarlo", "--motions", "3", "--duration", "4", "--strong-motion", "1",
                   "--no-progress", "--json", str(tmp_path / "mc.json")])
    assert status == 1
    assert "3 of 3 runs" in capsys.readouterr().err
    summary = json.loads((tmp_path / "mc.json").read_text())
    assert summary["all_converged"] is False
    assert summary["percentiles"]["n_converged"] == 0 and summary["percentiles"]["base_disp_m"]["n"] == 0
