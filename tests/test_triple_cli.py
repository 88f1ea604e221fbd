"""`--isolator triple-fp --isolator-file FILE` of `teflon-jax run` and `montecarlo`: one and two
horizontal components through the structures on triple friction pendulums, the isolator
file's units at the boundary, and bad flags refused by name before any work."""

import hashlib
import json

import jax
import numpy as np
import pytest

from teflon_jax.cli import main
from teflon_jax.excitation import uniform_signal
from teflon_jax.formats import load_isolator
from teflon_jax.systems import (
    simulate_history,
    triple_structure,
)
from teflon_jax.units import INCH, STANDARD_GRAVITY


def _surface(radius, capacity, f_max, delta_f=0.0):
    friction = {"f_max": {"value": f_max, "unit": "1"}, "delta_f": {"value": delta_f, "unit": "1"},
                "rate_a": {"value": 0.5, "unit": "s/in"}}
    return {"radius": {"value": radius, "unit": "in"}, "capacity": {"value": capacity, "unit": "in"},
            "friction": friction}


@pytest.fixture
def isolator_file(tmp_path):
    path = tmp_path / "tfp.json"
    path.write_text(json.dumps({
        "format": "teflon-jax isolator", "format_version": 1, "isolator": "triple-fp",
        "surfaces": {"inner": _surface(12, 2, 0.02, 0.01), "bottom": _surface(84, 12, 0.06, 0.02),
                     "top": _surface(84, 14, 0.10, 0.03)},
        "yield_disp": {"value": 0.004, "unit": "in"}}))
    return path


def _record(path, dt=0.01, n=801, peak=0.3, frequency=1.0):
    t = dt * np.arange(n)
    a = peak * np.sin(2 * np.pi * frequency * t) * np.sin(np.pi * t / t[-1]) ** 2
    path.write_text("time acc\n" + "\n".join(f"{ti:.4f} {ai:.6e}" for ti, ai in zip(t, a)) + "\n")
    return np.asarray([float(f"{ai:.6e}") for ai in a]) * STANDARD_GRAVITY  # as written


def test_run_on_a_triple_pendulum(tmp_path, capsys, isolator_file):
    """The rigid mass: its base shear is the bearing force (m a = -F), the isolator file's
    inches read as such (the library run on the SI bearing gives the same peak)."""
    acc = _record(tmp_path / "x.txt")
    out = tmp_path / "run.json"
    code = main(["run", "--record-x", str(tmp_path / "x.txt"), "--record-units", "g", "--isolator",
                 "triple-fp", "--isolator-file", str(isolator_file), "--weight", "500kN",
                 "--json", str(out), "--histories", str(tmp_path / "h.csv")])
    capsys.readouterr()
    assert code == 0
    payload = json.loads(out.read_text())
    assert payload["isolator"] == "triple-fp" and payload["isolator_file"] == str(isolator_file)
    peak = payload["peak"]
    assert peak["base_shear_ratio_resultant"] == pytest.approx(peak["bearing_force_ratio_resultant"], rel=1e-9)
    assert peak["base_disp_y_m"] == 0.0 and peak["base_disp_x_m"] > 0.02
    bearing = load_isolator(isolator_file)
    assert float(bearing.inner_radius) == pytest.approx(12 * INCH, rel=1e-12)
    system = triple_structure("rigid", bearing, uniform_signal(acc, 0.01), time_step=0.0025, weight=500e3)
    response = jax.jit(simulate_history, static_argnums=1)(system, 8.0)
    assert peak["base_disp_x_m"] == pytest.approx(float(np.max(np.abs(response.displacement[:, 0]))), rel=1e-9)
    assert (tmp_path / "h.csv").read_text().splitlines()[0].split(",")[-1] == "slider_top_m"


def test_run_on_a_building_gives_its_storeys(tmp_path, capsys, isolator_file):
    _record(tmp_path / "x.txt", n=401)
    out = tmp_path / "run.json"
    assert main(["run", "--structure", "building", "--record-x", str(tmp_path / "x.txt"), "--record-units",
                 "g", "--isolator", "triple-fp", "--isolator-file", str(isolator_file), "--json", str(out)]) == 0
    capsys.readouterr()
    peak = json.loads(out.read_text())["peak"]
    assert len(peak["storey_drift_ratio_x"]) == 6 and len(peak["floor_acceleration_resultant_g"]) == 6
    # the base shear of the floors stays below the bearing force over W plus the slab's share
    assert 0 < peak["base_shear_ratio_resultant"] < 2 * peak["bearing_force_ratio_resultant"]


