"""The vertical component on the command line: `run --record-z` and `montecarlo
--vertical-ratio`, with the uplift (N = W (1 + a_v / g) <= 0) reported, never NaN, and inputs
that cannot be run refused by name."""

import json

import numpy as np
import pytest

from teflon_jax.cli import main
from teflon_jax.units import STANDARD_GRAVITY

G = STANDARD_GRAVITY


def _at2(path, values, dt=0.01):
    lines = ["PEER NGA STRONG MOTION DATABASE RECORD", "Test event, 1/1/2000, Station, UP",
             "ACCELERATION TIME SERIES IN UNITS OF G", f"NPTS=  {len(values)}, DT=   {dt:.4f} SEC"]
    rows = [" ".join(f"{v: .7E}" for v in values[i:i + 5]) for i in range(0, len(values), 5)]
    path.write_text("\n".join(lines + rows) + "\n")
    return path


def _records(tmp_path, dt_z=0.01, n_z=801):
    t = 0.01 * np.arange(801)
    x = _at2(tmp_path / "x.at2", 0.3 * np.sin(2 * np.pi * 0.8 * t))
    tz = dt_z * np.arange(n_z)
    z = _at2(tmp_path / "z.at2", np.where((tz > 4.0 - 1e-9) & (tz < 4.5 + 1e-9), -1.5, 0.0), dt=dt_z)
    return x, z


@pytest.mark.slow
def test_run_reports_the_uplift_of_a_vertical_record(tmp_path, capsys):
    """a_v = -1.5 g on the samples 4.00-4.50 s: N <= 0 for 0.5067 s (linear between samples);
    the JSON and the printout say so, the load factor history is 0 there and the peaks finite."""
    x, z = _records(tmp_path)
    out = tmp_path / "run.json"
    code = main(["run", "--record-x", str(x), "--record-z", str(z), "--isolator", "single-fp",
                 "--radius", "2m", "--json", str(out), "--histories", str(tmp_path / "h.csv")])
    printed = capsys.readouterr().out
    assert code == 0
    payload = json.loads(out.read_text())
    assert payload["record_z"] == str(z)
    uplift = payload["uplift"]
    assert uplift["occurred"] and uplift["min_load_factor"] == 0.0
    assert abs(uplift["time_s"] - (0.5 + 2 * 0.01 / 3)) <= 0.0025
    assert "uplift: N <= 0 during" in printed
    assert all(np.isfinite(v) for v in payload["peak"].values() if isinstance(v, float))
    table = np.genfromtxt(tmp_path / "h.csv", delimiter=",", names=True)
    during = (table["time_s"] > 4.01) & (table["time_s"] < 4.49)
    assert np.all(table["load_factor"][during] == 0)
    assert np.all(table["bearing_force_x_N"][during] == 0)


def test_run_vertical_record_refused_by_name(tmp_path, capsys):
    x, z = _records(tmp_path, dt_z=0.02, n_z=401)
    assert main(["run", "--record-x", str(x), "--record-z", str(z)]) != 0
    assert "--record-z" in capsys.readouterr().err
    x, z = _records(tmp_path, n_z=301)
    assert main(["run", "--record-x", str(x), "--record-z", str(z)]) != 0
    err = capsys.readouterr().err
    assert "--record-z" in err and "--resample" in err


@pytest.mark.slow
def test_montecarlo_counts_uplifted_motions(tmp_path, capsys):
    """A vertical component of 1.8 times the horizontal peak lifts some motions' isolators:
    the summary counts and lists them, the results file has each motion's uplift time, and
    the uplifted motions stay in the statistics."""
    summary, table = tmp_path / "mc.json", tmp_path / "mc.csv"
    code = main(["montecarlo", "--motions", "8", "--duration", "10s", "--strong-motion", "5s",
                 "--pga", "0.5g", "--vertical-ratio", "1.8", "--isolator", "single-fp", "--radius", "2m",
                 "--json", str(summary), "--out", str(table), "--no-progress"])
    printed = capsys.readouterr().out
    assert code == 0
    payload = json.loads(summary.read_text())
    rows = np.genfromtxt(table, delimiter=",", names=True)
    uplifted = np.flatnonzero(rows["uplift_time_s"] > 0)
    vertical = payload["vertical"]
    assert vertical["n_uplifted"] == uplifted.size > 0
    assert vertical["uplifted_motions"] == uplifted.tolist()
    disp = next(v for k, v in payload["statistics"].items() if k.startswith("base_disp"))
    assert disp["n"] == 8
    assert f"uplift (N <= 0): {uplifted.size} motion(s)" in printed
    assert np.all(np.isfinite(rows["base_disp_m"])) and payload["all_converged"]


