"""Discovery's fits: on data its own candidate model made without noise they return the
constants that made it (to the solver's tolerance), from the starts discovery chooses.
"""

import numpy as np
import pytest
from test_discovery import HIDDEN, UF_1000_P, generate_record

from identification.discovery import (
    active_mask,
    default_parameters,
    discover_effects,
    prepare_record,
    simulate_augmented,
)
from teflon_jax.formats import test_record_from_arrays
from teflon_jax.units import INCH

EFFECTS = ("velocity_dependence", "asymmetry", "wear")
TRUTH = {**UF_1000_P, "yield_disp": 0.004 * INCH, "asymmetry": 0.08, "wear_change": -0.25}


def _own_record():
    """A record whose force is discovery's candidate model (`simulate_augmented`) at `TRUTH`."""
    path = generate_record(noise=0.0, cycles=2, samples_per_cycle=400, **HIDDEN["asymmetry"])
    data, _ = prepare_record(path)
    params = {**default_parameters(), **TRUTH}
    force = np.asarray(simulate_augmented(params, data, active_mask(EFFECTS))["force"])
    return test_record_from_arrays(path.ux, force, time=path.time,
                                   normal_load=path.normal_load,
                                   metadata={"contact_area": path.metadata["contact_area"]})


def test_fit_of_its_own_noise_free_model_returns_the_constants():
    result = discover_effects(_own_record(), baseline=EFFECTS, max_effects=0)
    assert result.fit_convergence["final_converged"], result.fit_convergence
    assert result.nrmse_final < 1e-7
    for name, value in TRUTH.items():
        assert result.parameters[name] == pytest.approx(value, rel=1e-5), name
