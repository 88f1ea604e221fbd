"""A rigid slab on groups of triple or double friction pendulums: each group is the series model
with its own sliders, every slider's force under the group's normal load N_g = W_g + dN_g, dN_g
the lever rule of the overturning moment h H (held from the step's start); no shear while
N_g <= 0.

Peers: the rigid mass on one pendulum of the same total weight (`simulate_history`,
its own tests against closed forms and OpenSees); the hand lever rule; central differences."""

import json

import equinox as eqx
import jax
import numpy as np
import pytest

from teflon_jax.bearing import BoucWen, DoublePendulum, FrictionParameters, TriplePendulum
from teflon_jax.cli import main
from teflon_jax.excitation import uniform_signal
from teflon_jax.structures import (
    overturning_map,
    redistributed_loads,
    resting_loads,
    support_plan,
)
from teflon_jax.systems import (
    simulate_history,
    slab_on_bearings,
    triple_structure,
)
from teflon_jax.units import STANDARD_GRAVITY

G = STANDARD_GRAVITY
LX, LY, W = 20.0, 12.0, 1.0e6
M = W / G
CORNERS = np.array([[2.0, 1.0], [18.0, 1.0], [18.0, 11.0], [2.0, 11.0]])  # SW, SE, NE, NW
CENTRE = np.array([LX / 2, LY / 2])
DT_RECORD, DURATION, STEP = 0.01, 6.0, 0.005
TIME = np.arange(0.0, DURATION + DT_RECORD / 2, DT_RECORD)
TRIPLE = TriplePendulum(inner_radius=0.3, bottom_radius=2.1, top_radius=2.1, inner_capacity=0.05,
                        bottom_capacity=0.3, top_capacity=0.3,
                        inner_friction=FrictionParameters(0.03, 0.015, 20.0),
                        bottom_friction=FrictionParameters(0.08, 0.03, 20.0),
                        top_friction=FrictionParameters(0.12, 0.05, 20.0), hysteresis=BoucWen(1.27e-4))
DOUBLE = DoublePendulum(bottom_radius=2.1, top_radius=2.1, bottom_capacity=0.3, top_capacity=0.3,
                        bottom_friction=FrictionParameters(0.06, 0.03, 20.0),
                        top_friction=FrictionParameters(0.09, 0.04, 20.0), hysteresis=BoucWen(1.27e-4))
PENDULUMS = {"triple-fp": TRIPLE, "double-fp": DOUBLE}
simulate = jax.jit(simulate_history, static_argnums=1, static_argnames="throw")  # one compilation per pendulum kind


def _ramp(peak_x, peak_y, rise=3.0):
    """A ground acceleration rising smoothly to (peak_x, peak_y) [g] over `rise` s, then held."""
    shape = np.where(TIME < rise, 0.5 - 0.5 * np.cos(np.pi * TIME / rise), 1.0)
    return peak_x * G * shape, peak_y * G * shape


def _pulse(peak_x, peak_y, frequency=0.7):
    shape = np.sin(np.pi * TIME / DURATION) ** 2
    return (peak_x * G * np.sin(2 * np.pi * frequency * TIME) * shape,
            peak_y * G * np.sin(2 * np.pi * 0.55 * frequency * TIME + 1.0) * shape)


def _slab(ax, ay, height, pendulum=TRIPLE, positions=CORNERS):
    return slab_on_bearings(
        length_x=LX, length_y=LY, weight=W, centre_of_mass=CENTRE, positions=positions, loads=[W / 4] * 4,
        ground_acceleration=uniform_signal(ax, DT_RECORD), ground_y=uniform_signal(ay, DT_RECORD), time_step=STEP,
        isolator=pendulum.isolator, pendulums=pendulum, height_of_centre_of_mass=height)


