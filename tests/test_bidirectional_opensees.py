"""Cross-check of the bidirectional rigid mass and Table 2 building against OpenSees in 3D.

OpenSees' `flatSliderBearing` (3D, `VelDependent` friction, Eq. 1 at the resultant speed)
is elastic-perfectly-plastic with a circular slip surface: stiffness f_min W / Y until the
resultant force reaches mu W, then sliding at mu W along the direction of the elastic trial
force. teflon-jax uses Park's smooth biaxial Bouc-Wen Z (Eqs. 8-9) with the same Y, whose
loop rounds off the corner between stick and slip (|Z| approaches 1 gradually, over a few
Y) and whose force direction lags the velocity direction after a turn of the path. The two
differ only there; both use Eq. 1 at the resultant speed and the same springs, dampers,
masses and record interpolation, at the same 2.5 ms step. OpenSees has no breakaway, so both
run without it. Peaks are read after every step, the base shear as the total horizontal
force on the structure above the bearings over its weight.

Measured (UF / 1000 psi, T = 2.5 s springs, 5 % damping; ours minus OpenSees, relative):

- rigid mass, stochastic 10 s pair: displacement -2.8 %, base shear -0.75 % (the same at a
  0.5 ms step on both sides: -2.7 %, -0.73 %);
- building, the same pair: displacement -0.96 %, base shear -0.45 %;
- building, PEER RSN6 (180 + 270, first 30 s): displacement -0.17 %, base shear -0.20 %
  (the rigid mass on the same pair: -2.3 %, -0.56 %).

The difference is the shape of the stick-slip transition, not the integration: both models
tend to Coulomb friction with an elastic stick as Y -> 0, and with Y = 0.001 in instead of
0.005 in on both sides the rigid mass's differences drop to -0.50 % and -0.13 % (-0.38 %,
-0.10 % at 0.5 ms). The two loops differ over a few Y at each reversal: with the paper's
constants (A = 1, beta = 0.1, gamma = 0.9, eta = 2) Bouc-Wen's tangent is (1 - Z^2) mu W / Y on
loading and (1 + 0.8 Z^2) mu W / Y on unloading, and |Z| reaches 1 only asymptotically, where
the elastic-perfectly-plastic slider has f_min W / Y up to the circle |F| = mu W and none beyond;
in two directions the force also turns towards a new direction of motion differently. These
act over lengths of order Y per excursion and add up over a record (2.8 % of the rigid mass's
37 mm peak is about 8 Y); the building's peaks are set more by its springs and superstructure
and differ less.

The building tests can fail: with our f_max raised by 10 % both go red (displacement off by
4.9 % on the stochastic pair and 3.3 % on RSN6; 15 % moved the peaks by 7-22 %)."""

import importlib.util
import pathlib

import numpy as np
import pytest

from teflon_jax.bearing import paper_bearing
from teflon_jax.excitation import uniform_signal
from teflon_jax.formats import read_at2
from teflon_jax.systems import (
    rigid_mass,
    simulate_history,
    six_storey_building,
)
from teflon_jax.tables import interface_parameters
from teflon_jax.units import INCH, PSI, STANDARD_GRAVITY

_PATH = pathlib.Path(__file__).resolve().parent.parent / "benchmarks" / "bench_bidirectional.py"
_spec = importlib.util.spec_from_file_location("bench_bidirectional", _PATH)
bench = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(bench)
try:
    from _opensees_models import import_opensees

    import_opensees()
except ImportError as error:  # pragma: no cover
    pytest.skip(f"openseespy is not importable: {error}", allow_module_level=True)

PERIOD, ZETA, STEP = 2.5, 0.05, 0.0025


def _friction():
    params, _ = interface_parameters("UF", 1000 * PSI)
    return params, dict(f_max=float(params.f_max), delta_f=float(params.delta_f),
                        rate_a=float(params.rate_a), yield_disp=0.005 * INCH)


def _peaks(system, duration):
    """(peak resultant base displacement [m], peak resultant base shear ratio [-]) of teflon-jax."""
    response = simulate_history(system, duration)
    m, R = np.asarray(system.mass), np.asarray(system.influence)
    total = np.asarray(response.total_acceleration)
    force = np.einsum("tn,n,nd->td", total, m, R)
    n = m.size // 2
    disp = np.max(np.hypot(response.displacement[:, 0], response.displacement[:, n]))
    return float(disp), float(np.max(np.hypot(*force.T)) / (np.sum(m * R[:, 0]) * STANDARD_GRAVITY))


