"""Anisotropic bearings whose lay of the steel is at an angle phi to x.

The physical statement: turning the bearing and the motion together by phi changes nothing but
the axes. Checked on the friction coefficient (exactly), on imposed-motion tests (Park's Z,
Tsit5) and end to end through `teflon-jax run` (rigid mass under a record). The parallel and
perpendicular limits are checked against Eq. 1 written out with Table 1's P and T rows.
"""

import json
import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from teflon_jax.bearing import paper_bearing
from teflon_jax.cli._main import main
from teflon_jax.excitation import AbstractBiaxialMotion, FigureEightMotion
from teflon_jax.systems import imposed_path_test
from teflon_jax.tables import interface_parameters
from teflon_jax.units import INCH, PSI

PARALLEL = interface_parameters("UF", 1000 * PSI, "P")[0]
PERPENDICULAR = interface_parameters("UF", 1000 * PSI, "T")[0]


def _bearing(lay_angle=None, breakaway=None):
    return paper_bearing(PARALLEL, friction_perpendicular=PERPENDICULAR, lay_angle=lay_angle,
                         breakaway_ratio=breakaway)


def _rotate(angle, x, y):
    c, s = math.cos(angle), math.sin(angle)
    return c * x - s * y, s * x + c * y


def _eq1(params, speed):
    return float(params.f_max) - float(params.delta_f) * np.exp(-float(params.rate_a) * speed)


@pytest.mark.parametrize("phi", [math.radians(30), math.radians(-70), math.radians(120)])
def test_coefficient_turns_with_the_lay(phi):
    """mu of the bearing with lay phi at velocity R(phi) v is mu of the lay-along-x bearing at
    v; along phi it is Eq. 1 with the P row, across phi with the T row."""
    v = np.random.default_rng(0).normal(scale=0.2, size=(64, 2))
    turned = _rotate(phi, v[:, 0], v[:, 1])
    np.testing.assert_allclose(_bearing(phi).coefficient(*turned), _bearing().coefficient(v[:, 0], v[:, 1]),
                               rtol=1e-12)
    speed = np.linspace(0.01, 0.5, 11)  # at rest the direction, and the row, is undefined
    along = _rotate(phi, speed, 0 * speed)
    across = _rotate(phi, 0 * speed, speed)
    np.testing.assert_allclose(_bearing(phi).coefficient(*along), _eq1(PARALLEL, speed), rtol=1e-12)
    np.testing.assert_allclose(_bearing(phi).coefficient(*across), _eq1(PERPENDICULAR, speed), rtol=1e-12)
    assert abs(_eq1(PARALLEL, 0.5) - _eq1(PERPENDICULAR, 0.5)) > 0.01  # the rows differ: the test can see it


def test_zero_lay_angle_keeps_the_lay_along_x_exactly():
    v = np.random.default_rng(1).normal(scale=0.2, size=(64, 2))
    np.testing.assert_array_equal(_bearing(0.0).coefficient(v[:, 0], v[:, 1]),
                                  _bearing().coefficient(v[:, 0], v[:, 1]))


class _Turned(AbstractBiaxialMotion):
    """A motion turned by `angle` [rad] in the plane."""

    motion: FigureEightMotion
    angle: float

    def _turn(self, u):
        c, s = jnp.cos(self.angle), jnp.sin(self.angle)
        return jnp.stack([c * u[0] - s * u[1], s * u[0] + c * u[1]])

    def displacement(self, t):
        return self._turn(self.motion.displacement(t))

    def velocity(self, t):
        return self._turn(self.motion.velocity(t))

    @property
    def duration(self):
        return self.motion.duration

    @property
    def angular_frequency(self):
        return self.motion.angular_frequency


