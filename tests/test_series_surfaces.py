"""Every surface of a double or triple pendulum carries the flat bearing's whole interface law.

A surface may add breakaway (Eq. 17), anisotropy across the lay, wear, direction asymmetry and
pressure dependence (`SurfaceParts`), each the flat bearing's formula, beside its Eq. 1 and
heating. Peers: closed forms of a slow imposed-displacement test of a double pendulum with
Coulomb surfaces (mu_1 < mu_2, so only the bottom surface slides while F / W < mu_2: the force
is W (u / R_1 + mu_1' Z) with mu_1' the bottom's coefficient as its part sets it), the rigid
mass held by breakaway friction under a constant ground acceleration below b mu g, and the
limits in which a part changes nothing (b = 1 on Coulomb surfaces, a heating scale of 0), in
the bearing test, the structures in one and two components and the slab.
"""

import equinox as eqx
import jax
import numpy as np
import pytest
from histories import planar_histories

from teflon_jax.bearing import (
    BoucWen,
    DirectionAsymmetry,
    DoublePendulum,
    FrictionalHeating,
    PressureDependence,
    SurfaceParts,
    TriplePendulum,
    Wear,
    check_series_pendulum,
    coulomb_friction,
)
from teflon_jax.excitation import uniform_signal
from teflon_jax.systems import (
    imposed_path_test,
    sampled_path,
    simulate_history,
    slab_on_bearings,
    triple_structure,
)
from teflon_jax.units import STANDARD_GRAVITY

W = 1e6
MU_BOTTOM, MU_TOP, R_BOTTOM = 0.05, 0.08, 1.0


def _double(bottom=None, top=None, **changes):
    values = dict(bottom_radius=R_BOTTOM, top_radius=2.0, bottom_capacity=0.5, top_capacity=0.5,
                  bottom_friction=coulomb_friction(MU_BOTTOM), top_friction=coulomb_friction(MU_TOP),
                  hysteresis=BoucWen(1e-5), surface_parts=(bottom, top))
    values.update(changes)
    pendulum = DoublePendulum(**values)
    check_series_pendulum(pendulum)
    return pendulum


def _slow_cycles(pendulum, amplitude=0.01, cycles=2, samples=4000):
    """A slow sine of `amplitude` [m] (the bottom surface alone slides), F / W."""
    t = np.linspace(0.0, 100.0 * cycles, samples * cycles + 1)
    u = amplitude * np.sin(2 * np.pi * t / 100.0)
    response = jax.jit(imposed_path_test)(pendulum, sampled_path(t, u, W))
    assert bool(np.all(response.converged))
    return t, u, np.asarray(response.force) / W


def _plateau(u, f, forward: bool):
    """F / W - u / R_1, the bottom surface's friction, at the path's last crossing of u = 0
    moving forward (or back)."""
    du = np.diff(u)
    i = np.flatnonzero((du > 0 if forward else du < 0) & (np.sign(u[:-1]) != np.sign(u[1:])))[-1]
    return f[i] - u[i] / R_BOTTOM


def test_breakaway_on_a_surface_holds_until_b_f_min_then_eq1_takes_over():
    b = 1.5  # b mu_1 = 0.075 < mu_2: the bottom surface breaks away first
    t, u, f = _slow_cycles(_double(bottom=SurfaceParts(breakaway_ratio=b)))
    first = u < 0.004  # the first loading, before the closed form's sliding line is reached
    first &= t < 25.0
    assert np.max(f[first]) == pytest.approx(b * MU_BOTTOM, abs=2e-4)
    sliding = (t > 20.0) & (t < 25.0)  # after breakaway: mu_1 + u / R_1
    np.testing.assert_allclose(f[sliding], MU_BOTTOM + u[sliding] / R_BOTTOM, atol=2e-4)
    _, _, plain = _slow_cycles(_double())
    assert np.max(plain[first]) == pytest.approx(MU_BOTTOM + 0.004 / R_BOTTOM, abs=2e-4)


def test_asymmetry_on_a_surface_scales_its_friction_by_one_plus_a_z():
    a = 0.2
    _, u, f = _slow_cycles(_double(bottom=SurfaceParts(asymmetry=DirectionAsymmetry(a))))
    assert _plateau(u, f, True) == pytest.approx(MU_BOTTOM * (1 + a), abs=5e-5)
    assert _plateau(u, f, False) == pytest.approx(-MU_BOTTOM * (1 - a), abs=5e-5)