def test_montecarlo_runs_a_triple_pendulum(tmp_path, capsys, isolator_file):
    out = tmp_path / "mc.json"
    code = main(["montecarlo", "--motions", "2", "--duration", "6s", "--strong-motion", "2s", "--isolator",
                 "triple-fp", "--isolator-file", str(isolator_file), "--no-progress", "--json", str(out)])
    capsys.readouterr()
    assert code == 0
    payload = json.loads(out.read_text())
    assert payload["design"]["isolator"] == "triple-fp"
    assert payload["design"]["isolator_file"] == str(isolator_file)
    assert payload["design"]["isolator_file_sha256"] == hashlib.sha256(isolator_file.read_bytes()).hexdigest()
    # the file's surfaces replace the flat sliders' PTFE, pressure and springs: none of them is recorded
    assert not {"ptfe", "isolation_period_s", "isolation_damping"} & set(payload["design"]) and payload["all_converged"]


@pytest.mark.slow
def test_run_under_two_equal_components_is_the_diagonal_record(tmp_path, capsys, isolator_file):
    """x and y the same record: the motion along the diagonal, sqrt(2) times the record; the
    bearing is isotropic, so the resultant peaks are those of one component scaled by sqrt(2)."""
    _record(tmp_path / "x.txt", n=601)
    common = ["run", "--structure", "building", "--record-x", str(tmp_path / "x.txt"), "--record-units", "g",
              "--isolator", "triple-fp", "--isolator-file", str(isolator_file)]
    assert main([*common, "--record-y", str(tmp_path / "x.txt"), "--json", str(tmp_path / "two.json")]) == 0
    assert main([*common, "--scale", repr(2**0.5), "--json", str(tmp_path / "one.json")]) == 0
    capsys.readouterr()
    two = json.loads((tmp_path / "two.json").read_text())["peak"]
    one = json.loads((tmp_path / "one.json").read_text())["peak"]
    assert two["base_disp_x_m"] == pytest.approx(two["base_disp_y_m"], rel=1e-9)
    for key in ("base_disp_resultant_m", "bearing_force_ratio_resultant", "first_storey_shear_ratio_resultant"):
        assert two[key] == pytest.approx(one[key], rel=1e-6)


@pytest.mark.slow
def test_montecarlo_runs_a_triple_pendulum_under_two_components(tmp_path, capsys, isolator_file):
    out = tmp_path / "mc.json"
    assert main(["montecarlo", "--motions", "2", "--duration", "6s", "--strong-motion", "2s", "--components", "2",
                 "--isolator", "triple-fp", "--isolator-file", str(isolator_file), "--no-progress",
                 "--json", str(out)]) == 0
    capsys.readouterr()
    payload = json.loads(out.read_text())
    assert payload["motions"]["components"] == 2 and payload["all_converged"]


@pytest.mark.parametrize("flags, message", [
    (["--isolator", "triple-fp"], "--isolator-file: --isolator triple-fp needs"),
    (["--isolator", "triple-fp", "--isolator-file", "{file}", "--radius", "88in"], "--radius: does not apply"),
    (["--isolator", "single-fp", "--radius", "88in", "--isolator-file", "{file}"],
     "--isolator-file: applies to --isolator triple-fp or double-fp only"),
    (["--isolator-file", "{file}"], "--isolator-file: applies to --isolator triple-fp or double-fp only"),
    (["--isolator", "triple-fp", "--isolator-file", "{file}", "--isolation-period", "3s"],
     "--isolation-period: does not apply"),
    (["--isolator", "triple-fp", "--isolator-file", "{file}", "--ptfe", "15GF"], "--ptfe: does not apply"),
    (["--isolator", "triple-fp", "--isolator-file", "{missing}"], "--isolator-file"),
])
@pytest.mark.parametrize("command", ["run", "montecarlo"])
def test_bad_triple_flags_are_refused_by_name_before_any_work(command, flags, message, capsys, tmp_path,
                                                              isolator_file):
    flags = [f.format(file=isolator_file, missing=tmp_path / "nothing.json") for f in flags]
    missing = ["--record-x", str(tmp_path / "missing.AT2")] if command == "run" else ["--motions", "2"]
    assert main([command, *missing, *flags]) == 2
    err = capsys.readouterr().err
    assert message in err and "missing.AT2" not in err


@pytest.mark.parametrize("command, flags, message", [
    ("run", ["--structure", "slab"], "--plan: --structure slab needs a plan file"),
    ("run", ["--plan", "plan.json"], "--plan: stands a slab (--structure slab) or the Table 2 building"),
    ("montecarlo", ["--newton-tolerance", "1e-3"], "--newton-tolerance"),
])
def test_what_the_triple_pendulum_cannot_run_is_refused(command, flags, message, capsys, tmp_path, isolator_file):
    _record(tmp_path / "x.txt", n=101)
    base = (["--record-x", str(tmp_path / "x.txt"), "--record-units", "g"] if command == "run"
            else ["--motions", "2"])
    code = main([command, *base, "--isolator", "triple-fp", "--isolator-file", str(isolator_file), *flags])
    assert code == 2
    assert message in capsys.readouterr().err