@pytest.mark.parametrize("isolator", [pytest.param("triple-fp", marks=pytest.mark.slow), "double-fp"])
def test_symmetric_slab_moves_as_the_rigid_mass_on_one_pendulum(isolator):
    """Equal groups at the corners, centre of mass on the plan's centre, x motion alone: at h = 0
    the slab is the rigid mass of the same weight on one pendulum (to 1e-9 m; each group carries
    a quarter of every slider's force); at h = 4 m the overturning moves load from one side to
    the other, but every slider's force scales with its group's N_g and the N_g add up to W, so
    the motion is the same and the slab does not twist."""
    pendulum = PENDULUMS[isolator]
    ax, ay = _pulse(0.35, 0.0)
    one = triple_structure("rigid", pendulum, uniform_signal(ax, DT_RECORD), time_step=STEP, weight=W)
    rigid = simulate_history(one, DURATION)
    reference = np.asarray(rigid.displacement[:, 0])
    acceleration = np.asarray(rigid.total_acceleration[:, 0])  # the base shear over the mass
    assert np.max(np.abs(reference)) > 0.1  # the outer surfaces slide
    for height in (0.0, 4.0):
        response = simulate(_slab(ax, ay, height, pendulum), DURATION)
        assert bool(np.all(response.converged))
        assert np.max(np.abs(np.asarray(response.displacement[:, 0]) - reference)) < 1e-9
        assert np.max(np.abs(response.displacement[:, 1:])) < 1e-12
        np.testing.assert_allclose(np.asarray(response.total_acceleration[:, 0]), acceleration, rtol=0,
                                   atol=1e-6 * np.max(np.abs(acceleration)))
    loads = np.asarray(response.normal_load)
    assert np.ptp(loads[:, 0]) > 0.05 * W / 4  # the loads did move
    assert np.allclose(loads.sum(axis=1), W, rtol=1e-12)


def _check_lever_rule(response, ax, ay, height, sign):
    dn = np.asarray(response.normal_load) - W / 4
    expected = overturning_map(CORNERS, CENTRE, height) @ (M * np.array([ax[-1], ay[-1]]))
    assert np.max(np.abs(dn[-1] - expected)) < 0.01 * np.max(np.abs(expected))
    # the hand lever rule of four corners: dN_g = -h (H_x rx / Lx'^2 + H_y ry / Ly'^2)
    r, spacing = CORNERS - CENTRE, np.ptp(CORNERS, axis=0)
    hand = -height * M * (ax[-1] * r[:, 0] / spacing[0] ** 2 + ay[-1] * r[:, 1] / spacing[1] ** 2)
    assert np.allclose(expected, hand, rtol=1e-12)
    # dN sums to zero and balances the moment of the isolators' force one step earlier
    force = -np.asarray(response.bearing_force).sum(axis=1)
    assert np.max(np.abs(dn.sum(axis=1))) < 1e-9 * W
    assert np.allclose(dn[1:] @ r, -height * force[:-1], rtol=0, atol=1e-9 * W * LX)
    unloaded = {name for name, d in zip(("SW", "SE", "NE", "NW"), dn[-1]) if d < 0}
    assert unloaded == ({"SE", "NE"} if sign > 0 else {"SW", "NW"})
    # every group's force over its own N_g is the same (the groups move together): friction
    # and W / R_e of every slider scale with N_g, not with the static W_g
    ratio = np.asarray(response.bearing_force)[1:] / np.asarray(response.normal_load)[1:, :, None]
    assert np.max(np.abs(ratio - ratio[:, :1])) < 1e-9
    assert np.max(np.abs(ratio[-1, :, 0])) > 0.02


@pytest.mark.slow
@pytest.mark.parametrize(("isolator", "sign"), [("triple-fp", 1.0), ("triple-fp", -1.0), ("double-fp", 1.0)])
def test_lever_rule_under_a_slow_ramp_and_the_leaning_side_loads(isolator, sign):
    """Under a slowly ramped, then held ground acceleration the slab comes to move with the
    ground, H = m a_g: each group's dN matches the lever rule within 1 %, the groups on the
    side the ground accelerates towards unload (the inertia force leans the slab the other
    way), and each group's force follows its own N_g."""
    height = 4.0
    ax, ay = _ramp(sign * 0.06, -0.03)
    response = simulate(_slab(ax, ay, height, PENDULUMS[isolator]), DURATION)
    assert bool(np.all(response.converged))
    _check_lever_rule(response, ax, ay, height, sign)


