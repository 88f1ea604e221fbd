"""A rigid slab on single friction pendulum groups with overturning: each group restores with
N_g / R_g at its position, and its normal load N_g = W_g + dN_g follows the moment h H of the
horizontal force H (a rigid slab on vertical supports, H held from the step's start)."""

import dataclasses
import json

import jax
import numpy as np
import pytest

from teflon_jax.bearing import paper_bearing
from teflon_jax.cli import main
from teflon_jax.excitation import uniform_signal
from teflon_jax.structures import overturning_map
from teflon_jax.systems import (
    peak_response,
    rigid_mass,
    simulate_history,
    slab_on_bearings,
)
from teflon_jax.tables import interface_parameters
from teflon_jax.units import PSI, STANDARD_GRAVITY

G = STANDARD_GRAVITY
LX, LY, W, R = 20.0, 12.0, 1.0e6, 2.0
M = W / G
CORNERS = np.array([[2.0, 1.0], [18.0, 1.0], [18.0, 11.0], [2.0, 11.0]])  # SW, SE, NE, NW
CENTRE = np.array([LX / 2, LY / 2])
DT_RECORD, DURATION, STEP = 0.01, 6.0, 0.005
TIME = np.arange(0.0, DURATION + DT_RECORD / 2, DT_RECORD)
BEARING = paper_bearing(interface_parameters("UF", 1000 * PSI)[0], yield_disp=1e-3)


def _ramp(peak_x, peak_y, rise=3.0):
    """A ground acceleration rising smoothly to (peak_x, peak_y) [g] over `rise` s, then held."""
    shape = np.where(TIME < rise, 0.5 - 0.5 * np.cos(np.pi * TIME / rise), 1.0)
    return peak_x * G * shape, peak_y * G * shape


def _pulse(peak_x, peak_y, frequency=0.7):
    shape = np.sin(np.pi * TIME / DURATION) ** 2
    return (peak_x * G * np.sin(2 * np.pi * frequency * TIME) * shape,
            peak_y * G * np.sin(2 * np.pi * 0.55 * frequency * TIME + 1.0) * shape)


def _slab(ax, ay, height, *, positions=CORNERS, radii=R, step=STEP, centre=CENTRE):
    return slab_on_bearings(
        length_x=LX, length_y=LY, weight=W, centre_of_mass=centre, positions=positions,
        bearings=BEARING, loads=[W / 4] * 4, ground_acceleration=uniform_signal(ax, DT_RECORD),
        ground_y=uniform_signal(ay, DT_RECORD), time_step=step, isolator="single-fp",
        radii=radii, height_of_centre_of_mass=height)


def _lever_rule(positions, height, force):
    """dN of four groups at the corners of a rectangle centred on the centre of mass, by hand:
    sum rx^2 = Lx'^2 (Lx' the spacing), so dN_g = -h (H_x rx_g / Lx'^2 + H_y ry_g / Ly'^2)."""
    r = positions - CENTRE
    spacing = np.ptp(positions, axis=0)
    return -height * (force[0] * r[:, 0] / spacing[0] ** 2 + force[1] * r[:, 1] / spacing[1] ** 2)


def _isolation_force(system, response):
    """H(t) (nt, 2) [N] from the groups' own forces: friction plus max(N_g, 0) / R_g d_g."""
    loads = np.maximum(np.asarray(response.normal_load), 0.0)
    pendulum = (loads / R)[..., None] * np.asarray(response.bearing_displacement)
    return -(np.asarray(response.friction_force) + pendulum).sum(axis=1)


