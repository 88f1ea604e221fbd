"""The slab on double or triple friction pendulums driven into the restrainers (a ground
acceleration of 0.2 g bias plus a 0.35 g oscillation along x, the sliders at their
displacement capacities): the run stays finite, and every step is either balanced or reported.

Laws: at h = 0, and at a height h whose moment h |H| stays below W times the arm of the leaning
pair (8 m here), the symmetric slab is the rigid mass of the same weight on one pendulum
(every slider's force scales with its group's N_g and the N_g add up to W); above it, the slab
on four corners would rest on one line (tension-free supports): it tips, a rigid slab without
rocking cannot balance it, and exactly those steps are reported, the loads still adding up to W.
Peer: `simulate_history` (its own tests against closed forms and OpenSees)."""

import numpy as np
import pytest
from test_slab_series import (
    CENTRE,
    CORNERS,
    DOUBLE,
    DT_RECORD,
    LX,
    LY,
    STEP,
    TRIPLE,
    W,
    _isolator_file,
    simulate,
)

from teflon_jax.cli import main
from teflon_jax.excitation import uniform_signal
from teflon_jax.systems import (
    simulate_history,
    slab_on_bearings,
    triple_structure,
)
from teflon_jax.units import STANDARD_GRAVITY as G

SECONDS = 3.0
TIME = np.arange(0.0, SECONDS + DT_RECORD / 2, DT_RECORD)
DRIVE = (0.2 + 0.35 * np.sin(2 * np.pi * 0.7 * TIME)) * G  # [m/s^2] along x
ARM = 8.0  # [m]: the corners' x arm about the centre of mass
RESTRAINED = 5.0  # |H| / W beyond which the restrainers carry the force (pendulum and friction < 0.5)


def _slab(height, pendulum):
    return slab_on_bearings(
        length_x=LX, length_y=LY, weight=W, centre_of_mass=CENTRE, positions=CORNERS, loads=[W / 4] * 4,
        ground_acceleration=uniform_signal(DRIVE, DT_RECORD), ground_y=uniform_signal(0 * DRIVE, DT_RECORD), time_step=STEP,
        isolator=pendulum.isolator, pendulums=pendulum, height_of_centre_of_mass=height)


def _rigid(pendulum):
    one = triple_structure("rigid", pendulum, uniform_signal(DRIVE, DT_RECORD), time_step=STEP, weight=W)
    return np.asarray(simulate_history(one, SECONDS).displacement[:, 0])


def _check_in_restrainers_as_the_rigid_mass(pendulum, heights):
    reference = _rigid(pendulum)
    for height in heights:
        response = simulate(_slab(height, pendulum), SECONDS, throw=False)
        force = -np.asarray(response.bearing_force).sum(axis=1)  # H (nt, 2) [N]
        loads = np.asarray(response.normal_load)
        assert np.max(np.abs(force[:, 0])) > RESTRAINED * W and ARM * W > height * np.max(np.abs(force[:, 0]))
        assert bool(np.all(response.converged)) and not np.asarray(response.tipped).any()
        assert np.max(np.abs(loads.sum(axis=1) - W)) < 1e-9 * W
        assert np.max(np.abs(np.asarray(response.displacement[:, 0]) - reference)) < 1e-9
        assert np.max(np.abs(np.asarray(response.displacement[:, 1:]) * [1.0, LX])) < 1e-8  # y and twist at the edges [m]
        if height > 0:  # the lever rule of H of the step before: dN_g = -h H_x rx_g / sum rx^2
            r = CORNERS[:, 0] - CENTRE[0]
            assert np.allclose(loads[1:] - W / 4, -height * np.outer(force[:-1, 0], r) / np.sum(r**2),
                               rtol=0, atol=1e-9 * W)


@pytest.mark.parametrize("pendulum", [DOUBLE, pytest.param(TRIPLE, marks=pytest.mark.slow)],
                         ids=["double-fp", "triple-fp"])
