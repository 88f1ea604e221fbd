"""A slab on a plan whose overturning loads, with its vertical record, take a bearing group past
where Table 1's extended end segments give Eq. 1 constants: `run` keeps the response before
that sample and names the group, the time and the contact pressure (exit 1, "complete": false);
a suite flags such a pair and keeps the others (exit 1), where before the first such pair
stopped the whole suite. The vertical record alone stays within the table (the check before
the run passes); the overturning moment of the slab 2 m up takes the groups beyond it.

Peer: the same run over a window that ends before that sample, which completes and has the same
histories over it."""

import csv
import json

import numpy as np
import pytest

from teflon_jax.cli import main
from teflon_jax.studies import open_suite

DT = 0.01
PLAN = {"length_x": "4m", "length_y": "4m", "weight": "400kip", "centre_of_mass": ["2m", "2m"],
        "height_of_centre_of_mass": "2m",
        "groups": [{"name": n, "x": x, "y": y, "load": "100kip"}
                   for n, x, y in (("SW", "0m", "0m"), ("SE", "4m", "0m"), ("NE", "4m", "4m"), ("NW", "0m", "4m"))]}
COMMON = ["--structure", "slab", "--pressure", "6500psi", "--isolation-period", "2.5s"]
"""UF at 6500 psi: Table 1's extended segments give constants up to s = 1.74 (11,300 psi)."""


def _at2(path, values):
    lines = ["PEER NGA STRONG MOTION DATABASE RECORD", "Test event, 1/1/2000, Station, UP",
             "ACCELERATION TIME SERIES IN UNITS OF G", f"NPTS=  {len(values)}, DT=   {DT:.4f} SEC"]
    rows = [" ".join(f"{v: .7E}" for v in values[i:i + 5]) for i in range(0, len(values), 5)]
    path.write_text("\n".join(lines + rows) + "\n")


def _inputs(folder):
    t = DT * np.arange(401)
    ramp = np.minimum(t, 1.0)
    _at2(folder / "x.at2", 0.6 * np.sin(2 * np.pi * 0.7 * t) * ramp)
    _at2(folder / "y.at2", 0.3 * np.sin(2 * np.pi * 0.5 * t) * ramp)
    _at2(folder / "z.at2", 0.4 * np.sin(2 * np.pi * 2.0 * t))
    (folder / "plan.json").write_text(json.dumps(PLAN))
    return ["--plan", str(folder / "plan.json"), *COMMON]


def _run(folder, name, *more):
    return main(["run", "--record-x", str(folder / "x.at2"), "--record-y", str(folder / "y.at2"),
                 "--record-z", str(folder / "z.at2"), *_inputs(folder), "--json", str(folder / f"{name}.json"),
                 *more])


def test_run_keeps_the_response_before_the_first_sample_beyond_the_table(tmp_path, capsys):
    """Exit 1, "complete": false with the first sample beyond the law as the stop, the group, its
    load and its contact pressure (beyond 11,300 psi) named on stderr, no traceback; at 0.4 of
    the records the run completes."""
    assert _run(tmp_path, "full", "--histories", str(tmp_path / "full.csv")) == 1
    err = capsys.readouterr().err
    payload = json.loads((tmp_path / "full.json").read_text())
    assert payload["complete"] is False and payload["beyond_pressure_law_s"] == payload["stopped_at_s"]
    assert payload["tipped_steps"] == payload["unconverged_steps"] == 0
    line = next(text for text in err.splitlines() if "error" in text)
    assert f"at t = {payload['stopped_at_s']:.4g} s bearing group" in line and "Table 1's extended end" in line
    pressure = float(line.split(" psi")[0].rsplit(" ", 1)[1])
    assert 11300 < pressure < 12500
    assert "Traceback" not in err
    with open(tmp_path / "full.csv") as handle:
        times = [float(row["time_s"]) for row in csv.DictReader(handle)]
    assert times[-1] == pytest.approx(payload["last_kept_s"]) and times[-1] < payload["stopped_at_s"]
    assert _run(tmp_path, "weak", "--scale", "0.4") == 0
    assert json.loads((tmp_path / "weak.json").read_text())["complete"] is True


