"""Monte Carlo of a structure built once (`BuiltStructure`): the slab and the building on a
plan of bearing groups, whose builders cannot run inside a vmapped study, run under each motion
with their records replaced (`under_ground`).

Peers: each motion's own run (`monte_carlo_motion`, `peak_response` of the structure under it),
and a run chunked differently."""

import jax
import numpy as np
import pytest
from test_building_on_plan_series import DOUBLE, _eccentric

from teflon_jax.bearing import paper_bearing
from teflon_jax.excitation import (
    StochasticGroundMotion,
    TwoComponentGroundMotion,
    VerticalGroundMotion,
    uniform_signal,
)
from teflon_jax.studies import (
    BuiltStructure,
    monte_carlo,
    monte_carlo_distributed,
    monte_carlo_motion,
)
from teflon_jax.systems import (
    peak_response,
    slab_on_bearings,
    under_ground,
    with_vertical_motion,
)
from teflon_jax.tables import interface_parameters
from teflon_jax.units import PSI

DT, DURATION = 0.01, 3.0
MODEL = StochasticGroundMotion(peak_ground_acceleration=3.5, duration=DURATION, time_step=DT, rise_time=0.5,
                               strong_motion_duration=1.5)
TWO = TwoComponentGroundMotion(MODEL, principal_angle=0.4, minor_ratio=0.7)
ZERO = uniform_signal(np.zeros(int(round(DURATION / DT)) + 1), DT)


def _slab():
    """A 1000 kN slab 3 m tall on four single pendulum groups, its mass off the plan's centre."""
    bearing = paper_bearing(interface_parameters("UF", 1000 * PSI)[0], yield_disp=1e-3)
    return slab_on_bearings(
        length_x=20.0, length_y=12.0, weight=1e6, centre_of_mass=[12.0, 7.0],
        positions=[[2.0, 1.0], [18.0, 1.0], [18.0, 11.0], [2.0, 11.0]], loads=[1.5e5, 2.5e5, 3.75e5, 2.25e5],
        ground_acceleration=ZERO, ground_y=ZERO, time_step=0.005, isolator="single-fp", bearings=bearing, radii=2.2,
        height_of_centre_of_mass=3.0)


def _each_motion(system, model, key, count, groups=None):
    """(base displacement, base shear ratio) (count,) of each motion's own run; with a list
    `groups`, each run's group loads ((G,) largest, least, uplift time) appended to it."""
    peaks = []
    for index in range(count):
        rows = [uniform_signal(row, DT) for row in np.asarray(monte_carlo_motion(model, key, index))]
        vertical = rows.pop() if isinstance(model, VerticalGroundMotion) else None
        run = peak_response(under_ground(system, *rows, ground_z=vertical), DURATION)
        assert bool(run.converged)
        if groups is not None:
            groups.append([np.asarray(run["group_normal_load"][k]) for k in ("peak_N", "min_N", "uplift_time_s")])
        peaks.append((float(run.base_disp), float(run.base_shear_ratio)))
    return np.array(peaks).T


def test_a_slab_on_a_plan_runs_each_motion_as_its_own_run():
    """Three two-component motions through the slab on its groups, in chunks of two: each
    motion's resultant peaks and each group's largest and least normal load and uplift time are
    those of its own run (to 1e-9), whatever the chunking; the groups' loads swing about their
    static shares (the slab's overturning)."""
    key, slab, groups = jax.random.key(3), _slab(), []
    result = monte_carlo(BuiltStructure(slab), TWO, 3, key=key, chunk_size=2)
    again = monte_carlo(BuiltStructure(slab), TWO, 3, key=key, chunk_size=3)
    disp, shear = _each_motion(slab, TWO, key, 3, groups)
    assert result.converged.all() and disp.min() > 0.02
    peak, least, lifted = (np.array(g) for g in zip(*groups))
    np.testing.assert_allclose(result.group_peak_load, peak, rtol=1e-9)
    np.testing.assert_allclose(result.group_min_load, least, rtol=1e-9)
    np.testing.assert_allclose(result.group_uplift_time, lifted, atol=1e-12)
    static = np.array([1.5e5, 2.5e5, 3.75e5, 2.25e5])
    assert (peak > 1.01 * static).all() and (least < 0.99 * static).all()
    assert result.group_names == ["group 1", "group 2", "group 3", "group 4"]
    np.testing.assert_allclose(result.base_disp, disp, rtol=1e-9)
    np.testing.assert_allclose(result.base_shear_ratio, shear, rtol=1e-9)
    np.testing.assert_allclose(again.base_disp, result.base_disp, rtol=1e-12)
    np.testing.assert_allclose(result.pga, [np.hypot(*np.asarray(monte_carlo_motion(TWO, key, i))).max()
                                            for i in range(3)], rtol=1e-12)