@pytest.mark.slow
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_static_lever_rule_and_which_groups_unload(sign):
    """Under a slowly ramped constant ground acceleration the slab comes to move with the
    ground, H = m a_g: each group's dN matches the hand lever rule within 1 %; dN sums to zero
    and balances the moment of the force one step earlier at every step (the held force); the
    groups on the side the ground accelerates towards unload (SE, NE for +x; SW, NW for -x)."""
    height = 4.0
    ax, ay = _ramp(sign * 0.06, -0.03)
    system = _slab(ax, ay, height)
    response = simulate_history(system, DURATION)
    dn = np.asarray(response.normal_load) - W / 4
    expected = _lever_rule(CORNERS, height, M * np.array([ax[-1], ay[-1]]))
    assert np.max(np.abs(dn[-1] - expected)) < 0.01 * np.max(np.abs(expected))
    assert np.max(np.abs(dn.sum(axis=1))) < 1e-9 * W
    force = M * np.asarray(response.total_acceleration)[:, :2]
    r = CORNERS - CENTRE
    assert np.allclose(dn[1:] @ r, -height * force[:-1], rtol=0, atol=1e-9 * W * LX)
    # the equation of motion holds with each group's pendulum under its own N_g
    assert np.allclose(_isolation_force(system, response), force, rtol=0, atol=1e-6 * W)
    unloaded = {name for name, d in zip(("SW", "SE", "NE", "NW"), dn[-1]) if d < 0}
    assert unloaded == ({"SE", "NE"} if sign > 0 else {"SW", "NW"})


@pytest.mark.slow
def test_uplifted_group_carries_no_shear_and_the_run_stays_finite():
    """Groups 4 m apart under a tall centre of mass (h = 20 m) and a ramped diagonal ground
    acceleration of 0.08 g: the lever rule asks tension of the NE group, the slab rests on the
    other three (the centre of the reactions, C - h H / W, inside the square); NE's friction and
    pendulum force are exactly zero, the uplift time is the count of its steps with N_g <= 0,
    the loads add up to W and the response stays finite and balanced."""
    positions = np.array([[8.0, 4.0], [12.0, 4.0], [12.0, 8.0], [8.0, 8.0]])
    ax, ay = _ramp(0.08, 0.08)
    system = _slab(ax, ay, 20.0, positions=positions)
    response = simulate_history(system, DURATION)
    loads = np.asarray(response.normal_load)
    lifted = loads <= 0
    assert lifted[:, 2].any() and not lifted[:, [0, 1, 3]].any() and np.all(np.isfinite(np.asarray(response.displacement)))
    assert np.max(np.abs(loads.sum(axis=1) - W)) < 1e-9 * W
    assert np.all(np.asarray(response.friction_force)[lifted] == 0.0)
    force = M * np.asarray(response.total_acceleration)[:, :2]
    assert np.allclose(_isolation_force(system, response), force, rtol=0, atol=1e-6 * W)
    assert np.allclose(np.asarray(response.group_uplift_time), lifted[1:].sum(axis=0) * STEP)


@pytest.mark.slow
def test_a_slab_that_tips_is_reported_not_balanced():
    """The same square under an x pulse: lifting the west pair leaves the slab on the east pair,
    one line it cannot rest on (h |H| > W times the 2 m arm): the first step whose held H (the
    step before's) passes that is flagged `tipped` and not balanced (raised with `throw`); the
    steps before it rested and balanced (|h H| <= 2 m W, every group loaded, the loads adding up
    to W), and the tipped step keeps W on the east pair."""
    positions = np.array([[8.0, 4.0], [12.0, 4.0], [12.0, 8.0], [8.0, 8.0]])
    ax, ay = _pulse(0.5, 0.0)
    system = _slab(ax, ay, 20.0, positions=positions)
    response = simulate_history(system, DURATION, throw=False)
    tipped, converged = np.asarray(response.tipped), np.asarray(response.converged)
    assert not bool(response.succeeded) and tipped.any()
    k = int(np.argmax(tipped))  # the first step on which the slab tipped
    assert 1 < k and converged[:k].all() and not tipped[:k].any() and not converged[k]
    force = _isolation_force(system, response)[:k]
    assert 20.0 * np.abs(force[-1, 0]) > 2.0 * W >= 20.0 * np.abs(force[:-1, 0]).max()
    loads = np.asarray(response.normal_load)[:k + 1]
    assert np.all(loads[:-1] > 0) and np.max(np.abs(loads.sum(axis=1) - W)) < 1e-9 * W
    assert np.allclose(loads[-1], [0.0, W / 2, W / 2, 0.0], rtol=1e-12, atol=0)
    with pytest.raises(Exception, match="the slab tipped"):
        jax.block_until_ready(simulate_history(system, DURATION))
    peaks = peak_response(system, DURATION)
    assert not bool(peaks["converged"]) and bool(peaks["tipped"])


