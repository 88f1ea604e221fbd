"""The double friction pendulum's isolator file (`"isolator": "double-fp"`) and the commands
that take it: `run` and `montecarlo --isolator double-fp --isolator-file FILE` (one and two
components), `simulate-test --isolator-file`; bad files and flags refused by key or flag.

Peers: the library run on the file's SI bearing; the closed-form backbone of Fenz &
Constantinou (2006) (see tests/test_double_pendulum.py); the diagonal record as sqrt(2) times
one component (the bearing is isotropic).
"""

import copy
import json
import pathlib

import jax
import numpy as np
import pytest
from test_isolator_file import edited

from teflon_jax.bearing import DoublePendulum, TriplePendulum
from teflon_jax.cli import main
from teflon_jax.excitation import uniform_signal
from teflon_jax.formats import isolator_from_dict, load_isolator, read_test_record
from teflon_jax.systems import (
    simulate_history,
    triple_structure,
)
from teflon_jax.units import INCH, STANDARD_GRAVITY

EXAMPLE = pathlib.Path(__file__).resolve().parents[1] / "benchmarks" / "double_isolator.json"


def _document():
    def surface(radius, capacity, mu):
        return {"radius": {"value": radius, "unit": "in"}, "capacity": {"value": capacity, "unit": "in"},
                "friction": {"f_max": {"value": mu, "unit": "1"}, "delta_f": {"value": 0.0, "unit": "1"},
                             "rate_a": {"value": 0.0, "unit": "s/in"}}}

    return {"format": "teflon-jax isolator", "format_version": 1, "isolator": "double-fp",
            "surfaces": {"bottom": surface(60.0, 4.0, 0.04), "top": surface(100.0, 8.0, 0.08)},
            "yield_disp": {"value": 0.004, "unit": "in"}}


def _record(path, dt=0.01, n=801, peak=0.3, frequency=0.7):
    t = dt * np.arange(n)
    a = peak * np.sin(2 * np.pi * frequency * t) * np.sin(np.pi * t / t[-1]) ** 2
    path.write_text("time acc\n" + "\n".join(f"{ti:.4f} {ai:.6e}" for ti, ai in zip(t, a)) + "\n")
    return np.asarray([float(f"{ai:.6e}") for ai in a]) * STANDARD_GRAVITY  # as written


def test_the_files_read_to_their_pendulums():
    bearing = isolator_from_dict(_document())
    assert isinstance(bearing, DoublePendulum) and bearing.slider_names == ("bottom", "top")
    assert float(bearing.bottom_radius) == pytest.approx(60 * INCH, rel=1e-15)
    assert float(bearing.top_capacity) == pytest.approx(8 * INCH, rel=1e-15)
    assert float(bearing.reference_radius()) == pytest.approx(160 * INCH, rel=1e-15)
    assert isinstance(load_isolator(EXAMPLE), DoublePendulum)
    triple = load_isolator(EXAMPLE.parent / "triple_isolator.json")
    assert isinstance(triple, TriplePendulum) and triple.isolator == "triple-fp"


def _edit(path, value):
    return edited(_document(), path, value)


@pytest.mark.parametrize("path, value, message", [
    (("surfaces", "top"), None, r"surfaces: missing \['top'\]"),
    (("surfaces", "middle"), {}, r"surfaces: unknown \['middle'\]"),
    (("surfaces", "inner"), {}, "'isolator' must be \"triple-fp\" for the surfaces inner"),
    (("surfaces", "bottom", "radius"), 60.0, r"surfaces.bottom.radius: write .* without a unit"),
    (("surfaces", "top", "friction", "delta_f"), None, r"surfaces.top.friction: missing \['delta_f'\]"),
    (("surfaces", "bottom", "radius", "value"), -1.0, "surfaces.bottom.radius: must be a finite number > 0"),
    (("surfaces", "top", "capacity", "value"), 0.0, "surfaces.top.capacity"),
    (("surfaces", "top", "friction", "f_max", "value"), -0.05, "surfaces.top.friction.f_max"),
    (("surfaces", "bottom", "friction", "delta_f", "value"), 0.05, "surfaces.bottom.friction.delta_f"),
    (("yield_disp", "value"), 0.0, "yield_disp"),
    (("isolator",), "quad-fp", "'isolator' must be \"triple-fp\" or \"double-fp\""),
    (("isolator",), "triple-fp", "'isolator' must be \"double-fp\" for the surfaces bottom, top"),
])
def test_a_bad_double_file_is_refused_by_key(path, value, message):
    with pytest.raises(ValueError, match=message) as error:
        isolator_from_dict(_edit(path, value), where="dfp.json")
    assert str(error.value).startswith("dfp.json: ")