def _building_against_opensees(ax, ay, dt, duration):
    params, friction = _friction()
    disp_os, shear_os, _ = bench.opensees_building_3d(ax, ay, dt, period=PERIOD, damping_ratio=ZETA,
                                                      time_step=STEP, **friction)
    system = six_storey_building(components=2, bearing=paper_bearing(params), ground_acceleration=uniform_signal(ax, dt),
                                    ground_y=uniform_signal(ay, dt), time_step=STEP,
                                    isolation_period=PERIOD, isolation_damping=ZETA)
    return _peaks(system, duration), (disp_os, shear_os)


@pytest.mark.slow
def test_rigid_mass_under_two_components_agrees_with_opensees_3d():
    ax, ay = bench._pairs(1, 10.0)
    params, friction = _friction()
    weight = 1.0e5
    disp_os, shear_os, _ = bench.opensees_rigid_mass_3d(
        ax[0], ay[0], 0.01, weight=weight, period=PERIOD, damping_ratio=ZETA, time_step=STEP, **friction)
    system = rigid_mass(components=2,
        weight=weight, bearing=paper_bearing(params), ground_acceleration=uniform_signal(ax[0], 0.01),
        ground_y=uniform_signal(ay[0], 0.01), time_step=STEP, isolation_period=PERIOD, damping_ratio=ZETA)
    disp, shear = _peaks(system, 10.0)
    assert disp > 0.01
    assert abs(disp - disp_os) < 0.05 * disp_os
    assert abs(shear - shear_os) < 0.03 * shear_os


@pytest.mark.slow
def test_building_under_two_components_agrees_with_opensees_3d():
    ax, ay = bench._pairs(1, 10.0)
    (disp, shear), (disp_os, shear_os) = _building_against_opensees(ax[0], ay[0], 0.01, 10.0)
    assert disp > 0.01
    assert abs(disp - disp_os) < 0.03 * disp_os
    assert abs(shear - shear_os) < 0.03 * shear_os


@pytest.mark.slow
@pytest.mark.external
def test_building_under_rsn6_pair_agrees_with_opensees_3d(external_data):
    folder = external_data / "elcentro1940_peer_nga_rsn6"
    x = read_at2(folder / "RSN6_IMPVALL.I_I-ELC180-hor1.AT2")
    y = read_at2(folder / "RSN6_IMPVALL.I_I-ELC270-hor2.AT2")
    n = 3001  # the first 30 s (strong motion) of both components, sampled alike
    assert x.time_step == y.time_step and min(x.acceleration.size, y.acceleration.size) >= n
    ax, ay = np.asarray(x.acceleration[:n]), np.asarray(y.acceleration[:n])
    (disp, shear), (disp_os, shear_os) = _building_against_opensees(ax, ay, x.time_step, 30.0)
    assert disp > 0.02
    assert abs(disp - disp_os) < 0.03 * disp_os
    assert abs(shear - shear_os) < 0.03 * shear_os


@pytest.mark.slow
def test_rigid_mass_difference_from_opensees_shrinks_with_the_yield_displacement():
    """The difference from OpenSees is that of Bouc-Wen vs elastic-perfectly-plastic stick-slip:
    with Y five times smaller on both sides, the displacement difference falls below 1 %."""
    ax, ay = bench._pairs(1, 10.0)
    params, friction = _friction()
    differences = []
    for yield_disp in (0.005 * INCH, 0.001 * INCH):
        friction["yield_disp"] = yield_disp
        disp_os, _, _ = bench.opensees_rigid_mass_3d(
            ax[0], ay[0], 0.01, weight=1.0e5, period=PERIOD, damping_ratio=ZETA, time_step=STEP, **friction)
        system = rigid_mass(components=2,
            weight=1.0e5, bearing=paper_bearing(params, yield_disp=yield_disp),
            ground_acceleration=uniform_signal(ax[0], 0.01), ground_y=uniform_signal(ay[0], 0.01), time_step=STEP,
            isolation_period=PERIOD, damping_ratio=ZETA)
        differences.append(abs(_peaks(system, 10.0)[0] / disp_os - 1))
    assert differences[1] < 0.01
    assert differences[1] < 0.3 * differences[0]