def test_a_slab_whose_balance_misses_is_not_said_to_tip():
    """The same square 0.5 m up, which rests on its groups, under a 1 g x 0.6 g pulse at 10 ms
    steps with one Newton iteration: 229 steps miss the balance's tolerance, none tips, and the
    peak run says so (not converged, not tipped); with the default iterations every step
    balances."""
    positions = np.array([[8.0, 4.0], [12.0, 4.0], [12.0, 8.0], [8.0, 8.0]])
    ax, ay = _pulse(1.0, 0.6)
    low = _slab(ax, ay, 0.5, positions=positions, step=0.01)
    short = dataclasses.replace(low, newton_iterations=1)
    history = simulate_history(short, DURATION, throw=False)
    assert int(np.sum(~np.asarray(history.converged))) > 100 and not np.asarray(history.tipped).any()
    peaks = peak_response(short, DURATION)
    assert not bool(peaks["converged"]) and not bool(peaks["tipped"])
    assert bool(peak_response(low, DURATION)["converged"])


@pytest.mark.slow
def test_symmetric_slab_under_one_component_equals_the_rigid_mass():
    """Equal radii and loads, centre of mass on the plan's centre, x motion alone: the
    overturning shifts load from one side to the other but the sums sum_g N_g mu Z and
    sum_g N_g / R d are unchanged, so the slab moves as the rigid mass on a single friction
    pendulum of the same R (period 2 pi sqrt(R / g)) and does not twist."""
    ax, ay = _pulse(0.35, 0.0)
    response = simulate_history(_slab(ax, ay, 4.0), DURATION)
    mass = rigid_mass(components=2, weight=W, bearing=BEARING, ground_acceleration=uniform_signal(ax, DT_RECORD),
                                    ground_y=uniform_signal(ay, DT_RECORD), time_step=STEP,
                                    isolation_period=2 * np.pi * np.sqrt(R / G))
    reference = simulate_history(mass, DURATION)
    assert np.max(np.abs(reference.displacement[:, 0])) > 0.02
    assert np.max(np.abs(np.asarray(response.displacement[:, :2]) - np.asarray(reference.displacement))) < 1e-9
    assert np.max(np.abs(response.displacement[:, 2])) < 1e-12
    assert np.ptp(np.asarray(response.normal_load)[:, 0]) > 0.05 * W / 4  # the loads did move


@pytest.mark.slow
def test_zero_height_is_todays_slab_and_the_rigid_mass():
    """h = 0 runs without overturning; a height of 1 nm (the overturning path) gives the same
    response to rounding; the symmetric slab under two components then equals the rigid mass on
    a single friction pendulum of the same R and does not twist."""
    ax, ay = _pulse(0.35, 0.25)
    today = simulate_history(_slab(ax, ay, 0.0), DURATION)
    assert today.normal_load is None
    tiny = simulate_history(_slab(ax, ay, 1e-9), DURATION)
    assert np.max(np.abs(np.asarray(tiny.displacement) - np.asarray(today.displacement))) < 1e-12
    mass = rigid_mass(components=2, weight=W, bearing=BEARING, ground_acceleration=uniform_signal(ax, DT_RECORD),
                                    ground_y=uniform_signal(ay, DT_RECORD), time_step=STEP,
                                    isolation_period=2 * np.pi * np.sqrt(R / G))
    reference = simulate_history(mass, DURATION)
    assert np.max(np.abs(np.asarray(today.displacement[:, :2]) - np.asarray(reference.displacement))) < 1e-9
    assert np.max(np.abs(today.displacement[:, 2])) < 1e-12


