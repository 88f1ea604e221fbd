"""`teflon-jax run`: a user's records through a structure; bad input refused by name."""

import argparse
import json

import numpy as np
import pytest

from teflon_jax.cli import main


def _two_column(path, dt=0.01, n=401, peak=0.3, frequency=1.0, header="time acc"):
    t = dt * np.arange(n)
    a = peak * np.sin(2 * np.pi * frequency * t) * np.sin(np.pi * t / t[-1]) ** 2
    path.write_text(header + "\n" + "\n".join(f"{ti:.4f} {ai:.6e}" for ti, ai in zip(t, a)) + "\n")
    return path


def _at2(path, values, dt=0.01, units_line=None, npts_line=None):
    lines = [
        "PEER NGA STRONG MOTION DATABASE RECORD",
        "Test event, 1/1/2000, Station, 090",
        units_line or "ACCELERATION TIME SERIES IN UNITS OF G",
        npts_line or f"NPTS=  {len(values)}, DT=   {dt:.4f} SEC",
    ]
    rows = [" ".join(f"{v: .7E}" for v in values[i:i + 5]) for i in range(0, len(values), 5)]
    path.write_text("\n".join(lines + rows) + "\n")
    return path


def _run(capsys, *argv):
    code = main(["run", *map(str, argv)])
    return code, capsys.readouterr()


def test_two_column_file_without_its_unit_is_refused(tmp_path, capsys):
    record = _two_column(tmp_path / "x.txt")
    code, out = _run(capsys, "--record-x", record)
    assert code == 2
    assert "--record-x" in out.err and "x.txt" in out.err and "--record-units" in out.err


def test_components_with_different_time_steps_are_refused(tmp_path, capsys):
    x = _two_column(tmp_path / "x.txt", dt=0.01)
    y = _two_column(tmp_path / "y.txt", dt=0.02, n=201)
    code, out = _run(capsys, "--record-x", x, "--record-y", y, "--record-units", "g")
    assert code == 2
    assert "time step 0.02 s differs from --record-x's 0.01 s" in out.err and "--resample" in out.err


def test_resample_of_a_record_that_runs_alone_is_refused(tmp_path, capsys):
    x = _two_column(tmp_path / "x.txt")
    code, out = _run(capsys, "--record-x", x, "--record-units", "g", "--resample", "--json", tmp_path / "r.json")
    assert code == 2 and "--resample: brings --record-y or --record-z onto the step" in out.err
    assert not (tmp_path / "r.json").exists()


@pytest.mark.parametrize("start, duration, note", [
    ("0.004s", "2.005s", "the window is 0 s to 2 s, --start and --duration taken to the nearest of the record's "
                         "samples (step 0.01 s)"),
    ("0.5s", "2s", None),
])
def test_a_window_between_the_samples_is_said_in_the_notes(tmp_path, start, duration, note):
    from teflon_jax.cli._run_records import load_components

    args = argparse.Namespace(record_x=str(_two_column(tmp_path / "x.txt")), record_y=None, record_z=None,
                              record_units="g", resample=False, start=start, duration=duration, scale=1.0,
                              time_step="2.5ms")
    ax, _, dt, notes = load_components(args)
    assert ax.size == 201 and dt == 0.01
    assert notes == ([] if note is None else [note])


def test_components_with_different_lengths_are_refused(tmp_path, capsys):
    x = _two_column(tmp_path / "x.txt", n=401)
    y = _two_column(tmp_path / "y.txt", n=301)
    code, out = _run(capsys, "--record-x", x, "--record-y", y, "--record-units", "g")
    assert code == 2
    assert "last 4 s (x, 401 samples) and 3 s (y, 301 samples)" in out.err


def test_duration_longer_than_the_record_is_refused(tmp_path, capsys):
    x = _two_column(tmp_path / "x.txt", n=401)
    code, out = _run(capsys, "--record-x", x, "--record-units", "g", "--start", "1s", "--duration", "5s")
    assert code == 2
    assert "--duration: 5s from --start 1 s runs past the end of the record (4 s)" in out.err


def test_malformed_at2_header_names_file_and_line(tmp_path, capsys):
    bad = _at2(tmp_path / "bad.AT2", np.zeros(10), npts_line="NPTS= ten, DT= 0.01 SEC")
    code, out = _run(capsys, "--record-x", bad)
    assert code == 2
    assert "bad.AT2, line 4" in out.err


def test_plan_loads_not_adding_to_the_weight_are_refused(tmp_path, capsys):
    x = _two_column(tmp_path / "x.txt")
    plan = {
        "length_x": "20m", "length_y": "10m", "weight": "1000kN",
        "groups": [
            {"x": "0m", "y": "0m", "load": "250kN"}, {"x": "20m", "y": "0m", "load": "250kN"},
            {"x": "20m", "y": "10m", "load": "250kN"}, {"x": "0m", "y": "10m", "load": "200kN"},
        ],
    }
    (tmp_path / "plan.json").write_text(json.dumps(plan))
    code, out = _run(capsys, "--structure", "slab", "--plan", tmp_path / "plan.json", "--record-x", x,
                     "--record-units", "g")
    assert code == 2
    assert "add up to 950 kN but the slab weighs 1000 kN" in out.err
    plan["groups"][3] = {"name": "NW", "x": "0m", "y": "12m", "load": "250kN"}
    (tmp_path / "plan.json").write_text(json.dumps(plan))
    code, out = _run(capsys, "--structure", "slab", "--plan", tmp_path / "plan.json", "--record-x", x,
                     "--record-units", "g")
    assert code == 2
    assert "NW at (0, 12) m lies outside the slab" in out.err


