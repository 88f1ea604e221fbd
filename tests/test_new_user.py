"""What a new user trips over first: every output path and count is checked before any work,
with the flag and the value as typed; nonsense values are refused; a solver step that does
not divide the record step is warned about; a Monte Carlo results file says what was run."""

import argparse
import json

import numpy as np
import pytest

from teflon_jax.cli import main
from teflon_jax.cli._common import warn_time_step
from teflon_jax.cli._montecarlo import _chunk_size


def _run(capsys, *argv):
    code = main(["--no-compile-cache", *map(str, argv)])
    return code, capsys.readouterr()


def _two_column(path, dt=0.01, n=51):
    t = dt * np.arange(n)
    a = 0.3 * np.sin(2 * np.pi * t) * np.sin(np.pi * t / t[-1]) ** 2
    path.write_text("time acc\n" + "\n".join(f"{ti:.4f} {ai:.6e}" for ti, ai in zip(t, a)) + "\n")
    return path


@pytest.fixture
def folder_and_file(tmp_path):
    (tmp_path / "adir").mkdir()
    (tmp_path / "afile").write_text("")
    return tmp_path / "adir", tmp_path / "afile"


# The record files named below do not exist: the output path is refused first, so the
# command stops before it reads, fits or simulates anything.
@pytest.mark.parametrize("argv, flag", [
    (["simulate-test", "--out", "{dir}"], "--out"),
    (["simulate-test", "--plot", "{dir}"], "--plot"),
    (["fit", "nowhere.csv", "--json", "{dir}"], "--json"),
    (["run", "--record-x", "nowhere.AT2", "--json", "{dir}"], "--json"),
    (["diagnose", "nowhere.csv", "--json", "d.json", "--report", "{file}"], "--report"),
    (["fit", "nowhere.csv", "--json", "f.json", "--bayes", "{file}"], "--bayes"),
    (["montecarlo", "--motions", "2", "--json", "{dir}"], "--json"),
    (["design", "--json", "{dir}"], "--json"),
    (["reproduce", "--out", "{file}"], "--out"),
])
def test_output_paths_are_refused_before_any_work(argv, flag, folder_and_file, capsys):
    folder, file = folder_and_file
    typed = [a.format(dir=folder, file=file) for a in argv]
    code, out = _run(capsys, *typed)
    assert code == 2
    assert f"{flag} {typed[typed.index(flag) + 1]}: is a" in out.err
    assert "nowhere" not in out.err  # nothing was read
    assert list(folder.iterdir()) == []


def test_plot_needs_an_image_format(tmp_path, capsys):
    code, out = _run(capsys, "simulate-test", "--out", tmp_path / "t.csv", "--plot", tmp_path / "loop.txt")
    assert code == 2 and "--plot" in out.err and "'.txt'" in out.err
    assert not (tmp_path / "t.csv").exists()


@pytest.mark.parametrize("argv, message", [
    (["--bayes", "b", "--draws", "0"], "--draws: must be >= 10"),
    (["--bayes", "b", "--chains", "1"], "--chains: must be >= 2"),
    (["--starts", "0"], "--starts: must be an integer >= 1"),
])
def test_fit_counts_are_refused_before_the_fit(argv, message, tmp_path, capsys):
    code, out = _run(capsys, "fit", tmp_path / "nowhere.csv", "--json", tmp_path / "f.json", *argv)
    assert code == 2
    assert message in out.err and ", got " + argv[-1] in out.err
    assert "nowhere" not in out.err


@pytest.mark.parametrize("argv, message", [
    (["simulate-test", "--samples-per-cycle", "0"], "--samples-per-cycle: must be >= 8"),
    (["simulate-test", "--amplitude", "1e6in"], "--amplitude: must be <= 100in, got 1e6in"),
    (["montecarlo", "--motions", "2", "--pga", "100g"], "--pga: must be <= 5g, got 100g"),
    (["run", "--record-x", "{x}", "--record-units", "g", "--scale", "0"], "--scale: must be a finite number > 0, got 0"),
    (["run", "--record-x", "{x}", "--record-units", "g", "--pressure", "-1000psi"], "--pressure: must be > 0, got -1000psi"),
    # the flag and the value as typed, not the library's names and SI values
    (["montecarlo", "--motions", "2", "--isolation-damping", "150%"], "--isolation-damping: must be <= 100%, got 150%"),
    (["design", "--isolation-damping", "1.5"], "--isolation-damping: must be <= 1, got 1.5"),
    (["montecarlo", "--motions", "2", "--pressure", "100psi"],
     "--pressure: 100psi is outside Table 1's rows for UF (1000-6500 psi)"),
    (["design", "--pressure-range", "0.5MPa", "2000psi"], "--pressure-range: 0.5MPa is outside Table 1's rows"),
    (["run", "--record-x", "{x}", "--record-units", "g", "--pressure", "100psi"],
     "--pressure: 100psi is outside Table 1's rows for UF"),
    (["simulate-test", "--pressure", "100psi"], "--pressure: 100psi is outside Table 1's rows"),
    (["montecarlo", "--motions", "2", "--ptfe", "XX"], "--ptfe: unknown PTFE type 'XX'"),
])
def test_nonsense_values_are_refused(argv, message, tmp_path, capsys):
    x = _two_column(tmp_path / "x.txt")
    typed = [a.format(x=x) for a in argv]
    code, out = _run(capsys, *typed, *(["--out", tmp_path / "t.csv"] if argv[0] == "simulate-test" else []))
    assert code == 2
    assert message in out.err
    assert not (tmp_path / "t.csv").exists()


@pytest.mark.parametrize("step, warned", [(0.003, True), (0.02, True), (0.005, False), (0.0025, False),
                                          (0.01, False), (1 / 150, True)])
def test_a_step_that_does_not_divide_the_record_step_is_warned_about(step, warned, capsys):
    warn_time_step("run", step, f"{step * 1e3:g}ms", 0.01, "0.01s")
    err = capsys.readouterr().err
    assert ("does not divide the record step 0.01s" in err) == warned
    if warned:
        assert f"--time-step {step * 1e3:g}ms" in err and "ms." in err


@pytest.mark.slow  # one compilation of the two-direction solver: ~15 s CPU, over a minute on busy cores
def test_run_warns_of_a_step_that_does_not_divide_its_record(tmp_path, capsys):
    x = _two_column(tmp_path / "x.txt", n=31)
    code, out = _run(capsys, "run", "--record-x", x, "--record-units", "g", "--time-step", "0.003s",
                     "--json", tmp_path / "r.json")
    assert code == 0
    assert "--time-step 0.003s does not divide the record step 0.01s" in out.err
    assert json.loads((tmp_path / "r.json").read_text())["solver_time_step_s"] == pytest.approx(0.003)


@pytest.mark.parametrize("scheduler, motions, given, chunk", [
    ("local:2", 200, None, 100), ("local:4", 10, None, 3), ("local:2", 5000, None, 512),
    (None, 200, None, 512), ("tcp://host:8786", 200, None, 512), ("local:2", 200, 50, 50)])
def test_every_local_worker_gets_a_task(scheduler, motions, given, chunk):
    args = argparse.Namespace(scheduler=scheduler, motions=motions, chunk_size=given)
    assert _chunk_size(args) == chunk