@pytest.mark.slow
def test_the_kept_response_is_the_run_up_to_there(tmp_path, capsys):
    """The same records over a window that ends at the record sample before the stop: the run
    completes (the law held up to there) and its histories equal the stopped run's (1e-12)."""
    assert _run(tmp_path, "full", "--histories", str(tmp_path / "full.csv")) == 1
    stop = json.loads((tmp_path / "full.json").read_text())["stopped_at_s"]
    window = np.floor(stop / DT - 1e-9) * DT
    assert _run(tmp_path, "window", "--duration", f"{window:.2f}s", "--histories", str(tmp_path / "window.csv")) == 0
    capsys.readouterr()
    assert json.loads((tmp_path / "window.json").read_text())["complete"] is True
    with open(tmp_path / "full.csv") as a, open(tmp_path / "window.csv") as b:
        full, short = list(csv.DictReader(a)), list(csv.DictReader(b))
    assert 0 < len(short) <= len(full)
    for mine, theirs in zip(full, short):
        for key, value in theirs.items():
            assert float(mine[key]) == pytest.approx(float(value), rel=1e-12, abs=1e-12), key


def test_a_suite_flags_the_pair_beyond_the_table_and_keeps_the_others(tmp_path, capsys):
    """Two pairs, the records at 1 and at 0.4: the first is flagged beyond the law (not converged,
    out of the summary, named on stderr), the second has the peaks of its own run (1e-9), exit
    1; the table, the JSON and the NetCDF file carry the flags."""
    flags = _inputs(tmp_path)
    (tmp_path / "pairs.csv").write_text("name,record_x,record_y,record_z,scale\n"
                                        "strong,x.at2,y.at2,z.at2,1\nweak,x.at2,y.at2,z.at2,0.4\n")
    assert main(["run", "--suite", str(tmp_path / "pairs.csv"), *flags, "--json", str(tmp_path / "s.json")]) == 1
    err = capsys.readouterr().err
    assert "1 of 2 pairs took a bearing group's contact pressure beyond" in err and "(strong)" in err
    assert "could not be balanced" not in err and "Traceback" not in err
    pairs = json.loads((tmp_path / "s.json").read_text())["pairs"]
    assert pairs["strong"]["beyond_pressure_law"] and not pairs["strong"]["converged"]
    assert not pairs["weak"]["beyond_pressure_law"] and pairs["weak"]["converged"]
    assert _run(tmp_path, "weak", "--scale", "0.4") == 0
    single = json.loads((tmp_path / "weak.json").read_text())["peak"]
    for key in ("base_disp_resultant_m", "base_shear_ratio_resultant"):
        assert pairs["weak"][key] == pytest.approx(single[key], rel=1e-9)
    with open(tmp_path / "s.csv") as handle:
        rows = {row["pair"]: row for row in csv.DictReader(handle)}
    assert (rows["strong"]["beyond_pressure_law"], rows["weak"]["beyond_pressure_law"]) == ("True", "False")
    stored = open_suite(tmp_path / "s.nc")
    np.testing.assert_array_equal(stored.beyond_pressure_law, [True, False])
    np.testing.assert_array_equal(stored.converged, [False, True])


def test_a_pair_that_tips_the_slab_is_not_taken_for_one_beyond_the_table(tmp_path, capsys):
    """UF at 1000 psi (the law holds far beyond these loads) and the centre of mass 4 m up: the
    strong pair tips the slab, and the loads of the steps its solve did not reach are not read
    as beyond the law; it is named as one that tipped the slab (`tipped` true), not as one
    beyond the law or one whose Newton balance missed (`beyond_pressure_law` false)."""
    _inputs(tmp_path)
    plan = dict(PLAN, height_of_centre_of_mass="4m")
    (tmp_path / "plan.json").write_text(json.dumps(plan))
    (tmp_path / "pairs.csv").write_text("name,record_x,record_y,record_z,scale\n"
                                        "tip,x.at2,y.at2,z.at2,1\ncalm,x.at2,y.at2,z.at2,0.2\n")
    flags = ["--plan", str(tmp_path / "plan.json"), "--structure", "slab", "--pressure", "1000psi",
             "--isolation-period", "2.5s"]
    assert main(["run", "--suite", str(tmp_path / "pairs.csv"), *flags, "--json", str(tmp_path / "s.json")]) == 1
    err = capsys.readouterr().err
    assert "1 of 2 pairs tipped the slab (or the building's base)" in err and "(tip)" in err
    assert "beyond where" not in err and "could not be balanced" not in err
    pairs = json.loads((tmp_path / "s.json").read_text())["pairs"]
    assert not pairs["tip"]["converged"] and not pairs["tip"]["beyond_pressure_law"] and pairs["tip"]["tipped"]
    assert pairs["calm"]["converged"] and not pairs["calm"]["tipped"]