def test_run_on_a_double_pendulum_writes_its_peaks(tmp_path, capsys):
    """The rigid mass on the example file: the JSON's peak displacement is the library's run on
    the file's SI bearing, the base shear is the bearing force, and the sliders add up."""
    acc = _record(tmp_path / "x.txt")
    out = tmp_path / "run.json"
    code = main(["run", "--record-x", str(tmp_path / "x.txt"), "--record-units", "g", "--isolator",
                 "double-fp", "--isolator-file", str(EXAMPLE), "--weight", "500kN", "--time-step", "5ms",
                 "--json", str(out), "--histories", str(tmp_path / "h.csv")])
    err = capsys.readouterr().err
    assert code == 0, err
    payload = json.loads(out.read_text())
    assert payload["isolator"] == "double-fp" and payload["isolator_file"] == str(EXAMPLE)
    peak = payload["peak"]
    assert peak["base_disp_resultant_m"] > 0.02 and peak["base_disp_y_m"] == 0.0
    assert set(peak["slider_disp_m"]) == {"bottom", "top"}
    assert peak["base_shear_ratio_resultant"] == pytest.approx(peak["bearing_force_ratio_resultant"], rel=1e-9)
    system = triple_structure("rigid", load_isolator(EXAMPLE), uniform_signal(acc, 0.01), time_step=0.005,
                              weight=500e3)
    response = jax.jit(simulate_history, static_argnums=1)(system, 8.0)
    assert peak["base_disp_resultant_m"] == pytest.approx(
        float(np.max(np.abs(response.displacement[:, 0]))), rel=1e-9)
    header = (tmp_path / "h.csv").read_text().splitlines()[0].split(",")
    assert header[-2:] == ["slider_bottom_m", "slider_top_m"]


def test_two_equal_components_are_the_diagonal_record(tmp_path, capsys):
    _record(tmp_path / "x.txt", n=601)
    common = ["run", "--record-x", str(tmp_path / "x.txt"), "--record-units", "g", "--isolator", "double-fp",
              "--isolator-file", str(EXAMPLE), "--time-step", "5ms"]
    assert main([*common, "--record-y", str(tmp_path / "x.txt"), "--json", str(tmp_path / "two.json")]) == 0
    assert "--record-y is the file of --record-x" in capsys.readouterr().err  # said, as the diagonal record
    assert main([*common, "--scale", repr(2**0.5), "--json", str(tmp_path / "one.json")]) == 0
    capsys.readouterr()
    two = json.loads((tmp_path / "two.json").read_text())["peak"]
    one = json.loads((tmp_path / "one.json").read_text())["peak"]
    assert two["base_disp_x_m"] == pytest.approx(two["base_disp_y_m"], rel=1e-9)
    for key in ("base_disp_resultant_m", "bearing_force_ratio_resultant"):
        assert two[key] == pytest.approx(one[key], rel=1e-6)


@pytest.mark.parametrize("components", ["1", pytest.param("2", marks=pytest.mark.slow)])
def test_montecarlo_runs_a_double_pendulum(tmp_path, capsys, components):
    out = tmp_path / "mc.json"
    code = main(["montecarlo", "--motions", "2", "--duration", "6s", "--strong-motion", "2s", "--components",
                 components, "--isolator", "double-fp", "--isolator-file", str(EXAMPLE), "--no-progress",
                 "--json", str(out)])
    err = capsys.readouterr().err
    assert code == 0, err
    payload = json.loads(out.read_text())
    assert payload["design"]["isolator"] == "double-fp" and payload["all_converged"]


def test_simulate_test_follows_the_closed_form(tmp_path, capsys):
    """A slow sine to 10 in (surface 1 at its restrainer, surface 2 alone): the force at the
    peak displacement within 1 % of mu_1 + d_1 / R_1 + (u - u_2) / R_2 (Fenz & Constantinou
    2006), u_2 = d_1 + R_2 (mu_1 + d_1 / R_1 - mu_2) where surface 2 takes over alone."""
    (tmp_path / "dfp.json").write_text(json.dumps(_document()))
    code = main(["simulate-test", "--isolator-file", str(tmp_path / "dfp.json"), "--normal-load", "500kip",
                 "--amplitude", "10in", "--frequency", "0.01Hz", "--cycles", "1", "--samples-per-cycle", "2000",
                 "--out", str(tmp_path / "dfp.csv")])
    assert code == 0, capsys.readouterr().err
    record = read_test_record(tmp_path / "dfp.csv")
    u, f = np.asarray(record.ux), np.asarray(record.fx) / np.asarray(record.normal_load)
    r1, r2, d1 = 60 * INCH, 100 * INCH, 4 * INCH
    ring = 0.04 + d1 / r1
    closed = ring + (u.max() - d1 - r2 * (ring - 0.08)) / r2
    assert f[np.argmax(u)] == pytest.approx(closed, rel=0.01)