@pytest.mark.slow
def test_run_writes_peaks_plot_and_histories(tmp_path, capsys):
    """End to end on a slab with an eccentric centre of mass: JSON peaks with the required
    keys, corner displacements above the centre's, NetCDF histories, a plot."""
    x = _two_column(tmp_path / "x.txt", n=301)
    y = _two_column(tmp_path / "y.txt", n=301, frequency=0.7, peak=0.25)
    plan = {
        "length_x": "20m", "length_y": "10m", "weight": "1000kN", "centre_of_mass": ["13m", "5m"],
        "groups": [
            {"name": "SW", "x": "0m", "y": "0m", "load": "175kN"},
            {"name": "SE", "x": "20m", "y": "0m", "load": "325kN", "pressure": "2000psi"},
            {"name": "NE", "x": "20m", "y": "10m", "load": "325kN", "pressure": "2000psi"},
            {"name": "NW", "x": "0m", "y": "10m", "load": "175kN"},
        ],
    }
    (tmp_path / "plan.json").write_text(json.dumps(plan))
    code, _ = _run(capsys, "--structure", "slab", "--plan", tmp_path / "plan.json", "--record-x", x,
                   "--record-y", y, "--record-units", "g", "--isolation-period", "2.5s",
                   "--isolation-damping", "5%", "--breakaway", "table",
                   "--json", tmp_path / "out.json", "--plot", tmp_path / "out.png",
                   "--histories", tmp_path / "h.nc")
    assert code == 0
    peak = json.loads((tmp_path / "out.json").read_text())["peak"]
    for key in ("base_disp_resultant_m", "base_disp_x_m", "base_disp_y_m", "base_shear_ratio_resultant"):
        assert peak[key] > 0
    assert max(peak["corner_disp_resultant_m"]) > peak["base_disp_resultant_m"]
    assert (tmp_path / "out.png").stat().st_size > 0 and (tmp_path / "h.nc").stat().st_size > 0


@pytest.mark.slow
@pytest.mark.parametrize("flag, name", [("--plot", "p.png"), ("--histories", "h.nc")])
def test_a_single_runs_plot_or_histories_on_a_suite_is_refused(tmp_path, capsys, flag, name):
    (tmp_path / "suite.csv").write_text("name,record_x\na,not-read.txt\n")
    code, out = _run(capsys, "--suite", tmp_path / "suite.csv", flag, tmp_path / name, "--json", tmp_path / "s.json")
    assert code == 2 and f"{flag}: belongs to a single record's run (--record-x); a suite writes" in out.err
    assert not (tmp_path / name).exists() and not (tmp_path / "s.json").exists()


def test_suite_of_pairs_gives_per_pair_peaks_mean_and_max(tmp_path, capsys):
    """Three pairs, one scaled by 2, in one call: the table holds every pair, and the mean and
    max rows are those of the per-pair peaks; the scaled pair moves more."""
    for i, (f, n) in enumerate(((1.0, 301), (0.7, 301), (0.9, 251))):
        _two_column(tmp_path / f"x{i}.txt", n=n, frequency=f)
        _two_column(tmp_path / f"y{i}.txt", n=n, frequency=f * 0.8, peak=0.2)
    (tmp_path / "suite.csv").write_text(
        "name,record_x,record_y,scale\na,x0.txt,y0.txt,1\nb,x1.txt,y1.txt,1\nc,x0.txt,y0.txt,2\n")
    code, _ = _run(capsys, "--suite", tmp_path / "suite.csv", "--record-units", "g",
                   "--isolation-period", "2.5s", "--isolation-damping", "5%", "--json", tmp_path / "s.json")
    assert code == 0
    payload = json.loads((tmp_path / "s.json").read_text())
    disp = [payload["pairs"][k]["base_disp_resultant_m"] for k in "abc"]
    assert disp[2] > disp[0] > 0
    assert payload["summary"]["base_disp_resultant_m"]["max"] == pytest.approx(max(disp))
    assert payload["summary"]["base_disp_resultant_m"]["mean"] == pytest.approx(np.mean(disp))
    assert payload["summary"]["base_disp_resultant_m"]["min"] == pytest.approx(min(disp))
    table = (tmp_path / "s.csv").read_text().splitlines()
    assert len(table) == 1 + 3 + 3 and [row.split(",")[0] for row in table[-3:]] == ["mean", "min", "max"]
    assert (tmp_path / "s.nc").stat().st_size > 0
