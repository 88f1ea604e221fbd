"""Monte Carlo with two ground components on the bidirectional rigid mass and building.

References: the full histories of `simulate_history` (peaks taken with NumPy), the
uniaxial Monte Carlo (a motion along one line on isotropic bearings is the uniaxial motion,
Park's Z reducing to Bouc-Wen's), and `monte_carlo_motion` for the motions a run used.
"""

import json
import math
import os
import subprocess
import sys

import jax
import numpy as np
import pytest

from teflon_jax.cli._main import main
from teflon_jax.excitation import (
    StochasticGroundMotion,
    TwoComponentGroundMotion,
    uniform_signal,
)
from teflon_jax.studies import (
    MonteCarloResult,
    bidirectional_isolated_structure,
    monte_carlo,
    monte_carlo_motion,
)
from teflon_jax.systems import isolated_structure, peak_response, simulate_history
from teflon_jax.units import PSI, STANDARD_GRAVITY

MODEL = StochasticGroundMotion(peak_ground_acceleration=3.0, duration=3.0, time_step=0.01, rise_time=0.5,
                               strong_motion_duration=1.5)


@pytest.mark.slow
def test_peaks_are_the_resultants_of_the_full_history():
    """Peak resultant bearing displacement and base shear (force on everything above the
    bearings over its weight) equal those of `simulate_history`'s histories."""
    motion = TwoComponentGroundMotion(MODEL, principal_angle=0.6, minor_ratio=0.7)
    ax, ay = np.asarray(monte_carlo_motion(motion, jax.random.key(4), 0))
    structure = bidirectional_isolated_structure("rigid", time_step=0.005, pressure=2000 * PSI,
                                                 isolation_period=1.5)
    system = structure((uniform_signal(ax, 0.01), uniform_signal(ay, 0.01)))
    peaks = peak_response(system, 3.0)
    history = simulate_history(system, 3.0)
    disp = np.hypot(*np.asarray(history.bearing_displacement)[:, 0].T)
    mass = np.asarray(system.mass)[0]
    total = np.asarray(history.total_acceleration)  # rigid mass: q = (u_x, u_y)
    shear = np.hypot(*total.T) * mass / (mass * STANDARD_GRAVITY)
    assert bool(peaks.converged) and bool(history.succeeded)
    np.testing.assert_allclose(peaks.base_disp, disp.max(), rtol=1e-8)
    np.testing.assert_allclose(peaks.base_shear_ratio, shear.max(), rtol=1e-6)
    assert disp.max() > 5e-3 and 0.3 * disp.max() < np.abs(np.asarray(history.displacement)[:, 1]).max()  # both directions slide


@pytest.mark.slow
def test_zero_minor_component_gives_the_uniaxial_result_along_the_principal_direction():
    """gamma = 0 at theta = 35 deg on isotropic bearings: every motion's peaks are those of the
    uniaxial run of the same seed (its motion i is the major component), although the two runs
    are chunked differently (motion i's key depends on the seed and i only). Without breakaway:
    the two solvers switch Eq. 17 off one step apart (uniaxial: at the step after |Z| reaches
    0.999; bidirectional: at that step), which moves the peaks by about 1e-4."""
    options = {"time_step": 0.005, "pressure": 2000 * PSI, "isolation_period": 1.5, "breakaway": False}
    key = jax.random.key(9)
    # the uniaxial run with the update the bidirectional step uses (Z along the net increment,
    # Newmark's rule)
    one = monte_carlo(isolated_structure("rigid", split_at_turn=False, linear_rule="newmark", **options), MODEL, 3,
                      key=key)
    two = monte_carlo(bidirectional_isolated_structure("rigid", **options),
                      TwoComponentGroundMotion(MODEL, principal_angle=math.radians(35), minor_ratio=0.0), 3,
                      key=key, chunk_size=2)
    assert two.converged.all() and one.converged.all()
    np.testing.assert_allclose(two.base_disp, one.base_disp, rtol=1e-6)
    np.testing.assert_allclose(two.base_shear_ratio, one.base_shear_ratio, rtol=1e-6)
    np.testing.assert_allclose(two.pga, one.pga, rtol=1e-12)
    assert two.attrs["components"] == 2 and two.attrs["minor_ratio"] == 0.0