def test_wear_on_a_surface_lowers_its_friction_with_the_surfaces_travel():
    change, reference = -0.3, 0.1
    _, u, f = _slow_cycles(_double(bottom=SurfaceParts(wear=Wear(change, reference))), cycles=3)
    # the last forward crossing of u = 0 starts the third cycle: the bottom surface has slid two
    # cycles of four amplitudes
    travel = 2 * 4 * 0.01
    assert _plateau(u, f, True) == pytest.approx(MU_BOTTOM * (1 + change * travel / reference), abs=5e-5)


def test_pressure_dependence_on_a_surface_takes_its_contact_pressure():
    pressure, area = 20e6, 0.01
    part = SurfaceParts(pressure_dependence=PressureDependence(0.5, 1.44 * pressure * area, area))
    _, u, f = _slow_cycles(_double(bottom=part, bottom_pressure=pressure))
    assert _plateau(u, f, True) == pytest.approx(MU_BOTTOM * 1.2, abs=5e-5)  # (1 / 1.44)^-0.5


@pytest.mark.slow
def test_anisotropy_on_a_surface_takes_the_constants_across_its_lay():
    across = 0.03
    pendulum = _double(bottom=SurfaceParts(friction_perpendicular=coulomb_friction(across)))
    turned = _double(bottom=SurfaceParts(friction_perpendicular=coulomb_friction(across), lay_angle=np.pi / 2))
    t = np.linspace(0.0, 200.0, 8001)
    s = 0.01 * np.sin(2 * np.pi * t / 100.0)
    for bearing, along_x, along_y in ((pendulum, MU_BOTTOM, across), (turned, across, MU_BOTTOM)):
        for axis, expected in ((0, along_x), (1, along_y)):
            path = np.zeros((t.size, 2))
            path[:, axis] = s
            response = jax.jit(imposed_path_test)(bearing, sampled_path(t, path, W))
            force = np.asarray(response.force)[:, axis] / W
            assert _plateau(s, force, True) == pytest.approx(expected, abs=5e-5)


def _held(pendulum, acceleration, components=1, duration=6.0):
    """The rigid mass's largest isolator displacement [m] under a constant ground acceleration
    `acceleration` [g] (along x, or x and y equally) after a 1 s ramp."""
    t = np.arange(0.0, duration + 0.005, 0.01)
    ground = acceleration * STANDARD_GRAVITY * np.minimum(t, 1.0)
    system = triple_structure("rigid", pendulum, uniform_signal(ground, 0.01), time_step=0.005)
    if components == 1:
        response = jax.jit(simulate_history, static_argnums=1)(system, duration)
        assert bool(np.all(response.converged))
        return np.max(np.abs(np.asarray(response.displacement[:, 0])))
    both = system.with_y_component(uniform_signal(ground, 0.01))
    _, x, _, _, _, converged = jax.jit(planar_histories, static_argnums=1)(both, duration)
    assert bool(np.all(converged))
    return np.max(np.linalg.norm(np.asarray(x[:, :, 0]), axis=1))


@pytest.mark.slow
@pytest.mark.parametrize("components", [1, 2])
def test_breakaway_on_both_surfaces_holds_the_mass_below_b_mu_g(components):
    b = 2.0  # b mu_1 = 0.1, b mu_2 = 0.16
    parts = dict(bottom=SurfaceParts(breakaway_ratio=b), top=SurfaceParts(breakaway_ratio=b))
    push = 0.085 / np.sqrt(components)  # the resultant 0.085 g: between mu_1 and b mu_1
    assert _held(_double(**parts), push, components) < 20 * 1e-5  # elastic Z only
    assert _held(_double(), push, components) > 0.05  # without breakaway the bottom slides


def _limits():
    heated = dict(bottom_heating=FrictionalHeating(contact_area=0.05, heat_scale=0.0), bottom_pressure=30e6)
    return (_double(**heated), _double(bottom=SurfaceParts(breakaway_ratio=1.0), **heated))