@pytest.mark.slow  # 30 s on two cores; the fast set runs the built building on flat sliders (test_montecarlo_plan_cli)
def test_a_building_on_series_groups_runs_each_motion_with_its_vertical_component():
    """The building on five double pendulum groups under two horizontal components and a
    vertical one (each motion's replaces the structure's record): each motion's peaks are its
    own run's, and the vertical component does move them."""
    key = jax.random.key(5)
    building = with_vertical_motion(_eccentric(DOUBLE, base_height=0.5)[0], ZERO)
    model = VerticalGroundMotion(TWO, vertical_ratio=0.6)
    result = monte_carlo(BuiltStructure(building), model, 2, key=key, chunk_size=2)
    disp, shear = _each_motion(building, model, key, 2)
    assert result.converged.all()
    np.testing.assert_allclose(result.base_disp, disp, rtol=1e-9)
    np.testing.assert_allclose(result.base_shear_ratio, shear, rtol=1e-9)
    flat_ground = monte_carlo(BuiltStructure(building), VerticalGroundMotion(TWO, vertical_ratio=0.0), 2, key=key)
    assert np.max(np.abs(flat_ground.base_shear_ratio / result.base_shear_ratio - 1)) > 1e-3


def test_what_a_built_structure_cannot_take_is_refused_by_name():
    """No design variables (the structure is not rebuilt); records that do not fit the
    structure are named."""
    slab = _slab()
    with pytest.raises(ValueError, match="design: a BuiltStructure is built once"):
        monte_carlo(BuiltStructure(slab), TWO, 2, design={"isolation_period": [2.0, 3.0]})
    with pytest.raises(ValueError, match="ground_y: the structure steps under 2 horizontal component"):
        under_ground(slab, ZERO)
    with pytest.raises(ValueError, match="ground_z: the structure has no vertical record to replace"):
        under_ground(slab, ZERO, ZERO, ground_z=ZERO)
    with pytest.raises(ValueError, match="motions with a vertical component"):
        monte_carlo(BuiltStructure(slab), VerticalGroundMotion(TWO), 2)


@pytest.mark.slow
def test_a_slab_on_a_plan_runs_on_a_cluster_as_in_this_process(dask_cluster, tmp_path):
    """The built slab pickles to the workers: a run on the cluster, chunk for chunk, gives the
    in-process run's peaks bit for bit."""
    slab = _slab()
    here = monte_carlo(BuiltStructure(slab), TWO, 3, key=jax.random.key(3), chunk_size=2)
    there = monte_carlo_distributed(BuiltStructure(slab), TWO, 3, seed=3, out=tmp_path / "mc.nc",
                                    scheduler=dask_cluster.scheduler_address, chunk_size=2)
    assert there.converged.all()
    np.testing.assert_array_equal(there.base_disp, here.base_disp)
    np.testing.assert_array_equal(there.base_shear_ratio, here.base_shear_ratio)
    for name in ("group_peak_load", "group_min_load", "group_uplift_time"):
        np.testing.assert_array_equal(getattr(there, name), getattr(here, name))