@pytest.mark.parametrize("flags, message", [
    (["--isolator", "double-fp"], "--isolator-file: --isolator double-fp needs"),
    (["--isolator", "double-fp", "--isolator-file", "{triple}"], "holds a triple-fp isolator, not the double-fp"),
    (["--isolator", "triple-fp", "--isolator-file", "{double}"], "holds a double-fp isolator, not the triple-fp"),
    (["--isolator", "double-fp", "--isolator-file", "{double}", "--radius", "88in"], "--radius: does not apply"),
    (["--isolator", "double-fp", "--isolator-file", "{double}", "--ptfe", "15GF"], "--ptfe: does not apply"),
])
@pytest.mark.parametrize("command", ["run", "montecarlo"])
def test_bad_double_flags_are_refused_by_name_before_any_work(command, flags, message, capsys, tmp_path):
    flags = [f.format(double=EXAMPLE, triple=EXAMPLE.parent / "triple_isolator.json") for f in flags]
    missing = ["--record-x", str(tmp_path / "missing.AT2")] if command == "run" else ["--motions", "2"]
    assert main([command, *missing, *flags]) == 2
    err = capsys.readouterr().err
    assert message in err and "missing.AT2" not in err


def test_simulate_test_refuses_a_bad_double_file_by_key(tmp_path, capsys):
    bad = copy.deepcopy(_document())
    bad["surfaces"]["top"]["capacity"] = 8
    (tmp_path / "bad.json").write_text(json.dumps(bad))
    code = main(["simulate-test", "--isolator-file", str(tmp_path / "bad.json"), "--normal-load", "500kip"])
    assert code == 2 and "bad.json: surfaces.top.capacity" in capsys.readouterr().err


@pytest.mark.parametrize("isolator, file, components", [
    ("double-fp", EXAMPLE, 1), pytest.param("double-fp", EXAMPLE, 2, marks=pytest.mark.slow), ("triple-fp", EXAMPLE.parent / "triple_isolator.json", 1)])
def test_run_with_a_vertical_record_reports_the_uplift(tmp_path, capsys, isolator, file, components):
    """--record-z: a_v = -1.4 g over 3-3.3 s lifts the bearings (N = W max(1 + a_v / g, 0)):
    the JSON reports about 0.3 s of uplift and the histories carry N / W; a zero vertical
    record gives the run without one to rounding."""
    _record(tmp_path / "x.txt")
    t = 0.01 * np.arange(801)
    lifted = np.where((t > 3.0) & (t < 3.3), -1.4, 0.0)
    for name, values in (("z.txt", lifted), ("zero.txt", 0 * t)):
        (tmp_path / name).write_text("time acc\n" + "\n".join(f"{a:.4f} {b:.6e}" for a, b in zip(t, values)) + "\n")
    common = ["run", "--record-x", str(tmp_path / "x.txt"), "--record-units", "g", "--isolator", isolator,
              "--isolator-file", str(file), "--time-step", "5ms"]
    common += ["--record-y", str(tmp_path / "x.txt")] if components == 2 else []
    runs = {}
    for name in ("z.txt", "zero.txt", None):
        out = tmp_path / f"{name}.json"
        vertical = [] if name is None else ["--record-z", str(tmp_path / name)]
        assert main([*common, *vertical, "--json", str(out), "--histories", str(tmp_path / f"{name}.csv")]) == 0
        runs[name] = json.loads(out.read_text())
    capsys.readouterr()
    uplift = runs["z.txt"]["uplift"]
    assert uplift["occurred"] and uplift["time_s"] == pytest.approx(0.3, abs=0.02)
    assert uplift["min_load_factor"] == 0.0 and runs["z.txt"]["record_z"] == str(tmp_path / "z.txt")
    assert (tmp_path / "z.txt.csv").read_text().splitlines()[0].endswith("load_factor")
    assert not runs["zero.txt"]["uplift"]["occurred"]
    assert runs["zero.txt"]["peak"]["base_disp_resultant_m"] == pytest.approx(
        runs[None]["peak"]["base_disp_resultant_m"], rel=1e-12)
    assert runs["z.txt"]["peak"]["base_disp_resultant_m"] != pytest.approx(
        runs[None]["peak"]["base_disp_resultant_m"], rel=1e-3)
