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


@pytest.mark.parametrize("step, warned", [(0.003, True), (0.005, False), (0.0025, False),
                                          (0.01, False), (1 / 150, True)])
def test_a_step_that_does_not_divide_the_record_step_is_warned_about(step, warned, capsys):
    warn_time_step("run", step, f"{step * 1e3:g}ms", 0.01, "0.01s")
    err = capsys.readouterr().err
    assert ("does not divide the record step 0.01s" in err) == warned
    if warned:
        assert f"--time-step {step * 1e3:g}ms" in err and "ms." in err


def test_a_step_longer_than_the_record_step_is_refused(capsys):
    with pytest.raises(ValueError, match="--time-step 20ms: longer than the record step 0.01s"):
        warn_time_step("run", 0.02, "20ms", 0.01, "0.01s")
    assert capsys.readouterr().err == ""


@pytest.mark.slow  # one compilation of the two-direction solver: ~15 s CPU, over a minute on busy cores
def test_run_warns_of_a_step_that_does_not_divide_its_record(tmp_path, capsys):
    x = _two_column(tmp_path / "x.txt", n=31)
    code, out = _run(capsys, "run", "--record-x", x, "--record-units", "g", "--time-step", "0.003s",
                     "--json", tmp_path / "r.json")
    assert code == 0
    assert "--time-step 0.003s does not divide the record step 0.01s" in out.err
    assert "teflon-jax run: rigid, 100 steps of 0.003s over 0.3 s of record" in out.err  # said before the work
    assert json.loads((tmp_path / "r.json").read_text())["solver_time_step_s"] == pytest.approx(0.003)
    assert "peak base disp resultant: " in out.out and out.out.splitlines()[0].endswith(" in")  # --units us


@pytest.mark.parametrize("family, shown", [
    ("us", ["peak base disp resultant: 1 in", "peak base shear ratio resultant: 0.125",
            "peak floor acceleration resultant: 0.2, 0.3 g", "peak group disp resultant: A 0.5 in"]),
    ("si", ["peak base disp resultant: 25.4 mm", "peak base shear ratio resultant: 0.125",
            "peak floor acceleration resultant: 0.2, 0.3 g", "peak group disp resultant: A 12.7 mm"]),
])
def test_run_prints_its_peaks_in_the_units_asked_for(family, shown):
    from teflon_jax.cli._common import output_units
    from teflon_jax.cli._run_output import _shown_peaks

    peak = {"base_disp_resultant_m": 0.0254, "base_shear_ratio_resultant": 0.125,
            "floor_acceleration_resultant_g": [0.2, 0.3], "group_disp_resultant_m": {"A": 0.0127}}
    assert _shown_peaks(peak, output_units(family)) == shown


@pytest.mark.parametrize("scheduler, motions, given, chunk", [
    ("local:2", 200, None, 100), ("local:4", 10, None, 3), ("local:2", 5000, None, 512),
    (None, 200, None, 512), ("tcp://host:8786", 200, None, 512), ("local:2", 200, 50, 50)])
def test_every_local_worker_gets_a_task(scheduler, motions, given, chunk):
    args = argparse.Namespace(scheduler=scheduler, motions=motions, chunk_size=given)
    assert _chunk_size(args) == chunk


@pytest.mark.parametrize("platform, free, per_motion, chunk", [
    ("cpu", 80e9, 260_000, 512),          # a CPU keeps 512, however much memory
    ("gpu", 80e9, 260_000, 65536),        # 40 GB / 260 kB = 153,846: capped at 65,536
    ("cuda", 80e9, 8_000_000, 4096),      # 40 GB / 8 MB = 5,000: 4,096
    ("gpu", 1e9, 260_000, 1024),          # little memory: 0.5 GB / 260 kB = 1,923: 1,024
    ("gpu", 100_000, 260_000, 1),         # less than one motion fits: 1
    ("gpu", None, 260_000, 512),          # free memory unknown: as on a CPU
])
def test_default_chunk_follows_the_device_and_its_free_memory(platform, free, per_motion, chunk):
    from teflon_jax.studies import default_chunk_size

    assert default_chunk_size(platform, free, per_motion) == chunk


@pytest.mark.parametrize("scheduler, given, chunk", [
    (None, None, 65536), ("local:2", None, 100), (None, 50, 50), ("local:2", 50, 50)])