@pytest.mark.slow
def test_imposed_figure_eight_turns_with_the_lay():
    """Eq. 16's figure eight on the lay-along-x bearing, and the same path turned by phi on the
    bearing with lay phi: the friction force turns by phi (Park's Z, Eq. 17 breakaway)."""
    phi = math.radians(35)
    path = FigureEightMotion(amplitude=2 * INCH, angular_frequency=2.0, cycles=1.0)
    reference = imposed_path_test(_bearing(breakaway=2.0), path, 1e5, samples_per_cycle=200)
    turned = imposed_path_test(_bearing(phi, breakaway=2.0), _Turned(path, phi), 1e5, samples_per_cycle=200)
    fx, fy = _rotate(phi, np.asarray(reference.fx), np.asarray(reference.fy))
    scale = float(np.max(np.hypot(fx, fy)))
    np.testing.assert_allclose(turned.fx, fx, atol=1e-6 * scale)
    np.testing.assert_allclose(turned.fy, fy, atol=1e-6 * scale)
    # the lay matters here: the same turned path on the lay-along-x bearing differs
    other = imposed_path_test(_bearing(breakaway=2.0), _Turned(path, phi), 1e5, samples_per_cycle=200)
    assert np.max(np.abs(np.asarray(other.fx) - fx)) > 1e-3 * scale


def _record(path, values, dt=0.01):
    path.write_text("time acc\n" + "\n".join(f"{i * dt:.4f} {a:.10e}" for i, a in enumerate(values)) + "\n")
    return str(path)


@pytest.mark.slow
def test_run_command_turns_with_the_lay(tmp_path):
    """`teflon-jax run`, rigid mass on anisotropic bearings: a record along x with the lay along
    x, and the same record along phi = 30deg (x and y components) with --lay-angle 30deg, give
    the same resultant peaks."""
    t = np.arange(301) * 0.01
    a = 0.35 * np.sin(2 * np.pi * 1.2 * t) * np.exp(-((t - 1.5) ** 2))  # [g]
    phi = math.radians(30)
    common = ["run", "--structure", "rigid", "--anisotropic", "--record-units", "g", "--time-step", "5ms",
              "--isolation-period", "2s"]
    assert main(common + ["--record-x", _record(tmp_path / "x.txt", a), "--json", str(tmp_path / "a.json")]) == 0
    assert main(common + ["--record-x", _record(tmp_path / "tx.txt", math.cos(phi) * a),
                          "--record-y", _record(tmp_path / "ty.txt", math.sin(phi) * a),
                          "--lay-angle", "30deg", "--json", str(tmp_path / "b.json")]) == 0
    first = json.loads((tmp_path / "a.json").read_text())
    second = json.loads((tmp_path / "b.json").read_text())
    assert second["lay_angle_deg"] == pytest.approx(30.0)
    for name in ("base_disp_resultant_m", "base_shear_ratio_resultant", "friction_force_ratio_resultant"):
        assert second["peak"][name] == pytest.approx(first["peak"][name], rel=1e-6), name
    assert first["peak"]["base_disp_resultant_m"] > 1e-3


@pytest.mark.parametrize("argv, message", [
    (["--lay-angle", "30deg"], "--lay-angle: the lay of the steel matters only for anisotropic bearings"),
    (["--anisotropic", "--lay-angle", "30"], "--lay-angle: '30' has no unit; write e.g. '30deg'"),
    (["--anisotropic", "--lay-angle", "30s"], "--lay-angle: unknown angle unit 's'"),
])
def test_bad_lay_angle_is_refused_by_name(argv, message, tmp_path, capsys):
    record = _record(tmp_path / "x.txt", np.zeros(11))
    assert main(["run", "--record-x", record, "--record-units", "g"] + argv) == 2
    assert message in capsys.readouterr().err


def test_lay_angle_needs_an_anisotropic_bearing():
    with pytest.raises(ValueError, match="lay_angle"):
        paper_bearing(PARALLEL, lay_angle=0.3)
    jax.block_until_ready(_bearing(0.3).coefficient(0.1, 0.0))