def test_in_the_restrainers_the_resting_slab_is_the_rigid_mass(pendulum):
    """h = 0 and h = 0.25 m (|h H| <= 4.4 m W under impacts of |H| up to 17 W, below the 8 m W
    the corners hold): the slab equals the rigid mass on one pendulum to 1e-9 m, does not
    twist (1e-8 m at its edges, of a 0.8 m motion: rounding under the restrainers' stiffness), every step balanced, the loads add up to W and follow the lever rule."""
    _check_in_restrainers_as_the_rigid_mass(pendulum, (0.0, 0.25))


# the heated slab (its own compilation, about 20 s) runs with the slow tests: the tipping is
# checked here on the unheated double pendulum, and a heated slab that tips, its tipped steps
# reported, in test_slab_series_heat.py::test_a_lifted_group_generates_no_heat
@pytest.mark.parametrize("pendulum", [DOUBLE, pytest.param(TRIPLE, marks=pytest.mark.slow),
                                      pytest.param("heated", marks=pytest.mark.slow)],
                         ids=["double-fp", "triple-fp", "double-fp-heated"])
def test_a_slab_that_tips_on_a_restrainer_is_reported_and_stays_finite(pendulum):
    """h = 4 m: a restrainer's impact (|H| of several W) gives h |H| > 8 m W, the slab would rest
    on the east or west pair alone and tips. The run stays finite (it went to NaN when the
    clipped lever rule loaded the pair with more than W, which fed the restrainer's force back
    on H step after step); the unbalanced steps are exactly the tipped ones, exactly those whose
    held H (the step before's) passes 2 W; the loads add up to W on every step, the lifted pair
    carrying nothing; before the first impact the unheated slab is the rigid mass (heated, the
    leaning groups heat more under their larger N_g, so their friction differs)."""
    height = 4.0
    if pendulum == "heated":  # every surface heated (the double pendulum of test_slab_series_heat)
        from test_slab_series_heat import _heated

        pendulum = _heated()
    response = simulate(_slab(height, pendulum), SECONDS, throw=False)
    if pendulum.heated:
        assert np.all(np.isfinite(np.asarray(response.surface_temperature_rise)))
    q, loads = np.asarray(response.displacement), np.asarray(response.normal_load)
    tipped, converged = np.asarray(response.tipped), np.asarray(response.converged)
    force = -np.asarray(response.bearing_force).sum(axis=1)
    assert np.all(np.isfinite(q)) and np.all(np.isfinite(loads)) and np.all(np.isfinite(force))
    assert tipped.sum() > 5 and np.array_equal(~converged, tipped)
    assert np.array_equal(tipped[1:], height * np.abs(force[:-1, 0]) > ARM * W)
    assert np.max(np.abs(loads.sum(axis=1) - W)) < 1e-9 * W
    lifted = loads[tipped]
    assert np.all(np.sort(lifted, axis=1)[:, :2] == 0.0)
    assert np.allclose(np.sort(lifted, axis=1)[:, 2:], W / 2, rtol=1e-9, atol=0)  # H_y ~ rounding
    first = int(np.argmax(tipped))
    if not pendulum.heated:  # heated groups differ in their loads' heat, so in friction
        assert np.max(np.abs(q[:first, 0] - _rigid(pendulum)[:first])) < 1e-9


