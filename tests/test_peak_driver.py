"""One peak driver (`systems.peak_response`) over every engine: the peaks it folds along a run
are the `REDUCERS` of the response, the same as `studies.response_peaks` takes over the saved
history of the same system and motion (`simulate_history`), for flat sliders and series
pendulums in one and two components and with a vertical record, and for a slab on groups of
double pendulums and the building on a plan of flat sliders, whose overturning moves load
between the groups (each group's largest and least normal load and uplift time, the same
as by hand from the history); and its base shear is the
force the bearings carry over the weight, sum_j m_j a_j^total / (g sum_j m_j), computed here by
hand from the history."""

import numpy as np
import pytest

from teflon_jax.bearing import (
    BoucWen,
    DoublePendulum,
    FrictionParameters,
    SlidingBearing,
    TriplePendulum,
)
from teflon_jax.excitation import uniform_signal
from teflon_jax.studies import bidirectional_isolated_structure, response_peaks
from teflon_jax.systems import (
    REDUCERS,
    bidirectional_storey_peaks,
    building_on_plan,
    isolated_structure,
    peak_response,
    response_layout,
    simulate_history,
    slab_on_bearings,
    triple_structure,
    with_vertical_motion,
)
from teflon_jax.units import STANDARD_GRAVITY

STEP = 0.01
DURATION = 1.5
TIME = np.arange(0.0, DURATION + 1e-9, STEP)
AX = 4.0 * np.sin(2 * np.pi * TIME) * np.minimum(TIME / 0.3, 1.0)
AY = 3.0 * np.cos(2 * np.pi * 1.3 * TIME) * np.minimum(TIME / 0.3, 1.0)
AZ = -11.0 * np.sin(2 * np.pi * 2.0 * TIME) ** 8  # N <= 0 near the crests
HEIGHT = 3.0
TRIPLE = TriplePendulum(inner_radius=0.3, bottom_radius=2.1, top_radius=2.1, inner_capacity=0.05,
                        bottom_capacity=0.4, top_capacity=0.4, inner_friction=FrictionParameters(0.03, 0.015, 20.0),
                        bottom_friction=FrictionParameters(0.07, 0.03, 20.0),
                        top_friction=FrictionParameters(0.11, 0.05, 20.0), hysteresis=BoucWen(1e-4))


DOUBLE = DoublePendulum(bottom_radius=2.1, top_radius=2.1, bottom_capacity=0.3, top_capacity=0.3,
                        bottom_friction=FrictionParameters(0.06, 0.03, 20.0),
                        top_friction=FrictionParameters(0.09, 0.04, 20.0), hysteresis=BoucWen(1.27e-4))

SLIDERS = SlidingBearing(friction=FrictionParameters(0.08, 0.04, 20.0), hysteresis=BoucWen(1.27e-4))


def _system(engine):
    gx, gy, gz = (uniform_signal(a, STEP) for a in (AX, AY, AZ))
    if engine == "series-slab":  # four corner groups, the centre of mass 4 m above them
        return slab_on_bearings(length_x=20.0, length_y=12.0, weight=1e6, centre_of_mass=[10.0, 6.0],
                                positions=[[2.0, 1.0], [18.0, 1.0], [18.0, 11.0], [2.0, 11.0]], loads=[2.5e5] * 4,
                                ground_acceleration=gx, ground_y=gy, time_step=STEP, isolator="double-fp", pendulums=DOUBLE,
                                height_of_centre_of_mass=4.0)
    if engine == "flat-building-plan":  # Table 2's building on the plan: its groups' loads move with the
        # overturning moment of the levels' inertia forces at their own heights
        return building_on_plan(
            length_x=20.0, length_y=12.0, centre_of_mass=[10.0, 6.0],
            positions=[[2.0, 1.0], [18.0, 1.0], [18.0, 11.0], [2.0, 11.0]], loads=[672 * 4448.2216152605 / 4] * 4,
            bearings=SLIDERS, ground_acceleration=gx, ground_y=gy, time_step=STEP, isolation_period=2.5)
    if engine == "flat-1c":
        return isolated_structure("building")(gx)
    if engine == "flat-2c":
        return bidirectional_isolated_structure("building")((gx, gy))
    if engine == "flat-1c-vertical":
        return with_vertical_motion(isolated_structure("rigid")(gx), gz)
    series = triple_structure("building", TRIPLE, gx, time_step=STEP)
    if engine == "series-1c":
        return series
    if engine == "series-2c":
        return series.with_y_component(gy)
    return with_vertical_motion(triple_structure("rigid", TRIPLE, gx, time_step=STEP), gz)  # series-1c-vertical


ENGINES = ["flat-1c", "flat-2c", "flat-1c-vertical", "series-1c", "series-2c", "series-1c-vertical", "series-slab",
           "flat-building-plan"]


