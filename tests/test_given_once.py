"""Inputs that argparse or the readers would take without a word, refused before any work
with the flag, file and line as typed: a flag or a NAME=VALUE given twice (the last would
win), one file given as two records, an output whose suffix is not the format written, a seed
beyond 32 bits, a suite row out of range or naming a file that is not there, a constant both
fitted and held; and a --start on a record whose times do not begin at zero, said in its own
times."""

import json

import numpy as np
import pytest
from test_new_user import _run, _two_column

from teflon_jax.formats import test_record_from_arrays, write_test_record


@pytest.fixture
def record(tmp_path):
    return _two_column(tmp_path / "r.csv")


@pytest.fixture
def test_csv(tmp_path):
    t = np.linspace(0.0, 4.0, 201)
    ux = 0.05 * np.sin(2 * np.pi * 0.5 * t)
    write_test_record(tmp_path / "t.csv", test_record_from_arrays(
        ux, 1e4 * np.tanh(ux / 1e-3), time=t, normal_load=np.full_like(t, 1e5)))
    return tmp_path / "t.csv"


@pytest.mark.parametrize("argv, message", [
    (["run", "--record-x", "{r}", "--record-units", "g", "--scale", "2", "--scale", "3"],
     "--scale: given twice (--scale 2.0, then --scale 3.0); give it once."),
    (["run", "--record-x", "{r}", "--record-x={r}", "--record-units", "g"], "--record-x: given twice"),
    (["montecarlo", "--motions", "2", "--mot", "3"], "--motions: given twice (--motions 2, then --motions 3)"),
    (["fit", "{t}", "--json", "{d}/f.json", "--starts", "1", "--starts", "2"], "--starts: given twice"),
])
def test_a_flag_given_twice_is_refused_naming_both_values(argv, message, record, test_csv, tmp_path, capsys):
    with pytest.raises(SystemExit) as stop:
        _run(capsys, *[a.format(r=record, t=test_csv, d=tmp_path) for a in argv])
    assert stop.value.code == 2
    assert message in capsys.readouterr().err


@pytest.mark.parametrize("argv, message", [
    (["fit", "{t}", "--json", "{d}/f.json", "--fixed", "f_max=0.1,f_max=0.2"],
     "--fixed: f_max given twice (f_max=0.1, then f_max=0.2)"),
    (["fit", "{t}", "--json", "{d}/f.json", "--fixed", "rate_a=0.6s/in", "--fixed", "rate_a=0.7s/in"],
     "--fixed: rate_a given twice"),
    (["fit", "{t}", "--json", "{d}/f.json", "--fixed", "f_max=0.1", "--free", "f_max,delta_f"],
     "--free and --fixed both name f_max"),
    (["fit", "{t}", "{d}/./{tn}", "--json", "{d}/f.json"], "is the file of the record"),
    (["run", "--record-x", "{r}", "--record-z", "{d}/./r.csv", "--record-units", "g", "--json", "{d}/f.json"],
     "--record-z {d}/./r.csv: is the file of --record-x {r}; the vertical component needs its own record"),
    (["montecarlo", "--motions", "2", "--json", "{d}/f.nc"], "--json {d}/f.nc: writes a JSON file; end the name in .json"),
    (["run", "--record-x", "{r}", "--record-units", "g", "--json", "{d}/f.txt"], "end the name in .json"),
    (["fit", "{t}", "--json", "{d}/f.png"], "--json {d}/f.png: writes a JSON file"),
    (["simulate-test", "--out", "{d}/f.txt"], "--out {d}/f.txt: writes a CSV file; end the name in .csv, e.g. f.csv"),
    (["montecarlo", "--motions", "2", "--json", "{d}/f.json", "--seed", str(2**32)],
     "--seed: expected an integer from 0 to 4294967295"),
    (["fit", "{t}", "--json", "{d}/f.json", "--bayes", "{d}/b", "--seed", "-1"], "--seed: expected an integer from 0"),
])
def test_an_input_given_twice_or_an_output_of_the_wrong_kind_is_refused_before_any_work(
        argv, message, record, test_csv, tmp_path, capsys):
    names = {"r": record, "t": test_csv, "tn": test_csv.name, "d": tmp_path}
    try:
        code, out = _run(capsys, *[a.format(**names) for a in argv])
        err = out.err
    except SystemExit as stop:  # argparse's own refusal
        code, err = stop.code, capsys.readouterr().err
    assert code == 2
    assert message.format(**names) in err, err
    assert not any(tmp_path.glob("f.*")) and not (tmp_path / "b").exists()


def _suite(tmp_path, rows):
    (tmp_path / "s").mkdir()
    _two_column(tmp_path / "s" / "ec.csv")
    (tmp_path / "s" / "late.csv").write_text("time,acc\n" + "".join(
        f"{10 + 0.01 * i:.2f},0.1\n" for i in (0, 1, 3, 4)))  # a sample missing at 10.02 s
    (tmp_path / "s" / "suite.csv").write_text("record_x,record_y,scale\n" + "".join(r + "\n" for r in rows))
    return tmp_path / "s" / "suite.csv"