@pytest.mark.slow
def test_montecarlo_command_with_two_components(tmp_path):
    """A small run through the command line: NetCDF and JSON written, the statistics those of
    the file's converged runs, pga the resultant of the motions the run says it drew; the same
    run as Dask tasks (--scheduler local:1, chunks of 2) gives the same peaks."""
    out, summary = tmp_path / "mc.nc", tmp_path / "mc.json"
    argv = ["montecarlo", "--motions", "3", "--components", "2", "--principal-angle", "30deg",
            "--minor-ratio", "0.7", "--duration", "3s", "--strong-motion", "1s", "--seed", "5",
            "--time-step", "5ms", "--units", "si", "--no-progress"]
    status = main(argv + ["--out", str(out), "--json", str(summary)])
    assert status == 0
    payload = json.loads(summary.read_text())
    result = MonteCarloResult.open(out)
    assert payload["n_converged"] == 3 and result.converged.all()
    assert payload["motions"]["minor_ratio"] == 0.7
    assert payload["motions"]["principal_angle_deg"] == pytest.approx(30.0)
    assert result.attrs["components"] == 2
    assert payload["statistics"]["base_disp_mm"]["p50"] == pytest.approx(1e3 * np.median(result.base_disp))
    assert payload["statistics"]["base_shear_ratio"]["mean"] == pytest.approx(result.base_shear_ratio.mean())
    model = StochasticGroundMotion(peak_ground_acceleration=0.3 * STANDARD_GRAVITY,
                                   site_frequency=2 * math.pi * 15.6 / (2 * math.pi),
                                   site_damping=0.6, high_pass_frequency=15.6 / 10,
                                   strong_motion_duration=1.0, duration=3.0, time_step=0.01)
    motion = TwoComponentGroundMotion(model, principal_angle=math.radians(30), minor_ratio=0.7)
    ax, ay = np.asarray(monte_carlo_motion(motion, jax.random.key(5), 2))
    assert result.pga[2] == pytest.approx(np.hypot(ax, ay).max(), rel=1e-12)
    distributed = tmp_path / "dask.nc"
    # in a process of its own, as a user runs it (and out of pytest's warnings-as-errors: a
    # dashboard port taken by another cluster on the machine is only a warning there)
    env = {k: v for k, v in os.environ.items() if k != "XLA_FLAGS"}
    done = subprocess.run([sys.executable, "-m", "teflon_jax.cli", *argv, "--scheduler", "local:1",
                           "--chunk-size", "2", "--out", str(distributed)],
                          env=dict(env, JAX_PLATFORMS="cpu"), capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stderr[-2000:]
    tasks = MonteCarloResult.open(distributed)
    assert tasks.attrs["components"] == 2
    np.testing.assert_allclose(tasks.base_disp, result.base_disp, rtol=1e-12)
    np.testing.assert_allclose(tasks.base_shear_ratio, result.base_shear_ratio, rtol=1e-12)
    np.testing.assert_allclose(tasks.pga, result.pga, rtol=1e-12)


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--minor-ratio", "0.7"], "--minor-ratio: describes the second ground component; add --components 2"),
        (["--principal-angle", "30deg"], "--principal-angle: describes the second ground component"),
        (["--components", "2", "--minor-ratio", "1.5"], "--minor-ratio: must be <= 1"),
        (["--components", "2", "--minor-ratio=-0.2"], "--minor-ratio: must be >= 0"),
        (["--components", "2", "--principal-angle", "30"], "--principal-angle: '30' has no unit; write e.g. '30deg'"),
        (["--components", "2", "--principal-angle", "30m"], "--principal-angle: unknown angle unit 'm'"),
        (["--components", "3"], "--components: invalid choice: 3"),
    ],
)
def test_bad_two_component_flags_are_refused_by_name(argv, message, capsys):
    try:
        status = main(["montecarlo", "--motions", "2", "--no-progress"] + argv)
    except SystemExit as exit_:  # argparse's own refusals
        status = exit_.code
    assert status == 2
    assert message in capsys.readouterr().err


@pytest.mark.slow
def test_two_component_runs_that_did_not_converge_are_reported(tmp_path, capsys):
    """A real failure of the bidirectional bearing solve (one Newton iteration per step; a
    failure that the peaks function carries from every step) makes
    the command exit 1 naming the runs, and the statistics rest on the converged runs only."""
    status = main(["montecarlo", "--motions", "3", "--components", "2", "--duration", "3s",
                   "--strong-motion", "1s", "--time-step", "5ms", "--newton-iterations", "1",
                   "--no-progress", "--json", str(tmp_path / "mc.json"), "--out", str(tmp_path / "mc.nc")])
    assert status == 1
    summary = json.loads((tmp_path / "mc.json").read_text())
    result = MonteCarloResult.open(tmp_path / "mc.nc")
    failed = np.flatnonzero(~result.converged).tolist()
    assert failed and summary["not_converged"] == failed
    assert f"{len(failed)} of 3 runs" in capsys.readouterr().err
    assert summary["statistics"]["base_disp_in"]["n"] == 3 - len(failed)
