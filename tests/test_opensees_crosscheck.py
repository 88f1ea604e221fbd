"""Cross-check of the rigid mass and the six-storey building under El Centro against OpenSees
(`flatSliderBearing` with `VelDependent` friction, see benchmarks/_opensees_models.py).

OpenSees' slider is elastic-perfectly-plastic with initial stiffness f_min W / Y (the sharp
limit of the Bouc-Wen loop) and has no breakaway, so the comparison uses breakaway_ratio=None
and a tolerance of a few per cent on peak base displacement and base shear.
"""

import sys

import jax.numpy as jnp
import numpy as np
import pytest

import teflon_jax as tj
from teflon_jax.structures import signal_from_motion, superstructure_matrices
from teflon_jax.systems import (
    building_response_quantities,
    rigid_mass,
    six_storey_building,
)

sys.path.insert(0, str(tj.__file__).rsplit("/teflon_jax/", 1)[0])
G = tj.units.STANDARD_GRAVITY
DURATION = 20.0  # [s] of El Centro (the strong part and the peaks)


@pytest.fixture(scope="module")
def opensees_models():
    try:
        from benchmarks import _opensees_models as models

        models.import_opensees()
    except ImportError as error:
        pytest.skip(f"openseespy cannot be imported: {error}")
    return models


@pytest.fixture(scope="module")
def record(external_data):
    motion = tj.load_record("elcentro")
    return motion.window(motion.start_time, motion.start_time + DURATION)


def _friction():
    friction, _ = tj.friction_table("UF", "P").at(1000 * tj.units.PSI)
    return friction


def test_rigid_mass_matches_opensees(opensees_models, record):
    friction, weight, period = _friction(), 1.0e6, 2.0
    k = weight / G * (2 * np.pi / period) ** 2
    peer = opensees_models.rigid_mass_on_slider(
        np.asarray(record.acceleration), record.time_step, weight=weight, f_max=float(friction.f_max),
        delta_f=float(friction.delta_f), rate_a=float(friction.rate_a), yield_disp=tj.DEFAULT_YIELD_DISP,
        spring_stiffness=k, damping_ratio=0.05, n_sub=4,
    )
    assert peer["n_failed"] == 0
    system = rigid_mass(weight=weight, bearing=tj.paper_bearing(friction), ground_acceleration=signal_from_motion(record),
                        time_step=0.005, isolation_period=period, damping_ratio=0.05)
    ours = tj.simulate_history(system, record.duration)
    np.testing.assert_allclose(float(jnp.max(jnp.abs(ours.displacement))), np.max(np.abs(peer["displacement"])), rtol=0.03)
    np.testing.assert_allclose(float(jnp.max(jnp.abs(ours.total_acceleration))),
                               np.max(np.abs(peer["total_acceleration"])), rtol=0.05)


@pytest.mark.slow
def test_building_matches_opensees(opensees_models, record):
    friction, period = _friction(), 2.0
    data = tj.load_table2()
    masses, K_s, C_s, _ = superstructure_matrices(data)
    total_mass = data.total_weight / G
    peer = opensees_models.building_on_sliders(
        np.asarray(record.acceleration), record.time_step, floor_masses=masses, stiffness=K_s, damping=C_s,
        base_mass=data.base_weight / G, f_max=float(friction.f_max), delta_f=float(friction.delta_f),
        rate_a=float(friction.rate_a), yield_disp=tj.DEFAULT_YIELD_DISP,
        rubber_stiffness=total_mass * (2 * np.pi / period) ** 2, rubber_damping_ratio=0.05,
        normal_load=data.total_weight, n_sub=4,
    )
    assert peer["n_failed"] == 0
    system = six_storey_building(bearing=tj.paper_bearing(friction), ground_acceleration=signal_from_motion(record),
                                 time_step=0.005, isolation_period=period)
    q = building_response_quantities(system, tj.simulate_history(system, record.duration))
    np.testing.assert_allclose(float(jnp.max(jnp.abs(q["base_displacement"]))),
                               np.max(np.abs(peer["base_displacement"])), rtol=0.03)
    superstructure_weight = masses.sum() * G
    np.testing.assert_allclose(float(jnp.max(jnp.abs(q["base_shear_ratio"]))),
                               np.max(np.abs(peer["base_shear"])) / superstructure_weight, rtol=0.05)
