"""The fitter recovers its own simulator: tests 62 and 75 and a figure eight, noise-free, written
to a test-record CSV and read back as the CLI does; fit and diagnosis share one force model;
interfaces in parallel and in series mean what FORMATS.md says."""

import numpy as np
import pytest

import teflon_jax as tj
from identification.bearing_fit import fit_bearing_test, simulate_record_force
from identification.discovery import discover_effects
from teflon_jax.systems import sample_velocity
from teflon_jax.units import INCH, PSI

Y_PAPER = 0.005 * INCH
PRESSURE = 1000 * PSI
AREA = np.pi * (5 * INCH) ** 2  # 10 in diameter specimens
FREE = ["f_max", "delta_f", "rate_a", "yield_disp"]
UF_P, _ = tj.interface_parameters("UF", PRESSURE, "P")
UF_T, _ = tj.interface_parameters("UF", PRESSURE, "T")
TRUTH = dict(f_max=float(UF_P.f_max), delta_f=float(UF_P.delta_f), rate_a=float(UF_P.rate_a),
             yield_disp=Y_PAPER)
TRUTH_T = dict(f_max_perpendicular=float(UF_T.f_max), delta_f_perpendicular=float(UF_T.delta_f),
               rate_a_perpendicular=float(UF_T.rate_a))


def _simulated_file(tmp_path, bearing, motion, metadata=None, name="test.csv"):
    """What `teflon-jax simulate-test` writes (400 samples per cycle, paper units), read back."""
    result = tj.imposed_path_test(bearing, motion, PRESSURE * AREA)
    record = tj.test_record_from_arrays(
        np.asarray(result.ux), np.asarray(result.fx), time=np.asarray(result.time),
        uy=np.asarray(result.uy) if isinstance(motion, tj.AbstractBiaxialMotion) else None,
        fy=np.asarray(result.fy) if isinstance(motion, tj.AbstractBiaxialMotion) else None,
        normal_load=np.asarray(result.normal_load),
        metadata={"ptfe": "UF", "direction": "P", "contact_area": AREA, **(metadata or {})})
    tj.write_test_record(tmp_path / name, record)
    return tj.read_test_record(tmp_path / name)


# Tests No. 62 (1 in at 0.16 Hz, peak 1 in/s) and No. 75 (4 in at 0.6 Hz, peak 15 in/s).
PAPER_TESTS = {62: (1 * INCH, 0.16), 75: (4 * INCH, 0.6)}


@pytest.fixture(scope="module")
def paper_records(tmp_path_factory):
    folder = tmp_path_factory.mktemp("records")
    bearing = tj.paper_bearing(UF_P, yield_disp=Y_PAPER)
    return {no: _simulated_file(folder, bearing, tj.SineMotion(a, f, cycles=3), name=f"{no}.csv")
            for no, (a, f) in PAPER_TESTS.items()}


@pytest.mark.parametrize("number", sorted(PAPER_TESTS))
def test_fit_recovers_simulate_test_output(paper_records, number):
    fit = fit_bearing_test(paper_records[number], free=FREE, n_starts=2)
    assert fit.converged and fit.clean, fit.warnings
    assert fit.nrmse < 1e-3
    for name, value in TRUTH.items():
        assert fit.parameters[name] == pytest.approx(value, rel=3e-3), name


def test_sample_velocity_is_second_order():
    # The velocity convention: central differences agree with the analytic velocity to O(h^2).
    errors = []
    for n in (200, 400):
        t = np.linspace(0.0, 1.0, n + 1)
        errors.append(np.abs(sample_velocity(t, np.sin(2 * np.pi * t))
                             - 2 * np.pi * np.cos(2 * np.pi * t)).max())
    assert errors[0] / errors[1] == pytest.approx(4.0, rel=0.1)


@pytest.mark.slow
def test_fit_and_diagnose_give_the_same_baseline(paper_records):
    record = paper_records[62]
    fit = fit_bearing_test(record, free=FREE, n_starts=2)
    result = discover_effects(record, max_effects=0, max_steps=80)
    baseline = result.baseline_parameters
    for name in FREE:
        assert baseline[name] == pytest.approx(fit.parameters[name], rel=1e-3), name
    np.testing.assert_allclose(np.asarray(result.forces["baseline"]), fit.records[0].fitted,
                               atol=2e-3 * np.abs(record.fx).max())