def test_chunk_flag_and_local_workers_win_over_the_device_default(scheduler, given, chunk):
    args = argparse.Namespace(scheduler=scheduler, motions=200, chunk_size=given)
    assert _chunk_size(args, 65536) == chunk


def test_progress_bar_counts_motions_per_second(capsys):
    from teflon_jax.cli._common import motion_bar

    bar = motion_bar(10_000, False)
    bar.update(1500)
    shown = bar.format_meter(**dict(bar.format_dict, elapsed=1.0, rate=None))
    bar.close()
    assert "1.50k motions/s" in shown, shown


@pytest.mark.slow  # a small Monte Carlo in process and on a local Dask cluster of 2 workers
def test_montecarlo_results_file_says_what_was_run(tmp_path, capsys):
    import xarray

    argv = ["montecarlo", "--motions", "3", "--duration", "4s", "--strong-motion", "1s", "--pga", "0.4g",
            "--pressure", "1500psi", "--isolation-period", "2.5s", "--ptfe", "15GF", "--no-progress"]
    assert main(argv + ["--out", str(tmp_path / "here.nc")]) == 0
    assert main(argv + ["--out", str(tmp_path / "there.nc"), "--scheduler", "local:2",
                        "--json", str(tmp_path / "there.json")]) == 0
    for name in ("here", "there"):
        with xarray.open_dataset(tmp_path / f"{name}.nc") as stored:
            attrs = stored.attrs
        assert attrs["structure"] == "rigid" and attrs["ptfe"] == "15GF", name
        assert attrs["pressure_Pa"] == pytest.approx(1500 * 6894.757, rel=1e-6), name
        assert attrs["isolation_period_s"] == pytest.approx(2.5) and attrs["pga_m_s2"] == pytest.approx(0.4 * 9.80665)
        assert "pressure=1500psi" in attrs["inputs_as_given"]
    # 3 motions on 2 local workers: two tasks, not one
    assert json.loads((tmp_path / "there.json").read_text())["chunk_size"] == 2


@pytest.mark.parametrize("family, rate, disp, noise", [("us", "s/in", "in", "kip"), ("si", "s/m", "mm", "kN")])
def test_posterior_table_is_in_the_units_asked_for(family, rate, disp, noise):
    from types import SimpleNamespace

    from identification.bayes import BayesResult
    from teflon_jax.cli._fit import _unit_of
    from teflon_jax.units import INCH, KIP

    def row(value):
        return dict(mean=value, median=value, q05=0.9 * value, q95=1.1 * value, rhat=1.0,
                    ess_bulk=900.0, identified="yes")

    si = {"rate_a": 23.62, "yield_disp": 0.005 * INCH, "noise_level_0": 2.0 * KIP}
    least_squares = SimpleNamespace(parameters={"rate_a": 23.62, "yield_disp": 0.005 * INCH},
                                    std_errors={"rate_a": 0.1, "yield_disp": 1e-6})
    result = BayesResult(draws={}, table={k: row(v) for k, v in si.items()}, divergences=0, converged=True,
                         messages=[], least_squares=least_squares, prior="bounds", priors={},
                         free=("rate_a", "yield_disp"), num_chains=2, num_samples=50, elapsed_s=0.0,
                         elapsed_least_squares_s=0.0, rhat_max=1.01, ess_min=200.0)
    lines = {line.split()[0]: line.split() for line in result.summary(unit_of=_unit_of(family)).splitlines()[1:4]}
    scale = {"us": (1 / INCH, INCH, KIP), "si": (1.0, 1e-3, 1e3)}[family]
    assert lines["rate_a"][1] == rate and float(lines["rate_a"][2]) == pytest.approx(23.62 / scale[0], rel=1e-4)
    assert lines["yield_disp"][1] == disp and float(lines["yield_disp"][2]) == pytest.approx(0.005 * INCH / scale[1], rel=1e-4)
    assert lines["noise_level_0"][1] == noise and float(lines["noise_level_0"][2]) == pytest.approx(2.0 * KIP / scale[2], rel=1e-4)


