"""Park's slope written out: dZ/dU of the exact biaxial update along a straight increment
(`park_exact_update_and_slope`) against forward mode through the update, against differences
of Eqs. 8-9 integrated along the increment, at rest, and as the sliders' Newton blocks."""

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from teflon_jax.bearing import (
    BoucWen,
    DirectionAsymmetry,
    FrictionParameters,
    PressureDependence,
    SurfaceParts,
    TriplePendulum,
    Wear,
    paper_bearing,
    park_rate,
    single_pendulum,
)
from teflon_jax.elements import balance_forces, initial_history, slider_forces, step_history
from teflon_jax.solver import park_exact_update, park_exact_update_and_slope
from teflon_jax.tables import interface_parameters
from teflon_jax.units import INCH, PSI

HYSTERESES = [BoucWen(1e-3), BoucWen(1e-3, beta=0.9, gamma=0.1), BoucWen(2e-4, beta=-0.3, gamma=1.3)]


def _points(count, seed, yield_disp):
    """Starts Z0 inside the unit disc and increments from 1e-4 Y to 50 Y in every direction
    (about half of them against a component of Z0, so that it crosses zero on the way)."""
    rng = np.random.default_rng(seed)
    angle = rng.uniform(0, 2 * np.pi, count)
    z0 = np.stack([np.cos(angle), np.sin(angle)], -1) * rng.uniform(0, 1, count)[:, None]
    du = rng.normal(size=(count, 2)) * yield_disp * np.exp(rng.uniform(np.log(1e-4), np.log(50.0), count))[:, None]
    return jnp.asarray(z0), jnp.asarray(du)


def _crossings(h, z0, du):
    """How many increments turn a component of Z0 that opposes them (e_i Z0_i < 0) past zero."""
    z1 = jax.vmap(lambda a, b: park_exact_update(h, a, b))(z0, du)
    return int(np.sum(np.any((np.asarray(z0) * np.asarray(du) < 0) & (np.asarray(z1) * np.asarray(du) > 0), -1)))


@pytest.mark.parametrize("h", HYSTERESES, ids=["paper", "beta-heavy", "softening"])
def test_the_slope_is_forward_mode_through_the_update(h):
    z0, du = _points(3000, 1, float(h.yield_disp))
    assert _crossings(h, z0, du) > 300  # the stretches after a crossing are tested too
    z, slope = jax.vmap(lambda a, b: park_exact_update_and_slope(h, a, b))(z0, du)
    jacobian = jax.vmap(jax.jacfwd(lambda b, a: park_exact_update(h, a, b)))(du, z0)
    assert np.array_equal(np.asarray(z), np.asarray(jax.vmap(lambda a, b: park_exact_update(h, a, b))(z0, du)))
    scale = np.max(np.abs(np.asarray(jacobian)), axis=(1, 2))
    assert np.max(np.max(np.abs(np.asarray(slope - jacobian)), axis=(1, 2)) / scale) < 1e-11


def test_the_slope_is_the_difference_of_the_integrated_equations():
    """Central differences of Eqs. 8-9 integrated along the increment (DOP853, rtol 1e-13),
    independent of the closed form, for increments that turn a component of Z past zero."""
    h = BoucWen(yield_disp=1.27e-4)
    rate = jax.jit(lambda z, du: park_rate(h, z, du))

    def integrated(z0, du):
        return solve_ivp(lambda t, z: np.asarray(rate(z, du)), (0, 1), z0, method="DOP853", rtol=1e-13,
                         atol=1e-14).y[:, -1]

    for z0, du in [((0.9, 0.3), (-3e-4, 1e-4)), ((-0.5, 0.7), (2e-4, -5e-4)), ((0.2, -0.95), (1e-5, 4e-5)),
                   ((0.6, 0.6), (-2e-3, -1e-3))]:
        z0, du = np.asarray(z0), np.asarray(du)
        step = 1e-4 * np.hypot(*du)
        columns = [(integrated(z0, du + step * e) - integrated(z0, du - step * e)) / (2 * step) for e in np.eye(2)]
        _, slope = park_exact_update_and_slope(h, jnp.asarray(z0), jnp.asarray(du))
        assert np.allclose(np.asarray(slope), np.stack(columns, -1), rtol=1e-6, atol=1e-6 * np.abs(slope).max())


def test_at_rest_each_column_is_the_one_sided_slope_of_its_direction():
    h = HYSTERESES[0]
    z0 = jnp.array([0.6, -0.7])
    _, slope = park_exact_update_and_slope(h, z0, jnp.zeros(2))
    step = 1e-9 * float(h.yield_disp)
    for j, e in enumerate(np.eye(2)):
        one_sided = (park_exact_update(h, z0, step * jnp.asarray(e)) - z0) / step
        assert np.allclose(np.asarray(slope[:, j]), np.asarray(one_sided), rtol=1e-6)


def test_constants_per_slider_broadcast_with_their_sliders():
    h = BoucWen(jnp.array([1e-3, 2e-4, 5e-4]), beta=jnp.array([0.5, 0.9, 0.1]), gamma=jnp.array([0.5, 0.1, 0.9]))
    z0 = jnp.array([[0.5, -0.3], [0.9, 0.1], [-0.2, -0.95]])
    du = jnp.array([[1e-3, -4e-4], [-2e-5, 3e-4], [6e-4, 2e-3]])
    _, slope = park_exact_update_and_slope(h, z0, du)
    jacobian = jax.jacfwd(lambda b: park_exact_update(h, z0, b))(du)
    for e in range(3):
        assert np.allclose(np.asarray(slope[e]), np.asarray(jacobian[e, :, e, :]), rtol=1e-11)