@pytest.mark.slow
def test_a_breakaway_ratio_of_one_on_coulomb_heated_surfaces_changes_nothing():
    t = np.arange(0.0, 8.0 + 0.005, 0.01)
    ground = 0.3 * STANDARD_GRAVITY * np.sin(2 * np.pi * t / 1.7) * np.minimum(t / 2.0, 1.0)
    runs = []
    for pendulum in _limits():
        system = triple_structure("building", pendulum, uniform_signal(ground, 0.01), time_step=0.005)
        runs.append(np.asarray(jax.jit(simulate_history, static_argnums=1)(system, 8.0).displacement))
    assert np.max(np.abs(runs[0][:, 0])) > 0.05
    np.testing.assert_allclose(runs[1], runs[0], rtol=0, atol=1e-12)


@pytest.mark.slow
def test_the_slab_carries_the_surfaces_parts_in_two_components():
    t = np.arange(0.0, 6.0 + 0.005, 0.01)
    ramp = 0.085 / np.sqrt(2) * STANDARD_GRAVITY * np.minimum(t, 1.0)
    corners = np.array([[2.0, 1.0], [18.0, 1.0], [18.0, 11.0], [2.0, 11.0]])
    peaks = []
    for parts in ((None, None), (SurfaceParts(breakaway_ratio=2.0), SurfaceParts(breakaway_ratio=2.0))):
        pendulum = _double(*parts)
        slab = slab_on_bearings(length_x=20.0, length_y=12.0, weight=W, centre_of_mass=(10.0, 6.0),
                                positions=corners, loads=[W / 4] * 4, ground_acceleration=uniform_signal(ramp, 0.01),
                                ground_y=uniform_signal(ramp, 0.01), time_step=0.005, isolator="double-fp",
                                pendulums=pendulum)
        response = jax.jit(simulate_history, static_argnums=1)(slab, 6.0)
        assert bool(np.all(np.asarray(response.converged)))
        peaks.append(np.max(np.linalg.norm(np.asarray(response.bearing_displacement), axis=-1)))
    assert peaks[0] > 0.05 and peaks[1] < 20 * 1e-5


@pytest.mark.parametrize("changes, message", [
    (dict(surface_parts=(SurfaceParts(),)), "surface_parts: one SurfaceParts (or None) per slider"),
    (dict(surface_parts=(SurfaceParts(breakaway_ratio=0.5), None)), "surface_parts.bottom.breakaway_ratio"),
    (dict(surface_parts=(None, SurfaceParts(asymmetry=DirectionAsymmetry(1.2)))),
     "surface_parts.top.asymmetry.asymmetry"),
    (dict(surface_parts=(SurfaceParts(pressure_dependence=PressureDependence(0.5, 1e5, 0.01)), None)),
     "surface_parts.bottom.pressure_dependence"),
    (dict(surface_parts=(SurfaceParts(lay_angle=0.3), None)), "surface_parts.bottom.lay_angle"),
    (dict(surface_parts=(None, "breakaway")), "surface_parts.top: expected a SurfaceParts"),
])
def test_parts_a_surface_cannot_take_are_refused_by_name(changes, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        _double(**changes)


def test_a_triple_pendulum_takes_parts_on_each_of_its_sliders():
    triple = TriplePendulum(inner_radius=0.3, bottom_radius=2.1, top_radius=2.1, inner_capacity=0.05,
                            bottom_capacity=0.4, top_capacity=0.4, inner_friction=coulomb_friction(0.02),
                            bottom_friction=coulomb_friction(0.06), top_friction=coulomb_friction(0.1),
                            hysteresis=BoucWen(1e-5))
    broken = eqx.tree_at(lambda p: p.surface_parts, triple, (SurfaceParts(breakaway_ratio=2.0), None, None),
                         is_leaf=lambda x: x is None)
    check_series_pendulum(broken)
    t = np.linspace(0.0, 25.0, 1001)
    u = 0.005 * np.sin(2 * np.pi * t / 100.0)  # regime I only: the inner pair slides
    force = np.asarray(jax.jit(imposed_path_test)(broken, sampled_path(t, u, W)).force) / W
    assert np.max(force[t < 10]) == pytest.approx(2 * 0.02, abs=2e-4)  # the inner pair's breakaway
    assert force[-1] == pytest.approx(0.02 + u[-1] / 0.6, abs=2e-4)  # then mu_2 + u / (2 a)
