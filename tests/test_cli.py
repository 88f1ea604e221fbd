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
    assert set(sub.choices) == {"simulate-test", "reproduce", "fit", "diagnose", "montecarlo", "design", "run"}


HEAVY = ("jax", "diffrax", "optimistix", "equinox", "numpyro", "matplotlib")


@pytest.mark.parametrize("argv", [["--help"], ["run", "--help"], ["montecarlo", "--help"],
                                  ["fit", "--help"]])
def test_help_does_not_import_jax(argv):
    # `teflon-jax --help` and a command's help answer at once: the parser is built without
    # JAX, diffrax, numpyro or matplotlib, which load when a command runs.
    import subprocess
    import sys

    code = ("import sys\nfrom teflon_jax.cli import main\ntry:\n    main(sys.argv[1:])\n"
            "except SystemExit as stop:\n    assert stop.code == 0, stop.code\n"
            f"print(sorted(m for m in {HEAVY!r} if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", code, *argv], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr
    assert "usage: teflon-jax" in done.stdout
    assert done.stdout.strip().splitlines()[-1] == "[]"


def test_python_m_teflon_jax_is_the_command():
    import subprocess
    import sys

    done = subprocess.run([sys.executable, "-m", "teflon_jax", "--help"], capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert "COMMAND" in done.stdout and "montecarlo" in done.stdout


def test_every_public_name_loads_on_first_use():
    # The package loads its sub-packages lazily; every name it lists is reachable, and the
    # re-exports are the objects of their sub-packages.
    import subprocess
    import sys

    code = (f"import sys\nimport teflon_jax as tj\nassert not set({HEAVY!r}) & set(sys.modules)\n"
            "missing = [n for n in tj.__all__ if not hasattr(tj, n)]\nprint(missing)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"
    assert tj.SlidingBearing is tj.bearing.SlidingBearing
    assert tj.sample_ground_motions is tj.excitation.sample
    assert {"monte_carlo", "load_record", "studies", "units"} <= set(dir(tj))
    with pytest.raises(AttributeError):
        tj.no_such_name  # noqa: B018


@pytest.mark.slow
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
        (["simulate-test", "--ptfe", "peek"], "--ptfe: unknown PTFE type 'peek'"),
        (["simulate-test", "--direction", "x"], "--direction: unknown direction 'x'"),
        (["simulate-test", "--pressure", "9000psi"], "--pressure: 9000psi is outside Table 1's rows"),
        (["simulate-test", "--yield-disp", "0in"], "--yield-disp: must be > 0in, got 0in."),
        (["simulate-test", "--yield-disp", "0.005"], "--yield-disp: '0.005' has no unit; write e.g. '0.005in'"),
        (["simulate-test", "--pressure", "-1000psi"], "--pressure: must be > 0psi, got -1000psi."),
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

    other = str(len(jax.devices()) + 1)
    assert main(["--cpu-devices", other, "montecarlo", "--motions", "2"]) == 2
    assert "--cpu-devices" in capsys.readouterr().err


@pytest.mark.slow
def test_montecarlo_command_uses_one_device_per_core(tmp_path):
    import os
    import subprocess
    import sys

    env = {k: v for k, v in os.environ.items() if k != "XLA_FLAGS"}
    out = subprocess.run(
        [sys.executable, "-m", "teflon_jax.cli", "--cpu-devices", "2", "montecarlo", "--motions", "4",
         "--duration", "4s", "--strong-motion", "1s", "--no-progress", "--json", str(tmp_path / "mc.json")],
        env=dict(env, JAX_PLATFORMS="cpu"), capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-2000:]
    payload = json.loads((tmp_path / "mc.json").read_text())
    assert payload["devices"] == 2
    assert payload["n_motions"] == 4


def test_montecarlo_command_reports_runs_that_did_not_converge(tmp_path, capsys):
    # A run with a step whose Newton solve failed must make the command fail (status 1) with
    # a message naming the runs, not print its untrustworthy peaks as a success; the results
    # are still written and the statistics rest on the converged runs only (here none). The
    # failure is real: with one Newton iteration per step and the equilibrium asked to rounding
    # (--newton-tolerance 0), every 10 s run has a step that needs a second iteration (at the
    # default 1e-3 Y one iteration is enough for these runs).
    status = main(["montecarlo", "--motions", "3", "--duration", "10s", "--strong-motion", "1s",
                   "--newton-iterations", "1", "--newton-tolerance", "0", "--no-progress",
                   "--json", str(tmp_path / "mc.json")])
    assert status == 1
    err = capsys.readouterr().err
    assert "3 of 3 runs" in err and "motion indices 0, 1, 2" in err
    summary = json.loads((tmp_path / "mc.json").read_text())
    assert summary["all_converged"] is False and summary["n_converged"] == 0
    assert summary["not_converged"] == [0, 1, 2]
    assert summary["statistics"]["base_disp_in"]["n"] == 0


@pytest.mark.parametrize("value", ["-1e-3", "nan", "inf", "tight"])
def test_montecarlo_newton_tolerance_refuses_bad_values(value, capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(["montecarlo", "--motions", "2", "--newton-tolerance", value])
    assert exit_info.value.code == 2
    assert "--newton-tolerance" in capsys.readouterr().err


def test_montecarlo_newton_tolerance_reaches_the_two_component_solve(tmp_path, capsys):
    """Under two components too: one iteration per step with the equilibrium asked to rounding
    (0) leaves every run short; asked to within 10 Y, the same iteration balances them all."""
    common = ["montecarlo", "--motions", "2", "--components", "2", "--duration", "6s", "--strong-motion", "1s",
              "--newton-iterations", "1", "--no-progress"]
    assert main([*common, "--newton-tolerance", "0", "--json", str(tmp_path / "tight.json")]) == 1
    assert "2 of 2 runs" in capsys.readouterr().err
    assert main([*common, "--newton-tolerance", "10", "--json", str(tmp_path / "loose.json")]) == 0
    assert json.loads((tmp_path / "loose.json").read_text())["n_converged"] == 2


def test_design_verdict_warns_on_bounds_and_fails_on_a_bad_gradient(capsys):
    from types import SimpleNamespace

    from teflon_jax.cli._design import _verdict
    from teflon_jax.studies import GRADIENT_TOLERANCE

    good = SimpleNamespace(messages=(), at_bounds=(), simulation_converged=True, optimiser_converged=True,
                           n_failed_motions=0, steps=12, converged=True, limit_met=True,
                           gradient_rel_error=GRADIENT_TOLERANCE / 10)
    assert _verdict(good, None) == 0
    assert capsys.readouterr().err == ""
    corner = SimpleNamespace(**{**vars(good), "at_bounds": ("isolation_period", "pressure")})
    assert _verdict(corner, None) == 0
    assert "optimum lies on a bound of isolation_period, pressure" in capsys.readouterr().err
    steep = SimpleNamespace(**{**vars(good), "gradient_rel_error": 0.57})
    assert _verdict(steep, None) == 1
    assert "differs from finite differences by 0.57" in capsys.readouterr().err
    diverged = SimpleNamespace(**{**vars(good), "simulation_converged": False, "n_failed_motions": 2})
    assert _verdict(diverged, None) == 1
    assert "2 motion(s) of the set did not converge" in capsys.readouterr().err
    stalled = SimpleNamespace(**{**vars(good), "optimiser_converged": False})
    assert _verdict(stalled, None) == 1
    assert "BFGS did not converge in 12 steps" in capsys.readouterr().err
    over = SimpleNamespace(**{**vars(good), "limit_met": False, "limited_disp": 0.0381})
    assert _verdict(over, SimpleNamespace(disp_limit_text="1.25in", units="us", limit_statistic="mean")) == 1
    assert "breaks --disp-limit 1.25in: its mean peak base displacement is 1.5 in" in capsys.readouterr().err
    assert _verdict(over, SimpleNamespace(disp_limit_text="1.25in", units="us", limit_statistic="p95")) == 1
    assert "its 95th-percentile peak base displacement is 1.5 in" in capsys.readouterr().err


def test_compile_cache_goes_to_the_user_cache_folder(tmp_path, monkeypatch):
    from teflon_jax.cli._main import compile_cache_dir

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert compile_cache_dir() == tmp_path / "xdg" / "teflon-jax" / "jax"
    monkeypatch.setenv("XDG_CACHE_HOME", "")
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert compile_cache_dir() == tmp_path / "home" / ".cache" / "teflon-jax" / "jax"


def test_no_compile_cache_flag_writes_no_cache(tmp_path):
    import os
    import subprocess
    import sys

    env = dict(os.environ, XDG_CACHE_HOME=str(tmp_path / "xdg"))
    command = [sys.executable, "-m", "teflon_jax.cli", "--no-compile-cache", "simulate-test",
               "--cycles", "0.5", "--samples-per-cycle", "40", "--out", str(tmp_path / "t.csv")]
    done = subprocess.run(command, env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    assert not (tmp_path / "xdg" / "teflon-jax").exists()


@pytest.mark.slow
def test_montecarlo_reports_the_rate_after_the_first_chunk(tmp_path):
    """The summary gives B3's rate (from the end of the first chunk to the end of the last)
    beside the rate over the whole run; with one chunk there is none to give."""
    for chunk, expected in (("2", "number"), ("8", "none")):
        out = tmp_path / f"mc{chunk}.json"
        assert main(["montecarlo", "--motions", "6", "--duration", "4s", "--strong-motion", "1s", "--chunk-size", chunk,
                     "--no-progress", "--json", str(out)]) == 0
        rate = json.loads(out.read_text())["records_per_s_after_first_chunk"]
        if expected == "none":
            assert rate is None
        else:
            assert rate > 0


def test_the_catalogue_is_the_one_list_of_isolators():
    # the command line, the bearing package and the design spaces read one catalogue, which
    # --help loads without JAX; each kind in series has its class, which takes its words from it
    from teflon_jax import catalogue
    from teflon_jax.bearing import (
        DESIGN_SPACES,
        ISOLATORS,
        SERIES_PENDULUMS,
        concave_surface,
        isolator_kind,
    )
    from teflon_jax.cli._isolator_flags import ISOLATORS as CLI_ISOLATORS
    from teflon_jax.cli._isolator_flags import SERIES

    assert CLI_ISOLATORS == ISOLATORS == tuple(DESIGN_SPACES) == tuple(catalogue.KINDS)
    assert tuple(SERIES) == tuple(SERIES_PENDULUMS) == catalogue.IN_SERIES
    for name, kind in SERIES.items():
        cls = SERIES_PENDULUMS[name]
        assert (cls.isolator, cls.description, len(cls.slider_names)) == (name, kind.description, kind.sliders)
    # the one-surface kinds are the values of flat sliders and of a concave surface
    assert (isolator_kind(None), isolator_kind(concave_surface(2.0))) == catalogue.ONE_SURFACE
    assert [kind.curved for kind in catalogue.KINDS.values()] == [False, True, True, True]


def test_every_command_table_is_keyed_by_the_one_list_of_isolators():
    from teflon_jax.cli import (
        _design_variables,
        _diagnose,
        _isolator_flags,
        _isolator_table,
    )

    tables = {"fit": _isolator_table.FIT_ROWS, "simulate-test": _isolator_table.TEST_ROWS,
              "diagnose": _diagnose.DIAGNOSES, "design": _design_variables.ISOLATOR_DESIGNS,
              "flags": _isolator_flags._READERS, "plan": _isolator_flags._GROUP_KEYS_REFUSED}
    for command, table in tables.items():
        assert tuple(table) == _isolator_flags.ISOLATORS, command
    # each series pendulum's facts reach its rows
    for name, facts in _isolator_flags.SERIES.items():
        assert _isolator_table.TEST_ROWS[name].model == facts.model
        assert facts.file_example in _isolator_table.TEST_ROWS[name].requires[0][1]
        assert _design_variables.ISOLATOR_DESIGNS[name].words.startswith(facts.description)
