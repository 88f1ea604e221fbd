"""The sweep file of `teflon-jax design --out` holds the objective the command chooses its grid
best by (the limit on the smoothed peaks lowered as the optimiser's), so the file's best row
is the summary's `grid_best`; the sweep's own objective, at the limit as given, is kept beside
it under its own name."""

import json

import numpy as np
import pytest
import xarray

import teflon_jax.studies as studies
from teflon_jax.cli._main import main
from teflon_jax.studies import DesignResult

LOWERED = 1e-4  # [m]: a lowered limit far below every smoothed peak, so that it decides the best row


def _optimum(structure, records, dt, *, variables, disp_limit, penalty, start, limit_statistic):
    """A stand-in for `optimise_design` (the file's bookkeeping is under test, not BFGS): its
    start, with a lowered limit that moves the grid's best point."""
    return DesignResult(
        optimum=dict(start), objective=1.0, mean_shear=0.1, mean_disp=0.01, peak_shear=0.1, peak_disp=0.01,
        disp_limit=disp_limit, smooth_disp_limit=LOWERED, limit_met=True, start=dict(start), steps=1,
        optimiser_converged=True, simulation_converged=True, n_failed_motions=0, at_bounds=(),
        gradient_rel_error=0.0, gradient={}, finite_differences={}, converged=True, messages=(), wall_s=0.0)


def test_best_row_of_the_sweep_file_is_the_grid_best(tmp_path, monkeypatch):
    monkeypatch.setattr(studies, "optimise_design", _optimum)
    out, summary = tmp_path / "sweep.nc", tmp_path / "design.json"
    # a limit as given that no grid point reaches: the sweep's own objective is the shear alone
    assert main(["--no-compile-cache", "design", "--motions", "2", "--duration", "4s", "--strong-motion", "2s",
                 "--time-step", "10ms", "--grid", "3", "--period-range", "1s", "4s", "--pressure", "1000psi",
                 "--disp-limit", "100in", "--out", str(out), "--json", str(summary), "--no-progress"]) == 0
    best = json.loads(summary.read_text())["grid_best"]
    with xarray.open_dataset(out) as sweep:
        sweep = sweep.load()
    row = sweep["objective"].argmin(...)  # the best row of the file by its objective column
    assert float(sweep["isolation_period"][row["isolation_period"]]) == pytest.approx(best["isolation_period_s"])
    assert float(sweep["objective"].min()) == pytest.approx(best["objective"], rel=1e-12)
    assert sweep.attrs["smooth_disp_limit_m"] == pytest.approx(LOWERED)
    assert "lowered" in sweep["objective"].attrs["long_name"]
    # the sweep's own objective, at the limit as given, is kept and chooses another row here
    shear = sweep["shear"].values
    np.testing.assert_allclose(sweep["objective_at_disp_limit"].values, shear, rtol=1e-12)
    assert int(np.argmin(shear)) != int(row["isolation_period"])


def test_a_streamed_sweep_file_takes_the_lowered_objective(tmp_path):
    """The layout a cluster streams (`design_sweep_distributed`) takes it too; a point that did
    not converge has no objective to choose by (NaN, its `converged` 0), and a second call keeps
    the sweep's own objective."""
    from teflon_jax.studies._cluster import add_attributes, create_netcdf
    from teflon_jax.studies._design_sweep import _sweep_layout

    periods = np.array([1.0, 2.0, 3.0])
    shear, disp = np.array([0.3, 0.2, 0.1]), np.array([0.01, 0.02, 0.03])
    sweep = {"grid": {"isolation_period": periods}, "shear": shear, "disp": disp, "objective": shear,
             "converged": np.array([False, True, True]), "n_failed": np.array([1, 0, 0]), "n_motions": 2}
    out = tmp_path / "sweep.nc"
    handle = create_netcdf(out, **_sweep_layout(["isolation_period"], [periods], {"n_motions": 2}))
    with handle:
        for name in ("objective", "shear", "disp", "n_failed"):
            handle.variables[name][:] = sweep[name]
        handle.variables["converged"][:] = sweep["converged"].astype(np.int8)
    add_attributes(out, {"complete": 1})
    for _ in range(2):
        studies.write_design_objective(out, sweep, 0.015, penalty=100.0)
    again = studies.open_sweep(out)
    expected = studies.sweep_objective(sweep, 0.015, 100.0)
    assert np.isnan(again["objective"][0]) and np.isnan(expected[0])
    np.testing.assert_allclose(again["objective"][1:], expected[1:], rtol=1e-15)
    assert int(np.nanargmin(again["objective"])) == 1  # the penalty moves the best point off the least shear
    with xarray.open_dataset(out) as file:
        np.testing.assert_array_equal(file["objective_at_disp_limit"].values, shear)