def test_a_lifted_group_carries_no_shear_and_its_sliders_share_its_motion():
    """Groups 4 m apart under a tall centre of mass (h = 20 m): the lever rule asks tension of
    one side; there every slider's force is exactly zero, the sliders share the group's
    increment as R_e (the inner pair 0.6 m, the outer 1.8 m each), the uplift time counts the
    steps with N_g <= 0, and the run stays finite. Under x motion a lifted side leaves the slab
    on two groups on one line: it tips, and exactly those steps are reported as unbalanced."""
    positions = np.array([[8.0, 4.0], [12.0, 4.0], [12.0, 8.0], [8.0, 8.0]])
    ax, ay = _pulse(0.5, 0.0)
    slab = _slab(ax, ay, 20.0, positions=positions)
    with pytest.raises(Exception, match="simulate_history: the slab tipped"):  # raised as the run ends
        jax.block_until_ready(simulate(slab, DURATION))
    response = simulate(slab, DURATION, throw=False)
    loads = np.asarray(response.normal_load)
    lifted = loads <= 0
    assert lifted.any() and np.all(np.isfinite(np.asarray(response.displacement)))
    assert np.array_equal(~np.asarray(response.converged), np.asarray(response.tipped))
    assert np.array_equal(np.asarray(response.tipped)[1:], lifted[1:].any(axis=1))
    assert np.max(np.abs(loads.sum(axis=1) - W)) < 1e-9 * W
    assert np.all(np.asarray(response.bearing_force)[lifted] == 0.0)
    steps = np.diff(np.asarray(response.slider), axis=0)[lifted[1:]]  # (n, S, 2)
    radii = np.array([0.6, 1.8, 1.8])
    assert np.max(np.abs(steps.sum(axis=1))) > 1e-4
    assert np.allclose(steps / radii[:, None], (steps.sum(axis=1) / radii.sum())[:, None], rtol=0, atol=1e-12)
    assert np.allclose(np.asarray(response.group_uplift_time), lifted[1:].sum(axis=0) * STEP)
    time = np.asarray(response.group_uplift_time)  # x motion lifts SW with NW and SE with NE
    assert time[0] == time[3] > 0 and time[1] == time[2] > 0


SQUARE = np.array([[8.0, 4.0], [12.0, 4.0], [12.0, 8.0], [8.0, 8.0]])  # SW, SE, NE, NW, 4 m apart


def test_a_lifted_groups_share_goes_to_the_others():
    """h = 20 m over the 4 m square under a ramped diagonal acceleration of 0.08 g: the lever
    rule leaves the NE group at W/4 - 5 m a = -0.15 W, so the slab rests on the other three,
    whose loads follow from statics alone: 0.8 W (SW) and 0.1 W (SE, NW) under H = m a. At
    every step the loads add up to W, NE carries exactly nothing once lifted, and the moment
    of the loads balances h H of the step before."""
    height = 20.0
    ax, ay = _ramp(0.08, 0.08)
    response = simulate(_slab(ax, ay, height, positions=SQUARE), DURATION)
    loads = np.asarray(response.normal_load)
    assert bool(np.all(response.converged)) and np.all(loads[:, [0, 1, 3]] > 0)
    lifted = loads[:, 2] <= 0
    assert lifted[-1] and np.all(loads[lifted, 2] == 0.0)
    assert np.max(np.abs(loads.sum(axis=1) - W)) < 1e-9 * W
    force = -np.asarray(response.bearing_force).sum(axis=1)
    assert np.allclose(loads[1:] @ (SQUARE - CENTRE), -height * force[:-1], rtol=0, atol=1e-9 * W * LX)
    assert np.allclose(loads[-1], [0.8 * W, 0.1 * W, 0.0, 0.1 * W], rtol=0, atol=0.01 * W)
    assert np.all(np.asarray(response.bearing_force)[1:][lifted[1:], 2] == 0.0)


def test_redistribution_by_statics_and_where_the_slab_cannot_rest():
    """Five groups (the corners and one at (14 m, 6 m)) under a force that lifts the west pair:
    the three others carry the load by statics alone (numpy's solve of the three
    equilibrium equations), whatever their vertical stiffness; the loads sum to W and the west
    pair carries nothing. Four corners whose west pair lifts leave two groups on one line: the
    slab tips (not resting), the west pair carries nothing and the east pair the whole weight,
    in the lever rule's proportion."""
    positions = np.vstack([CORNERS, [[14.0, 6.0]]])
    static = np.array([0.15, 0.2, 0.2, 0.15, 0.3]) * W
    centre = static @ positions / W
    height, force = 8.0, np.array([-0.7 * W, 0.02 * W])
    remaining = [1, 2, 4]
    arms = positions[remaining] - centre
    statics = np.linalg.solve(np.vstack([np.ones(3), arms.T]),
                              np.array([W, *(static @ (positions - centre) - height * force)]))
    assert np.all(statics > 0)
    for stiffness in (None, [1.0, 2.0, 0.5, 1.0, 3.0]):
        linear = static + overturning_map(positions, centre, height, stiffness) @ force
        assert np.all(linear[[0, 3]] < 0) and np.all(linear[remaining] > 0)
        loads = np.asarray(redistributed_loads(support_plan(positions, centre, height, stiffness), static,
                                               linear, force))
        assert np.all(loads[[0, 3]] == 0.0)
        assert np.allclose(loads[remaining], statics, rtol=1e-10)
    linear = W / 4 + overturning_map(CORNERS, CENTRE, 20.0) @ force
    assert np.all(linear[[0, 3]] < 0)
    loads, rests = resting_loads(support_plan(CORNERS, CENTRE, 20.0), np.full(4, W / 4), linear, force)
    loads = np.asarray(loads)
    assert not bool(rests) and np.all(loads[[0, 3]] == 0.0)
    assert np.allclose(loads[[1, 2]], W * linear[[1, 2]] / linear[[1, 2]].sum(), rtol=1e-12)