@pytest.mark.slow
def test_figure_eight_fits_parallel_and_perpendicular_constants(tmp_path):
    bearing = tj.paper_bearing(UF_P, yield_disp=Y_PAPER, friction_perpendicular=UF_T)
    motion = tj.FigureEightMotion(1 * INCH, 2 * np.pi * 0.16, cycles=2)
    record = _simulated_file(tmp_path, bearing, motion)
    fit = fit_bearing_test(record, n_starts=2)
    assert set(TRUTH_T) <= set(fit.free)
    assert fit.converged and fit.nrmse < 1e-3, (fit.nrmse, fit.warnings)
    for name, value in {**TRUTH, **TRUTH_T}.items():
        assert fit.parameters[name] == pytest.approx(value, rel=3e-3), name


def test_biaxial_force_equals_simulator_on_its_path():
    # Park's equations along the sampled path: the simulator's force to 1e-4 of its RMS.
    bearing = tj.paper_bearing(UF_P, yield_disp=Y_PAPER, friction_perpendicular=UF_T)
    r = tj.imposed_path_test(bearing, tj.FigureEightMotion(1 * INCH, 1.0, cycles=2), 1.0)
    t, ux, uy = (np.asarray(x) for x in (r.time, r.ux, r.uy))
    fx, fy = simulate_record_force({**TRUTH, **TRUTH_T, "breakaway_ratio": None}, t, ux, 1.0,
                                   uy=uy, park_elements=32)
    error = np.hypot(np.asarray(fx) - np.asarray(r.fx), np.asarray(fy) - np.asarray(r.fy))
    assert np.sqrt(np.mean(error**2)) < 2e-4 * np.sqrt(np.mean(np.asarray(r.fx**2 + r.fy**2)))


def test_two_interfaces_in_parallel_give_the_true_friction(tmp_path):
    # The paper's rig: two identical interfaces, forces recorded together (fx = 2 mu N Z).
    bearing = tj.paper_bearing(UF_P, yield_disp=Y_PAPER)
    motion = tj.SineMotion(*PAPER_TESTS[75], cycles=3)
    result = tj.imposed_path_test(bearing, motion, PRESSURE * AREA)
    record = tj.test_record_from_arrays(
        np.asarray(result.ux), 2 * np.asarray(result.fx), time=np.asarray(result.time),
        normal_load=PRESSURE * AREA, metadata={"interfaces_in_parallel": 2})
    tj.write_test_record(tmp_path / "rig.csv", record)
    fit = fit_bearing_test(tj.read_test_record(tmp_path / "rig.csv"), free=FREE, n_starts=2)
    for name, value in TRUTH.items():
        assert fit.parameters[name] == pytest.approx(value, rel=3e-3), name


def test_interfaces_in_series_evaluate_eq1_at_v_over_n(tmp_path):
    stack = tj.paper_bearing(UF_P, yield_disp=Y_PAPER, n_interfaces=4)
    record = _simulated_file(tmp_path, stack, tj.SineMotion(*PAPER_TESTS[75], cycles=3),
                             metadata={"interfaces_in_series": 4})
    fit = fit_bearing_test(record, free=FREE, n_starts=2)
    for name, value in TRUTH.items():
        assert fit.parameters[name] == pytest.approx(value, rel=3e-3), name


def test_bare_interfaces_key_is_refused_by_name(tmp_path):
    with pytest.raises(ValueError, match="interfaces_in_parallel.*interfaces_in_series"):
        tj.test_record_from_arrays([0.0, 1.0], [0.0, 1.0], time=[0.0, 1.0],
                                   metadata={"interfaces": 2})
    path = tmp_path / "bad.csv"
    path.write_text("# interfaces: 2\ntime [s],ux [in],fx [kip]\n0,0,0\n1,1,1\n")
    with pytest.raises(ValueError, match="line 1.*interfaces_in_parallel"):
        tj.read_test_record(path)


def test_poorly_determined_fit_is_not_clean():
    # Constant velocity far above the plateau: rate_a and delta_f cannot be seen.
    bearing = tj.paper_bearing(UF_P, yield_disp=Y_PAPER)
    motion = tj.TriangleMotion(amplitude=4 * INCH, frequency=1.0, cycles=2)
    result = tj.imposed_path_test(bearing, motion, PRESSURE * AREA, samples_per_cycle=400)
    rng = np.random.default_rng(0)
    fx = np.asarray(result.fx)
    record = tj.test_record_from_arrays(
        np.asarray(result.ux), fx + 0.02 * np.abs(fx).max() * rng.standard_normal(fx.size),
        time=np.asarray(result.time), normal_load=PRESSURE * AREA)
    fit = fit_bearing_test(record, free=["f_max", "delta_f", "rate_a"],
                           fixed={"yield_disp": Y_PAPER}, n_starts=2)
    assert not fit.clean
    assert fit.to_json_dict()["clean"] is False
    assert any(w.startswith(("rate_a", "delta_f")) for w in fit.warnings)