@pytest.mark.slow
def test_peaks_with_overturning_converge_as_the_step_halves():
    """A centre of mass (11.5, 7) m off the loads' centroid at h = 5 m, groups of radii
    1.5-2.5 m, two components: the force held over a step lags by one step. Halving the step
    from 10 ms to 1.25 ms, the peak normal loads and displacement change less at every halving
    (measured: 0.21 %, 0.070 %, 0.023 %), within 0.1 % at the end; the peak rotation, which
    turns on the small differences of the groups' forces, within 0.3 % at every halving."""
    ax, ay = _pulse(0.3, 0.25, frequency=1.0)
    peaks = []
    for step in (0.01, 0.005, 0.0025, 0.00125):
        system = _slab(ax, ay, 5.0, radii=[1.5, 2.0, 2.5, 2.0], step=step, centre=(11.5, 7.0))
        response = simulate_history(system, DURATION)
        loads = np.asarray(response.normal_load)
        peaks.append(np.array([*loads.max(axis=0), *(W / 4 - loads.min(axis=0)),
                               np.max(np.hypot(response.displacement[:, 0], response.displacement[:, 1])),
                               np.max(np.abs(response.displacement[:, 2]))]))
    peaks = np.array(peaks)
    changes = np.abs(np.diff(peaks, axis=0)) / np.abs(peaks[-1])
    loads_and_displacement, rotation = np.max(changes[:, :-1], axis=1), changes[:, -1]
    assert np.all(loads_and_displacement[1:] < 0.6 * loads_and_displacement[:-1])
    assert loads_and_displacement[-1] < 0.001
    assert np.all(rotation < 0.003)


def test_three_groups_follow_statics_whatever_their_vertical_stiffness():
    """Three groups off line: dN is fixed by sum dN = 0 and the two moments alone (here
    solved by numpy from the equilibrium), the same for any relative vertical stiffness; four
    groups at a rectangle's corners follow the hand lever rule."""
    positions = np.array([[1.0, 1.0], [15.0, 2.0], [6.0, 11.0]])
    centre, height, force = np.array([7.0, 5.0]), 3.0, np.array([2.0e5, -1.0e5])
    r = positions - centre
    statics = np.linalg.solve(np.vstack([np.ones(3), r.T]), np.array([0.0, *(-height * force)]))
    for stiffness in (None, [1.0, 5.0, 0.2]):
        dn = overturning_map(positions, centre, height, stiffness) @ force
        assert np.allclose(dn, statics, rtol=1e-12, atol=1e-9)
    dn = overturning_map(CORNERS, CENTRE, height) @ force
    assert np.allclose(dn, _lever_rule(CORNERS, height, force), rtol=1e-12)


def test_bad_pendulum_slab_inputs_are_refused_by_name():
    ax, ay = _pulse(0.1, 0.1)
    with pytest.raises(ValueError, match=r"radii: must be > 0 m"):
        _slab(ax, ay, 1.0, radii=[2.0, 0.0, 2.0, 2.0])
    with pytest.raises(ValueError, match=r"radii: give one radius for all groups or one per group"):
        _slab(ax, ay, 1.0, radii=[2.0, 2.0])
    with pytest.raises(ValueError, match=r"height_of_centre_of_mass: must be >= 0 m"):
        _slab(ax, ay, -1.0)
    with pytest.raises(ValueError, match=r"height_of_centre_of_mass: the bearing groups lie on one line"):
        _slab(ax, ay, 1.0, positions=np.array([[2.0, 6.0], [8.0, 6.0], [12.0, 6.0], [18.0, 6.0]]))
    with pytest.raises(ValueError, match=r"vertical_stiffness: group 2 has -1"):
        overturning_map(CORNERS, CENTRE, 1.0, [1.0, -1.0, 1.0, 1.0])
    common = dict(length_x=LX, length_y=LY, weight=W, centre_of_mass=CENTRE, positions=CORNERS,
                  bearings=BEARING, loads=[W / 4] * 4, ground_acceleration=uniform_signal(ax, DT_RECORD),
                  ground_y=uniform_signal(ay, DT_RECORD), time_step=STEP)
    with pytest.raises(ValueError, match=r"isolation_period, spring_shares: a slab on single friction"):
        slab_on_bearings(**common, isolator="single-fp", radii=R, isolation_period=2.5)
    with pytest.raises(ValueError, match=r"radii: apply to isolator 'single-fp' only"):
        slab_on_bearings(**common, radii=R, isolation_period=2.5)
    with pytest.raises(ValueError, match=r"radii: isolator 'single-fp' needs the radius"):
        slab_on_bearings(**common, isolator="single-fp")