def test_bad_series_slab_inputs_are_refused_by_name():
    ax, ay = _pulse(0.1, 0.1)
    common = dict(length_x=LX, length_y=LY, weight=W, centre_of_mass=CENTRE, positions=CORNERS,
                  loads=[W / 4] * 4, ground_acceleration=uniform_signal(ax, DT_RECORD),
                  ground_y=uniform_signal(ay, DT_RECORD), time_step=STEP)
    with pytest.raises(ValueError, match=r"pendulums: group 2 is a double-fp, not the triple-fp"):
        slab_on_bearings(**common, isolator="triple-fp", pendulums=[TRIPLE, DOUBLE, TRIPLE, TRIPLE])
    with pytest.raises(ValueError, match=r"pendulums: 2 given for 4 groups"):
        slab_on_bearings(**common, isolator="triple-fp", pendulums=[TRIPLE, TRIPLE])
    with pytest.raises(ValueError, match=r"pendulums: isolator 'double-fp' needs its pendulum"):
        slab_on_bearings(**common, isolator="double-fp")
    with pytest.raises(ValueError, match=r"radii: does not apply to isolator 'triple-fp'"):
        slab_on_bearings(**common, isolator="triple-fp", pendulums=TRIPLE, radii=2.0)
    with pytest.raises(ValueError, match=r"isolation_period: does not apply to isolator 'double-fp'"):
        slab_on_bearings(**common, isolator="double-fp", pendulums=DOUBLE, isolation_period=3.0)
    with pytest.raises(ValueError, match=r"pendulums: apply to isolator 'triple-fp' or 'double-fp'"):
        slab_on_bearings(**common, isolator="single-fp", radii=2.0, pendulums=TRIPLE)


@pytest.mark.slow
def test_the_slab_response_is_differentiable_in_a_surface_friction():
    """d(slab displacement at 2 s)/d(f_max of the top surfaces) through every group's sliders'
    balance (implicit derivative) equals central differences within 1e-4 relative."""
    ax, ay = _pulse(0.4, 0.2)
    base = _slab(ax, ay, 3.0)

    def displacement(f_max):
        friction = FrictionParameters(f_max, 0.05, 20.0)
        system = slab_on_bearings(
            length_x=LX, length_y=LY, weight=W, centre_of_mass=CENTRE, positions=CORNERS, loads=[W / 4] * 4,
            ground_acceleration=base.ground_acceleration, ground_y=base.ground_y, time_step=STEP, isolator="triple-fp",
            pendulums=eqx.tree_at(lambda p: p.top_friction, TRIPLE, friction),
            height_of_centre_of_mass=3.0)
        return simulate_history(system, 2.0).displacement[-1, 0]

    value, slope = jax.jit(jax.value_and_grad(displacement))(0.12)
    h = 1e-5
    forward = jax.jit(displacement)
    central = (forward(0.12 + h) - forward(0.12 - h)) / (2 * h)
    assert abs(float(value)) > 0.01
    assert abs(float(slope) - float(central)) < 1e-4 * abs(float(central))


# --------------------------------------------------------------------------- command line


def _isolator_file(path, pendulum):
    from teflon_jax.formats import write_isolator

    write_isolator(path, pendulum)
    return path


def _plan(tmp_path, height="6m", **group_keys):
    groups = [{"name": n, "x": f"{x}m", "y": f"{y}m", "load": "250kN"}
              for n, (x, y) in zip(("SW", "SE", "NE", "NW"), CORNERS)]
    groups[1].update(group_keys)
    plan = {"length_x": "20m", "length_y": "12m", "weight": "1000kN", "height_of_centre_of_mass": height,
            "groups": groups}
    path = tmp_path / "plan.json"
    path.write_text(json.dumps(plan))
    return path