def test_run_exits_non_zero_naming_the_tipping(tmp_path, capsys):
    """`run --structure slab --isolator double-fp` under the same drive with h = 4 m: exit 1
    with a message that names the tipping, its step count and the plan's height. The JSON and
    histories still come out, labelled partial: the histories end at the step before the first
    tipped one, which is the first whose held H (the last kept step's) passes 2 W (8 m W over
    4 m), the JSON's peaks are their maxima, and its counts and first time are the message's."""
    import json

    groups = [{"name": n, "x": f"{x}m", "y": f"{y}m", "load": "250kN"}
              for n, (x, y) in zip(("SW", "SE", "NE", "NW"), CORNERS)]
    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps({"length_x": "20m", "length_y": "12m", "weight": "1000kN",
                                "height_of_centre_of_mass": "4m", "groups": groups}))
    record = tmp_path / "x.txt"
    np.savetxt(record, np.column_stack([TIME, DRIVE / G]))
    out, histories = tmp_path / "run.json", tmp_path / "run.csv"
    code = main(["run", "--structure", "slab", "--plan", str(plan), "--record-x", str(record), "--record-units",
                 "g", "--isolator", "double-fp", "--isolator-file", str(_isolator_file(tmp_path / "d.json", DOUBLE)),
                 "--time-step", "0.005s", "--json", str(out), "--histories", str(histories)])
    err = capsys.readouterr().err
    assert code == 1
    assert "the slab tips on" in err and "height_of_centre_of_mass" in err and "4 m above" in err
    assert "did not converge" not in err and '"complete": false' in err
    steps, first = err.split("the slab tips on ")[1].split(" steps (first at t = ")
    result = json.loads(out.read_text(), parse_constant=pytest.fail)  # NaN or Infinity: not JSON
    assert result["complete"] is False and result["tipped_steps"] == int(steps) > 5
    assert result["first_tipped_s"] == result["stopped_at_s"] == pytest.approx(float(first.split(" s")[0]), rel=1e-3)
    assert result["unconverged_steps"] == 0 and result["first_unconverged_s"] is None
    assert set(result["partial_fields"]) == {"peak", "normal_load", "slider_disp_m"}  # unheated: no temperature
    h = np.genfromtxt(histories, delimiter=",", names=True)
    assert h["time_s"][-1] == pytest.approx(result["last_kept_s"]) == pytest.approx(result["stopped_at_s"] - STEP)
    held = np.abs(h["bearing_force_x_N"])  # |H| [N], H_y = 0
    assert held[-1] * 4.0 > ARM * W >= held[:-1].max() * 4.0
    peak = result["peak"]
    assert peak["base_disp_resultant_m"] == pytest.approx(np.hypot(h["base_disp_x_m"], h["base_disp_y_m"]).max(),
                                                          rel=1e-12)
    assert peak["bearing_force_ratio_resultant"] == pytest.approx(
        np.hypot(h["bearing_force_x_N"], h["bearing_force_y_N"]).max() / W, rel=1e-12)
    assert peak["base_shear_ratio_resultant"] == pytest.approx(
        np.hypot(h["base_shear_ratio_x"], h["base_shear_ratio_y"]).max(), rel=1e-12)
    assert peak["base_disp_resultant_m"] > 0.1  # into the restrainers before it tipped


@pytest.mark.slow
def test_an_eccentric_slab_driven_into_its_restrainers_in_two_components_balances_every_step():
    """The mass 2 m east and 1 m north of the plan's centre (h = 0), the drive along x with
    0.1 g + 0.35 g along y a radian out of phase: the sliders hit their restrainers along a
    skew path, one of them reversing within a step. Newton's iteration from the last step's
    increments stalled on one such step (t = 0.615 s: a minimum of the residual's square with
    38 kN left); it now starts once more from the groups' increments shared among their
    sliders. Laws: every step balances (none tips at h = 0), each group's displacement is the
    sum of its sliders' (the series model's compatibility) to 1e-9 m, the isolators' force is
    the slab's inertia m (a + a_g) to 1e-6 W, and the slab twists (the mass off the centre)."""
    drive_y = (0.1 + 0.35 * np.sin(2 * np.pi * 0.7 * TIME + 1.0)) * G
    system = slab_on_bearings(
        length_x=LX, length_y=LY, weight=W, centre_of_mass=CENTRE + [2.0, 1.0], positions=CORNERS,
        loads=[W / 4] * 4, ground_acceleration=uniform_signal(DRIVE, DT_RECORD), ground_y=uniform_signal(drive_y, DT_RECORD),
        time_step=STEP, isolator=TRIPLE.isolator, pendulums=TRIPLE, height_of_centre_of_mass=0.0)
    response = simulate(system, SECONDS)
    assert bool(np.all(response.converged)) and not np.asarray(response.tipped).any()
    sliders = np.asarray(response.slider).sum(axis=2)  # (nt, G, 2)
    assert np.max(np.abs(np.asarray(response.bearing_displacement) - sliders)) < 1e-9
    force = -np.asarray(response.bearing_force).sum(axis=1)
    inertia = W / G * np.asarray(response.total_acceleration)[:, :2]
    assert np.max(np.abs(force - inertia)) < 1e-6 * W
    assert np.max(np.abs(force) / W) > RESTRAINED  # in the restrainers
    assert np.max(np.abs(np.asarray(response.displacement)[:, 2])) > 1e-4
