"""The displacement limit of a design holds on the TRUE mean peak base displacement, the one
the design is judged by, not only on the smoothed mean that BFGS differentiates (which lies
below it); a design that cannot meet it is reported as failed, and `teflon-jax design` then
exits non-zero."""

import json

import jax
import numpy as np
import pytest

from teflon_jax.cli._main import main
from teflon_jax.excitation import StochasticGroundMotion, sample
from teflon_jax.studies import expected_response, optimise_design
from teflon_jax.systems import isolated_structure
from teflon_jax.units import PSI

DT = 0.01


@pytest.fixture(scope="module")
def problem():
    model = StochasticGroundMotion(peak_ground_acceleration=3.0, duration=3.0, time_step=DT,
                                   rise_time=0.5, strong_motion_duration=2.0)
    records = sample(model, jax.random.key(2), 2)
    structure = isolated_structure("rigid", time_step=DT, pressure=1000 * PSI, split_at_turn=False,
                                   newton_tolerance=0.0, linear_rule="newmark")
    # a limit between the true mean peaks at the ends of the period range: it binds
    ends = [float(expected_response(structure, {"isolation_period": t}, records, DT)["peak_disp"])
            for t in (1.0, 4.0)]
    return structure, records, 0.5 * (ends[0] + ends[1])


@pytest.mark.slow  # BFGS, its restarts and the gradient check compile: ~45 s on 2 busy cores
def test_optimum_meets_the_limit_on_true_peaks(problem):
    structure, records, limit = problem
    result = optimise_design(structure, records, DT, variables={"isolation_period": (1.0, 4.0)},
                             disp_limit=limit, start={"isolation_period": 2.5})
    again = expected_response(structure, result.optimum, records, DT)
    assert float(again["peak_disp"]) == pytest.approx(result.peak_disp, rel=1e-12)
    assert result.peak_disp <= limit and result.limit_met
    assert result.peak_disp >= 0.99 * limit  # it binds: not a needlessly stiff design
    assert result.mean_disp < result.peak_disp  # the smoothed mean BFGS sees lies below
    assert result.smooth_disp_limit < limit
    assert result.optimiser_converged and result.simulation_converged


@pytest.mark.slow  # sweep, BFGS and gradient check compile: ~60 s on 2 busy cores
def test_design_command_exits_non_zero_when_its_design_breaks_the_limit(tmp_path, capsys):
    out = tmp_path / "d.json"
    code = main(["--no-compile-cache", "design", "--motions", "2", "--duration", "4s", "--strong-motion", "2s",
                 "--time-step", "10ms", "--grid", "2", "--period-range", "1s", "1.2s",
                 "--disp-limit", "0.01in", "--json", str(out), "--no-progress"])
    err = capsys.readouterr().err
    assert code == 1
    assert "breaks --disp-limit 0.01in" in err and "exceeds the limit" in err
    summary = json.loads(out.read_text())
    assert summary["optimum"]["disp_limit_met"] is False
    assert summary["optimum"]["mean_peak_base_disp_in"] > summary["disp_limit_in"] == pytest.approx(0.01)
    assert np.isfinite(summary["optimum"]["smooth_disp_limit_in"])
    assert summary["optimum"]["converged"] is False
    assert isinstance(summary["motions"]["pga_g"], list) and len(summary["motions"]["pga_g"]) == 1
    # the grid's best point is read on the optimum's own objective (the lowered limit), so the
    # comparison the summary reports is the one its two objectives show
    best, optimum = summary["grid_best"]["objective"], summary["optimum"]["objective"]
    assert summary["optimum_beats_grid"] == (optimum <= best * (1 + 1e-9))


@pytest.mark.slow  # sweep, BFGS and gradient check compile: ~50 s on 2 busy cores
def test_flat_sliders_start_bfgs_from_the_grid_best_on_its_own_objective(tmp_path):
    # on flat sliders, as on pendulums, BFGS starts from the grid's best point for the limit on the
    # smoothed peaks lowered as its own (the point grid_best reports), not for the limit as given,
    # which the smoothed peaks, lying below the true ones, meet too late (here: a softer design)
    out, sweep = tmp_path / "d.json", tmp_path / "s.nc"
    code = main(["--no-compile-cache", "design", "--motions", "2", "--duration", "4s", "--strong-motion", "2s",
                 "--time-step", "10ms", "--grid", "5", "--period-range", "1s", "4s", "--disp-limit", "1in",
                 "--json", str(out), "--out", str(sweep), "--no-progress"])
    assert code == 0
    summary = json.loads(out.read_text())
    start, best = summary["bfgs_start"], summary["grid_best"]
    assert start == {name: best[name] for name in start}
    import xarray

    with xarray.open_dataset(sweep) as data:
        given = data["objective_at_disp_limit"].stack(point=data["objective"].dims)
        at_given = given.isel(point=int(np.nanargmin(given.values)))
        assert (float(at_given["isolation_period"]), float(at_given["pressure"])) != pytest.approx(
            (start["isolation_period_s"], start["pressure_psi"] * PSI), rel=1e-9)
