"""The anisotropy law of the paper (MODEL.md, Section 4): f_max, delta_f and rate_a are
interpolated LINEARLY IN THE SLIDING ANGLE theta between the parallel-to-lay (theta = 0) and
perpendicular-to-lay (theta = 90 deg) rows of Table 1, w = theta / 90 deg.

At 45 deg the linear weight and sin^2(theta) both give 1/2, so the law is checked at angles
where the plausible candidates differ (sin^2 30 deg = 1/4, linear 1/3; sin 30 deg = 1/2), and
with the lay turned by phi, where turning the velocity the wrong way (or not at all) changes
the angle to the lay. The expected values are Eq. 1 written out here with the Table 1 rows.
"""

import math

import numpy as np
import pytest

from teflon_jax.bearing import paper_bearing
from teflon_jax.tables import interface_parameters
from teflon_jax.units import PSI

PARALLEL = interface_parameters("UF", 1000 * PSI, "P")[0]
PERPENDICULAR = interface_parameters("UF", 1000 * PSI, "T")[0]
SPEED = 0.05  # [m/s]: delta_f exp(-a v) still matters, so the mixed rate_a is seen too


def _expected(theta_deg: float, speed: float = SPEED) -> float:
    """Eq. 1 with each constant mixed linearly in the angle theta [deg] to the lay."""
    w = min(abs(theta_deg) % 180.0, 180.0 - abs(theta_deg) % 180.0) / 90.0

    def mix(name):
        return (1 - w) * float(getattr(PARALLEL, name)) + w * float(getattr(PERPENDICULAR, name))

    return mix("f_max") - mix("delta_f") * math.exp(-mix("rate_a") * speed)


def _velocity(direction_deg: float, speed: float = SPEED):
    angle = math.radians(direction_deg)
    return np.array(speed * math.cos(angle)), np.array(speed * math.sin(angle))


def test_candidate_laws_differ_where_the_law_is_checked():
    """Guard of the guard: at 30 and 70 deg the linear weight, sin^2(theta) and sin(theta)
    give coefficients far apart compared with the tolerance of the checks below (1e-12)."""
    for theta in (30.0, 70.0):
        sin = math.sin(math.radians(theta))
        for other_weight in (sin**2, sin):
            assert abs(_expected(theta) - _expected(90.0 * other_weight)) > 1e-5


@pytest.mark.parametrize("theta", [0.0, 20.0, 30.0, 60.0, 70.0, 90.0, 150.0, -120.0])
def test_constants_are_linear_in_the_sliding_angle(theta):
    """Lay along x: mu at a velocity theta from x is Eq. 1 with w = |theta| / 90 deg (folded)."""
    bearing = paper_bearing(PARALLEL, friction_perpendicular=PERPENDICULAR)
    mu = float(bearing.coefficient(*_velocity(theta)))
    assert mu == pytest.approx(_expected(theta), rel=1e-12, abs=1e-15)


@pytest.mark.parametrize("phi, direction", [(20.0, 50.0), (-25.0, 5.0), (35.0, -25.0), (100.0, 130.0)])
def test_lay_angle_turns_the_law(phi, direction):
    """Lay at phi from x towards y: a velocity at `direction` from x makes the angle
    direction - phi with the lay (30 or 60 deg here, never 45); turning the wrong way, or not
    turning, gives another angle and another coefficient."""
    bearing = paper_bearing(PARALLEL, friction_perpendicular=PERPENDICULAR, lay_angle=math.radians(phi))
    mu = float(bearing.coefficient(*_velocity(direction)))
    assert mu == pytest.approx(_expected(direction - phi), rel=1e-12, abs=1e-15)
    assert abs(_expected(direction - phi) - _expected(direction + phi)) > 1e-5
    assert abs(_expected(direction - phi) - _expected(direction)) > 1e-5


def test_sliding_along_x_with_a_turned_lay_uses_the_mixed_constants():
    """`uniaxial_coefficient` (the one-direction models) with the lay at 30 deg to x: the
    velocity is 30 deg from the lay, w = 1/3; its slope is d/dv of the same Eq. 1."""
    bearing = paper_bearing(PARALLEL, friction_perpendicular=PERPENDICULAR, lay_angle=math.radians(30.0))
    mu, slope = bearing.uniaxial_coefficient(np.array(SPEED))
    assert float(mu) == pytest.approx(_expected(30.0), rel=1e-12)
    h = 1e-6
    fd = (_expected(30.0, SPEED + h) - _expected(30.0, SPEED - h)) / (2 * h)
    assert float(slope) == pytest.approx(fd, rel=1e-6)