def test_montecarlo_vertical_flags_refused_by_name(capsys):
    assert main(["montecarlo", "--motions", "2", "--vertical-ratio", "-0.7"]) != 0
    assert "--vertical-ratio" in capsys.readouterr().err
    assert main(["montecarlo", "--motions", "2", "--vertical-frequency-ratio", "2"]) != 0
    assert "--vertical-frequency-ratio" in capsys.readouterr().err


def test_vertical_motion_model_matches_its_description():
    """The vertical component's nominal peak is vertical_ratio times the horizontal one and
    its site and high-pass frequencies frequency_ratio times theirs; the horizontal component
    is the one-component motion of the same key."""
    import jax

    from teflon_jax.excitation import (
        StochasticGroundMotion,
        VerticalGroundMotion,
        sample,
        sample_with_vertical,
    )

    model = StochasticGroundMotion(peak_ground_acceleration=3.0, duration=10.0, strong_motion_duration=5.0)
    motion = VerticalGroundMotion(model, vertical_ratio=2 / 3, frequency_ratio=2.0)
    v = motion.vertical_model
    assert float(v.peak_ground_acceleration) == pytest.approx(2.0)
    assert float(v.site_frequency) == pytest.approx(2 * float(model.site_frequency))
    assert float(v.high_pass_frequency) == pytest.approx(2 * float(model.high_pass_frequency))
    key = jax.random.key(3)
    both = sample_with_vertical(motion, key, 2)
    assert np.array_equal(np.asarray(both[:, 0]), np.asarray(sample(model, key, 2)))
    with pytest.raises(ValueError, match="vertical_ratio"):
        VerticalGroundMotion(model, vertical_ratio=-1.0)


def test_the_message_of_a_check_inside_a_compiled_run_is_read_out():
    """A check that stops a compiled run (`equinox.error_if`) reaches the command line as its
    own message, whether the run was compiled by `jax.jit` or `equinox.filter_jit`; any other
    runtime error is not taken for one."""
    import equinox as eqx
    import jax
    import jax.numpy as jnp

    from teflon_jax.cli._main import runtime_check_message

    def step(x):
        return eqx.error_if(x, x > 0, "the contact pressure is beyond the table; give the constants")

    for compiled in (jax.jit(step), eqx.filter_jit(step)):
        with pytest.raises(RuntimeError) as caught:
            jax.block_until_ready(compiled(jnp.asarray(1.0)))
        assert runtime_check_message(caught.value) == "the contact pressure is beyond the table; give the constants"
    assert runtime_check_message(RuntimeError("XLA ran out of memory")) is None


@pytest.mark.slow
def test_runs_beyond_the_table_end_a_study_with_their_names_not_a_traceback(tmp_path, capsys):
    """Monte Carlo on Table 1's UF at 6500 psi under vertical components 1.5 times the
    horizontal: the contact pressure passes where Table 1's extended rows give Eq. 1
    constants; the runs that do are named (stderr, JSON), the command ends with exit status 1,
    and no traceback is printed (tests/test_montecarlo_pressure_law.py: the flags themselves)."""
    code = main(["montecarlo", "--motions", "2", "--duration", "4s", "--strong-motion", "2s", "--pga", "0.6g",
                 "--vertical-ratio", "1.5", "--pressure", "6500psi", "--json", str(tmp_path / "mc.json"),
                 "--no-progress"])
    err = capsys.readouterr().err
    assert code == 1
    assert "took the bearings' contact pressure beyond where Table 1's extended end segments give Eq. 1" in err
    payload = json.loads((tmp_path / "mc.json").read_text())
    assert payload["beyond_pressure_law"] and payload["beyond_pressure_law"] == payload["not_converged"]
    assert "Traceback" not in err