def test_correlation_notes_are_told_from_warnings():
    """The fitter's own texts: a high correlation is a note (the fit stays clean); a poorly
    determined constant or a bound is a warning."""
    from teflon_jax.cli._isolator_table import _is_correlation_note

    assert _is_correlation_note("f_max, delta_f: correlation 0.998; the records hardly separate them.")
    assert _is_correlation_note("rate_a, yield_disp: correlation -0.995; the records hardly separate them.")
    assert not _is_correlation_note("rate_a: poorly determined; standard error 3 is 80% of the estimate 4 (limit 50%).")
    assert not _is_correlation_note("breakaway_ratio: at its lower bound 1.")
    assert not _is_correlation_note("t75.csv: asymmetric misfit; the mean residual is 3 N while moving in +x")


def test_one_flag_name_for_one_thing_and_every_default_shown():
    """fit and diagnose both take --fixed and --known (repeatable), diagnose --no-progress as
    the other commands; every option with a default says it in its help; no literal '%%'."""
    import contextlib
    import io

    from teflon_jax.cli._isolator_table import _parse_fixed
    from teflon_jax.cli._main import _parser
    from teflon_jax.units import INCH

    parser = _parser()
    fit = parser.parse_args(["fit", "r.csv", "--json", "f.json", "--fixed", "yield_disp=0.005in",
                             "--known", "rate_a=0.6s/in,breakaway_ratio=1.5"])
    assert _parse_fixed(fit.fixed) == pytest.approx({"yield_disp": 0.005 * INCH, "rate_a": 0.6 / INCH,
                                                     "breakaway_ratio": 1.5})
    diagnose = parser.parse_args(["diagnose", "r.csv", "--json", "d.json", "--report", "d",
                                  "--fixed", "rate_a=0.6s/in", "--known", "yield_disp=0.005in", "--no-progress"])
    assert diagnose.known == ["rate_a=0.6s/in", "yield_disp=0.005in"] and diagnose.quiet
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    for name, command in sub.choices.items():
        for action in command._actions:
            if action.default not in (None, False, argparse.SUPPRESS) and action.help != argparse.SUPPRESS:
                assert "default" in action.help, (name, action.option_strings)
        text = io.StringIO()
        with contextlib.redirect_stdout(text), pytest.raises(SystemExit):
            parser.parse_args([name, "--help"])
        assert "%%" not in text.getvalue(), name


def test_pair_plot_axes_carry_units(tmp_path):
    import matplotlib

    from identification.bayes import BayesResult
    from teflon_jax.cli._fit import _unit_of
    from teflon_jax.units import INCH

    rng = np.random.default_rng(0)
    draws = {"f_max": rng.normal(0.12, 1e-4, (2, 50)), "rate_a": rng.normal(23.6, 0.3, (2, 50)),
             "yield_disp": rng.normal(0.005 * INCH, 1e-6, (2, 50))}
    result = BayesResult(draws=draws, table={}, divergences=0, converged=True, messages=[],
                         least_squares=None, prior="bounds", priors={}, free=("f_max", "rate_a", "yield_disp"),
                         num_chains=2, num_samples=50, elapsed_s=0.0, elapsed_least_squares_s=0.0,
                         rhat_max=1.01, ess_min=200.0)
    result._diverging = np.zeros((2, 50), dtype=bool)
    with matplotlib.rc_context({"svg.fonttype": "none"}):
        result.plot_pairs(tmp_path / "pairs.svg", unit_of=_unit_of("us"))
    text = (tmp_path / "pairs.svg").read_text()
    assert "rate_a [s/in]" in text and "yield_disp [in]" in text and "f_max [-]" in text
    assert "0.005" in text  # Y in inches, not an offset from 1.27e-4 m


def test_design_contour_levels_resolve_the_designs_within_the_limit():
    """The penalty beyond the limit (orders of magnitude above the shear) must not take the
    colour scale: the designs within the limit spread over at least half of the levels."""
    from types import SimpleNamespace

    from teflon_jax.report._design_plot import _levels

    period, pressure = np.meshgrid(np.linspace(1, 4, 7), np.linspace(0, 1, 7), indexing="ij")
    disp = 0.01 + 0.008 * (period - 1) + 0.01 * pressure
    shear = 0.16 - 0.015 * (period - 1) - 0.02 * pressure
    limit = 0.025
    objective = shear + 100 * np.maximum(disp / limit - 1, 0) ** 2
    levels = _levels({"objective": objective, "disp": disp}, SimpleNamespace(smooth_disp_limit=limit))
    within = objective[disp <= limit]
    assert objective.max() > 100 * within.max()  # the penalty dominates the range
    assert levels[0] <= within.min() and np.sum(levels <= within.max()) >= len(levels) // 2