def _record(tmp_path, seconds=DURATION):
    path = tmp_path / "x.txt"
    ax, _ = _pulse(0.4, 0.0)
    keep = TIME <= seconds + 1e-9
    np.savetxt(path, np.column_stack([TIME[keep], ax[keep] / G]))
    return path


@pytest.fixture()
def files(tmp_path):
    """An isolator file of each kind beside the plan (the plan names them by relative path)."""
    (tmp_path / "isolators").mkdir()
    return {kind: _isolator_file(tmp_path / "isolators" / f"{kind}.json", p) for kind, p in PENDULUMS.items()}


@pytest.mark.parametrize(("isolator", "group", "message"), [
    ("triple-fp", {"radius": "2m"}, "SE.radius does not apply to --isolator triple-fp"),
    ("triple-fp", {"springs": 2.0}, "SE.springs does not apply to --isolator triple-fp"),
    ("double-fp", {"ptfe": "UF"}, "SE.ptfe does not apply to --isolator double-fp"),
    ("triple-fp", {"isolator_file": "isolators/missing.json"}, "SE.isolator_file"),
    ("triple-fp", {"isolator_file": "isolators/double-fp.json"},
     "SE.isolator_file: --isolator-file: isolators/double-fp.json holds a double-fp isolator"),
])
def test_run_refuses_bad_series_plans_by_key_before_reading_records(tmp_path, capsys, files, isolator, group,
                                                                     message):
    plan = _plan(tmp_path, **group)
    code = main(["run", "--structure", "slab", "--plan", str(plan), "--record-x", str(tmp_path / "missing.txt"),
                 "--record-units", "g", "--isolator", isolator, "--isolator-file", str(files[isolator])])
    assert code == 2
    err = capsys.readouterr().err
    assert message.replace("isolators/", str(tmp_path / "isolators") + "/") in err or message in err
    assert "missing.txt" not in err


def test_run_refuses_an_isolator_file_with_single_pendulums(tmp_path, capsys, files):
    record = _record(tmp_path, seconds=1.0)
    plan = _plan(tmp_path, isolator_file="isolators/triple-fp.json")
    code = main(["run", "--structure", "slab", "--plan", str(plan), "--record-x", str(record),
                 "--record-units", "g", "--isolator", "single-fp", "--radius", "88in"])
    assert code == 2
    assert "SE.isolator_file applies with --isolator triple-fp or double-fp only" in capsys.readouterr().err


def test_run_reports_each_groups_normal_load_on_series_pendulums(tmp_path, capsys, files):
    """`run --structure slab --isolator triple-fp`: one group on its own isolator file (a
    triple pendulum of slipperier surfaces); per group the static, peak and least normal load
    and its file; x motion moves load between the west and east pairs, equal and opposite.
    (The record's grid and the step are the other tests': the run reuses their compiled program.)"""
    slippery = eqx.tree_at(lambda p: (p.bottom_friction, p.top_friction), TRIPLE,
                           (FrictionParameters(0.05, 0.02, 20.0), FrictionParameters(0.07, 0.03, 20.0)))
    _isolator_file(tmp_path / "isolators" / "slippery.json", slippery)
    out = tmp_path / "run.json"
    code = main(["run", "--structure", "slab", "--plan", str(_plan(tmp_path, isolator_file="isolators/slippery.json")),
                 "--record-x", str(_record(tmp_path)), "--record-units", "g", "--isolator",
                 "triple-fp", "--isolator-file", str(files["triple-fp"]), "--json", str(out),
                 "--time-step", "0.005s"])
    assert code == 0
    assert "normal load SE: peak" in capsys.readouterr().out
    payload = json.loads(out.read_text())
    groups = payload["normal_load"]["groups"]
    assert groups["SE"]["isolator_file"].endswith("slippery.json")
    assert groups["SW"]["isolator_file"].endswith("triple-fp.json")
    for g in groups.values():
        assert g["min_N"] < g["static_N"] == 250e3 < g["peak_N"] and g["uplift_time_s"] == 0
    assert groups["SW"]["peak_N"] - 250e3 == pytest.approx(250e3 - groups["NE"]["min_N"], rel=0.05)
    peak = payload["peak"]
    assert peak["rotation_rad"] > 0  # the slipperier SE group twists the slab
    assert set(payload["slider_disp_m"]["SE"]) == {"inner", "bottom", "top"}
    assert peak["base_disp_x_m"] > 0.01 and peak["bearing_force_ratio_resultant"] > 0.03