@pytest.mark.parametrize("engine", ENGINES)
def test_the_peaks_along_a_run_are_the_reducers_over_its_history(engine):
    system = _system(engine)
    layout = response_layout(system)
    history = simulate_history(system, DURATION)
    height = HEIGHT if layout.building else None  # storey results are refused for a rigid mass
    saved = response_peaks(layout, history, height)
    folded = peak_response(system, DURATION, reducers=tuple(REDUCERS), storey_height=height)
    assert bool(folded["converged"]) and bool(history.succeeded)
    common = [k for k in saved if k in folded]
    assert {"base_disp", "base_disp_resultant", "base_shear_ratio_resultant"} <= set(common)
    assert ("group_normal_load" in common) == ("plan" in engine or "slab" in engine)  # overturning groups only
    for name in common:  # the flat engine's history is its diffrax solve: the same step to rounding
        np.testing.assert_allclose(np.asarray(folded[name]) if name != "group_normal_load" else
                                   np.array([folded[name][k] for k in ("peak_N", "min_N", "uplift_time_s")]),
                                   np.asarray(saved[name]) if name != "group_normal_load" else
                                   np.array([saved[name][k] for k in ("peak_N", "min_N", "uplift_time_s")]),
                                   rtol=1e-8, atol=1e-12, err_msg=name)
    if "group_normal_load" in common:  # each group's extremes by hand, the rest's load among them
        loads = np.asarray(history.normal_load)
        group = folded["group_normal_load"]
        np.testing.assert_allclose(np.asarray(group["peak_N"]), loads.max(axis=0), rtol=1e-8)
        np.testing.assert_allclose(np.asarray(group["min_N"]), loads.min(axis=0), rtol=1e-8)
        np.testing.assert_allclose(np.asarray(group["uplift_time_s"]), (loads[1:] <= 0).sum(axis=0) * STEP)
        assert np.all(np.asarray(group["min_N"]) < loads[0]) and np.all(loads[0] < np.asarray(group["peak_N"]))
    if engine == "series-slab":  # read every 5th step, as the other peaks: the rest and steps 5, 10, ...
        sparse = peak_response(system, DURATION, read_every=5)["group_normal_load"]
        read = loads[np.r_[0, 5:len(loads):5]]
        np.testing.assert_allclose(np.asarray(sparse["peak_N"]), read.max(axis=0), rtol=1e-8)
        np.testing.assert_allclose(np.asarray(sparse["min_N"]), read.min(axis=0), rtol=1e-8)
        np.testing.assert_allclose(np.asarray(sparse["uplift_time_s"]), np.asarray(group["uplift_time_s"]))
    # the base shear by hand: every mass's inertia force over the whole weight
    mass = np.asarray(layout.mass)
    force = np.asarray(history.total_acceleration) @ (mass[:, None] * np.asarray(layout.influence))
    shear = np.hypot(*force.T) if force.shape[1] == 2 else np.abs(force[:, 0])
    expected = shear.max() / (STANDARD_GRAVITY * mass @ np.asarray(layout.influence)[:, 0])
    np.testing.assert_allclose(float(folded.base_shear_ratio), expected, rtol=1e-8)
    base = np.asarray(history.displacement)[:, [row[0] for row in layout.levels]]
    np.testing.assert_allclose(float(folded.base_disp), np.hypot(*base.T).max() if base.shape[1] == 2
                               else np.abs(base).max(), rtol=1e-8)
    if engine == "flat-building-plan":  # `building_on_plan`'s coordinates: x: base, floors 1-6; y: the same; rotation
        q = np.asarray(history.displacement)
        assert layout.building and layout.rotation == 14
        np.testing.assert_allclose(float(folded.base_disp), np.hypot(q[:, 0], q[:, 7]).max(), rtol=1e-8)
        drift = np.hypot(np.diff(q[:, 0:7], axis=1), np.diff(q[:, 7:14], axis=1)).max(axis=0) / HEIGHT
        np.testing.assert_allclose(np.asarray(saved["storey_drift_ratio_resultant"]), drift, rtol=1e-8)
        storeys = bidirectional_storey_peaks(history, system, HEIGHT)  # the same read of the coordinates
        np.testing.assert_allclose(storeys["storey_drift_resultant"], drift, rtol=1e-8)
    if layout.building:
        levels = np.asarray(history.displacement)[:, np.array(layout.levels)]
        drift = np.abs(np.diff(levels, axis=-1)).max(axis=0) / HEIGHT
        np.testing.assert_allclose(np.asarray(folded["storey_drift_ratio"]), drift, rtol=1e-8, atol=1e-14)
    if "vertical" in engine:
        dt = float(system.time_step)  # the record interpolated at each step's end
        ends = np.arange(1, round(DURATION / dt) + 1) * dt
        lifted = np.sum(1 + np.interp(ends, TIME, AZ) / STANDARD_GRAVITY <= 0) * dt
        assert lifted > 0 and float(folded.uplift_time) == pytest.approx(lifted, abs=1e-12)


def test_unknown_reducers_are_refused_by_name():
    system = _system("flat-1c")
    with pytest.raises(ValueError, match="reducers: unknown 'base_sheer'"):
        peak_response(system, DURATION, reducers=("base_sheer",))
    with pytest.raises(ValueError, match="smooth: 'base_disp' not among"):
        peak_response(system, DURATION, reducers=("base_disp_resultant",), smooth={"base_disp": 1e-3})