def _triple():
    return TriplePendulum(inner_radius=0.3, bottom_radius=2.1, top_radius=2.1, inner_capacity=0.05,
                          bottom_capacity=0.3, top_capacity=0.3,
                          inner_friction=FrictionParameters(0.03, 0.015, 20.0),
                          bottom_friction=FrictionParameters(0.08, 0.03, 20.0),
                          top_friction=FrictionParameters(0.12, 0.05, 20.0), hysteresis=BoucWen(0.005 * INCH))


def _breakaway_surface():
    params, ratio = interface_parameters("UF", 1000 * PSI)
    return single_pendulum(paper_bearing(params, breakaway_ratio=ratio), radius=1.5)


@pytest.mark.parametrize(("pendulum", "law"), [(_triple(), "mean"), (_breakaway_surface(), "mean"),
                                                (_breakaway_surface(), "end")], ids=["triple", "breakaway", "end"])
def test_the_sliders_newton_blocks_are_the_jacobian_of_their_forces(pendulum, law):
    count = pendulum.slider_count
    rng = np.random.default_rng(3)
    p = {"pendulum": pendulum, "N": 1e5, "s0": jnp.asarray(rng.normal(size=(count, 2)) * 0.05),
         "z0": jnp.asarray(rng.uniform(-0.6, 0.6, (count, 2)))}
    if pendulum.remembers:
        p["history"] = step_history(initial_history(pendulum, (count,), jnp.float64), p["z0"])
    if law == "end":  # the velocity at the step's end, linear in the increment
        p["v"] = (jnp.asarray(rng.normal(size=(count, 2)) * 0.2), jnp.asarray(-150.0))
    d = jnp.asarray(rng.normal(size=(count, 2)) * 1e-3)
    forces, z, blocks = balance_forces(p, d, 0.005, blocks=True)
    plain = balance_forces(p, d, 0.005)
    assert np.array_equal(np.asarray(forces), np.asarray(plain[0])) and np.array_equal(np.asarray(z),
                                                                                       np.asarray(plain[1]))
    jacobian = jax.jacfwd(lambda x: balance_forces(p, x, 0.005)[0])(d)
    own = np.stack([np.asarray(jacobian[e, :, e, :]) for e in range(count)])
    assert np.allclose(np.asarray(blocks), own, rtol=1e-10, atol=1e-10 * np.abs(own).max())


def _every_part_triple():
    """B7's triple with a different part on every surface, each at its own contact pressure."""
    parts = (SurfaceParts(breakaway_ratio=1.6, wear=Wear(0.3, 2.0)),
             SurfaceParts(friction_perpendicular=FrictionParameters(0.1, 0.04, 25.0), lay_angle=0.4,
                          asymmetry=DirectionAsymmetry(0.1)),
             SurfaceParts(pressure_dependence=PressureDependence(0.3, 2e5, contact_area=0.01), breakaway_ratio=1.2,
                          wear=Wear(-0.2, 1.0)))
    return dataclasses.replace(_triple(), surface_parts=parts, inner_pressure=30e6, bottom_pressure=20e6,
                               top_pressure=25e6)


def test_the_sliders_one_by_one_are_the_law_of_all_at_once():
    # a planar step's balance evaluates the sliders one after the other (`balance_forces`):
    # each slider's force, Z and block are those of the law over all sliders together
    # (`slider_forces`), with every per-slider input in its own slider's place
    pendulum = _every_part_triple()
    rng = np.random.default_rng(5)
    shape = (3, 2)
    z0 = jnp.asarray(rng.uniform(-0.9, 0.9, shape))
    # the inner slider before its breakaway ends, the top one after; each surface's own travel
    history = step_history({"z_peak": jnp.asarray([0.3, 0.5, 1.0]), "travel": jnp.asarray([0.1, 0.4, 2.0])}, z0)
    p = {"pendulum": pendulum, "N": 1e5, "s0": jnp.asarray(rng.normal(size=shape) * 0.05), "z0": z0,
         "k": jnp.asarray([0.9, 1.0, 0.8]), "history": history, "s": 1.3}
    d = jnp.asarray(rng.normal(size=shape) * 1e-3)
    together = slider_forces(pendulum, 1e5, p["s0"], z0, d, 0.005, p["k"], history, 1.3)
    one_by_one = balance_forces(p, d, 0.005, blocks=True)
    for own, all_at_once in zip(one_by_one, together):
        np.testing.assert_allclose(np.asarray(own), np.asarray(all_at_once), rtol=1e-13, atol=1e-13)
    jacobian = jax.jacfwd(lambda x: slider_forces(pendulum, 1e5, p["s0"], z0, x, 0.005, p["k"], history, 1.3)[0])(d)
    blocks = np.stack([np.asarray(jacobian[e, :, e, :]) for e in range(3)])
    np.testing.assert_allclose(np.asarray(one_by_one[2]), blocks, rtol=1e-10, atol=1e-10 * np.abs(blocks).max())