@pytest.mark.parametrize("rows, message", [
    (["ec.csv,,1", "ec.csv,,-1"], "line 3: scale must be a finite number > 0, got -1"),
    (["ec.csv,,0"], "line 2: scale must be a finite number > 0, got 0"),
    (["ec.csv,missing.csv,1"], "line 2, pair ec: record_y missing.csv is not a file"),
    (["ec.csv,,1", "late.csv,,1"], "pair 'late': record_x "),
])
def test_a_suite_row_is_named_by_its_file_line_and_column(rows, message, tmp_path, capsys):
    suite = _suite(tmp_path, rows)
    code, out = _run(capsys, "run", "--suite", suite, "--record-units", "g", "--json", tmp_path / "out.json")
    assert code == 2 and f"--suite: {suite}" in out.err and message in out.err, out.err
    assert "--record-x" not in out.err and "--scale" not in out.err
    assert not (tmp_path / "out.json").exists()


def test_start_is_counted_from_the_first_sample_and_said_in_the_files_own_times(tmp_path, capsys):
    """A record whose file times run 10 to 10.5 s: --start 11s is refused saying how file times
    map onto --start, and --start 0.2s runs from file time 10.2 s, as the note says; the same
    record written from 0 s gives the same peaks."""
    t = 0.01 * np.arange(51)
    a = 0.3 * np.sin(2 * np.pi * 4 * t)
    for name, t0 in (("late.csv", 10.0), ("early.csv", 0.0)):
        (tmp_path / name).write_text("time,acc\n" + "".join(f"{t0 + ti:.2f},{ai:.6f}\n" for ti, ai in zip(t, a)))
    code, out = _run(capsys, "run", "--record-x", tmp_path / "late.csv", "--record-units", "g", "--start", "11s")
    assert code == 2 and "the file's times run 10 to 10.5 s; file time T is --start (T - 10) s" in out.err, out.err
    peaks = []
    for name in ("late.csv", "early.csv"):
        code, out = _run(capsys, "run", "--record-x", tmp_path / name, "--record-units", "g", "--start", "0.2s",
                         "--json", tmp_path / f"{name}.json")
        assert code == 0
        peaks.append(json.loads((tmp_path / f"{name}.json").read_text())["peak"])
        assert ("the window begins at file time 10.2 s" in out.err) == (name == "late.csv"), out.err
    assert peaks[0] == peaks[1] and peaks[0]


@pytest.mark.parametrize("displacement, said", [
    (0.2, None),
    (0.3, "0.3 of the radius R, where the sphere's restoring force W u / sqrt(R^2 - u^2) is 4.8 % above"),
    (2.0, "2 times the radius R: no point of the concave surface lies that far out"),
])
def test_a_pendulum_run_says_when_its_displacement_leaves_the_small_rotation_range(displacement, said):
    """Against the closed form of a sphere of radius R: W u / sqrt(R^2 - u^2) over W u / R is
    1 / sqrt(1 - 0.09) = 1.048 at u = 0.3 R; past R the sphere has no point (probe: u = 2 R
    under a scaled El Centro was reported with no word)."""
    from teflon_jax.cli._run import slope_note

    note = slope_note(displacement * 1.5, 1.5)
    assert (note is None) if said is None else (said in note), note
    assert slope_note(displacement, None) is None


def test_the_suite_summary_on_the_console_is_in_the_units_asked_for():
    """A suite's summary (SI inside) printed as `run` prints one record's peaks: lengths in the
    --units family (0.0254 m is 1 in, 25.4 mm), times in seconds, ratios as they are."""
    from teflon_jax.cli._common import output_units
    from teflon_jax.cli._run_suite import summary_lines

    summary = {"base_disp_resultant_m": {"mean": 0.0254, "max": 0.0508}, "uplift_time_s": {"mean": 0.5, "max": 1.0},
               "base_shear_ratio_resultant": {"mean": 0.1, "max": 0.125}}
    assert summary_lines(summary, output_units("us")) == [
        "base disp resultant: mean 1 in, max 2 in", "uplift time: mean 0.5 s, max 1 s",
        "base shear ratio resultant: mean 0.1, max 0.125"]
    assert summary_lines(summary, output_units("si"))[0] == "base disp resultant: mean 25.4 mm, max 50.8 mm"


def test_the_namespace_holds_the_flags_alone_and_each_parse_starts_afresh(capsys):
    # the flags seen twice are tracked per parse, outside the namespace the commands read
    from teflon_jax.cli._main import _parser

    parser = _parser(only="montecarlo")
    argv = ["montecarlo", "--motions", "2", "--seed", "3"]
    for _ in range(2):  # a second parse of the same flags by the same parser is no repeat
        args = parser.parse_args(argv)
        assert (args.motions, args.seed) == (2, 3)
        assert not [name for name in vars(args) if "given" in name]
    with pytest.raises(SystemExit):
        parser.parse_args([*argv, "--seed", "4"])
    assert "--seed: given twice (--seed 3, then --seed 4); give it once." in capsys.readouterr().err