def _plan(tmp_path, height="6m", **group_keys):
    groups = [{"name": n, "x": f"{x}m", "y": f"{y}m", "load": "250kN"}
              for n, (x, y) in zip(("SW", "SE", "NE", "NW"), CORNERS)]
    groups[1].update(group_keys)
    plan = {"length_x": "20m", "length_y": "12m", "weight": "1000kN", "height_of_centre_of_mass": height,
            "groups": groups}
    path = tmp_path / "plan.json"
    path.write_text(json.dumps(plan))
    return path


def _record(tmp_path):
    path = tmp_path / "x.txt"
    ax, _ = _pulse(0.4, 0.0)
    np.savetxt(path, np.column_stack([TIME, ax / G]))
    return path


@pytest.mark.parametrize(("flags", "group", "height", "message"), [
    ([], {"radius": "0m"}, "6m", "SE.radius must be > 0"),
    ([], {}, "-1m", "height_of_centre_of_mass must be >= 0"),
    ([], {"springs": 2.0}, "6m", "SE.springs conflicts with --isolator single-fp"),
    ([], {"vertical_stiffness": 0}, "6m", "SE.vertical_stiffness must be > 0"),
    (["--isolator", "flat", "--isolation-period", "2.5s"], {"radius": "2m"}, "6m",
     "SE.radius applies with --isolator single-fp only"),
])
def test_run_refuses_bad_plans_by_key(tmp_path, capsys, flags, group, height, message):
    args = ["run", "--structure", "slab", "--plan", str(_plan(tmp_path, height, **group)),
            "--record-x", str(_record(tmp_path)), "--record-units", "g"]
    args += flags or ["--isolator", "single-fp", "--radius", "88in"]
    assert main(args) == 2
    assert message in capsys.readouterr().err


@pytest.mark.slow
def test_run_reports_each_groups_normal_load(tmp_path, capsys):
    """`run --structure slab --isolator single-fp` with a height: per group the static, peak
    and least normal load and the uplift time; the plan's radius overrides --radius; x motion
    moves load between the west and east pairs; the run completes ("complete": true, no entries
    of a partial run)."""
    out = tmp_path / "run.json"
    code = main(["run", "--structure", "slab", "--plan", str(_plan(tmp_path, radius="60in")),
                 "--record-x", str(_record(tmp_path)), "--record-units", "g", "--isolator",
                 "single-fp", "--radius", "88in", "--json", str(out), "--time-step", "0.005s"])
    assert code == 0
    assert "normal load SE: peak" in capsys.readouterr().out
    result = json.loads(out.read_text())
    assert result["complete"] is True and "stopped_at_s" not in result and "partial_fields" not in result
    groups = result["normal_load"]["groups"]
    assert groups["SE"]["radius_m"] == pytest.approx(60 * 0.0254)
    assert groups["SW"]["radius_m"] == pytest.approx(88 * 0.0254)
    for g in groups.values():
        assert g["min_N"] < g["static_N"] == 250e3 < g["peak_N"] and g["uplift_time_s"] == 0
    assert groups["SW"]["peak_N"] - 250e3 == pytest.approx(250e3 - groups["SE"]["min_N"], rel=0.05)


def test_run_exits_non_zero_naming_a_slab_that_tips(tmp_path, capsys):
    """`run --structure slab --isolator single-fp` with the centre of mass 40 m up: the 0.4 g
    pulse's H passes W times the 8 m arm over 40 m (0.2 W), the west or east pair lifts and the
    slab tips: exit 1 naming the tipping and the plan's height. The JSON and histories still come
    out, labelled partial: they stop at the step before the tipped one, which is the first step
    whose held H (the step before's, the last kept) passes 0.2 W (the lever rule about the
    leaning pair), and the JSON's peaks are the maxima of the kept histories."""
    out, histories = tmp_path / "run.json", tmp_path / "run.csv"
    code = main(["run", "--structure", "slab", "--plan", str(_plan(tmp_path, height="40m")),
                 "--record-x", str(_record(tmp_path)), "--record-units", "g", "--isolator",
                 "single-fp", "--radius", "88in", "--json", str(out), "--time-step", "0.005s",
                 "--histories", str(histories)])
    err = capsys.readouterr().err
    assert code == 1
    assert "the slab tips on" in err and "height_of_centre_of_mass" in err and "40 m above" in err
    assert '"complete": false' in err
    result = json.loads(out.read_text(), parse_constant=pytest.fail)  # NaN or Infinity: not JSON
    first = float(err.split("the slab tips on ")[1].split("first at t = ")[1].split(" s")[0])
    assert result["complete"] is False and result["tipped_steps"] >= 1 and result["unconverged_steps"] == 0
    assert result["first_tipped_s"] == result["stopped_at_s"] == pytest.approx(first, rel=1e-3)
    assert result["first_unconverged_s"] is None
    assert set(result["partial_fields"]) == {"peak", "normal_load"}
    h = np.genfromtxt(histories, delimiter=",", names=True)
    assert h["time_s"][-1] == pytest.approx(result["last_kept_s"]) == pytest.approx(result["stopped_at_s"] - 0.005)
    assert np.all(np.isfinite(h.view((float, len(h.dtype.names)))))
    ratio = np.abs(h["base_shear_ratio_x"])  # |H| / W, H_y = 0
    assert ratio[-1] > 8.0 / 40.0 >= ratio[:-1].max()
    peak = result["peak"]
    assert peak["base_disp_resultant_m"] == pytest.approx(np.hypot(h["base_disp_x_m"], h["base_disp_y_m"]).max(),
                                                          rel=1e-12)
    assert peak["base_disp_x_m"] == pytest.approx(np.abs(h["base_disp_x_m"]).max(), rel=1e-12)
    assert peak["base_shear_ratio_resultant"] == pytest.approx(
        np.hypot(h["base_shear_ratio_x"], h["base_shear_ratio_y"]).max(), rel=1e-12)
    assert peak["rotation_rad"] == pytest.approx(np.abs(h["rotation_rad"]).max(), rel=1e-9, abs=1e-15)
    assert peak["base_disp_resultant_m"] > 0.1  # the pulse moved the slab before it tipped


def test_a_suite_pair_whose_balance_misses_is_not_said_to_tip():
    """Two pairs on the square 2 m up with one Newton iteration per 10 ms step: both miss the
    balance's tolerance before any step tips the slab, so the suite flags them not converged
    and not tipped (`SuiteResult.tipped`), as the peak run does."""
    from teflon_jax.studies import suite_peaks

    positions = np.array([[8.0, 4.0], [12.0, 4.0], [12.0, 8.0], [8.0, 8.0]])

    def build(ground_x, ground_y):
        system = slab_on_bearings(
            length_x=LX, length_y=LY, weight=W, centre_of_mass=CENTRE, positions=positions, bearings=BEARING,
            loads=[W / 4] * 4, ground_acceleration=ground_x, ground_y=ground_y, time_step=0.01, isolator="single-fp",
            radii=R, height_of_centre_of_mass=2.0)
        return dataclasses.replace(system, newton_iterations=1)

    pulses = [_pulse(peak, 0.6 * peak) for peak in (0.3, 0.6)]
    result = suite_peaks(build, ("weak", "strong"), np.stack([p[0] for p in pulses]),
                         np.stack([p[1] for p in pulses]), DT_RECORD, DURATION)
    assert result.converged.tolist() == [False, False] and result.tipped.tolist() == [False, False]
    single = peak_response(build(uniform_signal(pulses[1][0], DT_RECORD), uniform_signal(pulses[1][1], DT_RECORD)),
                           DURATION)
    assert not bool(single["converged"]) and not bool(single["tipped"])
