"""The batched fits of `diagnose` on a flat slider keep Eq. 1's friction at rest non-negative:
each delta_f is fitted as its ratio to f_max in (0, 1) (`identification.bearing_fit._ratio`, as
the single flat fit and the series fits), mu = f_max - delta_f exp(-rate_a |v|) (Constantinou,
Mokha & Reinhorn 1990, Eq. 1). A smoothed Coulomb loop, which Eq. 1 matches best with delta_f
above f_max, ends with 0 <= delta_f <= f_max and a bearing file that loads; the batched fit
still returns the constants of a noise-free record of its own model."""

import json

import numpy as np
import pytest

from teflon_jax.cli import main
from teflon_jax.formats import load_bearing, test_record_from_arrays, write_test_record


def _smoothed_coulomb(path):
    """Two cycles of a 0.5 Hz sine of 0.05 m under 1 MN, friction 0.06 tanh(20 cos(pi t))."""
    t = np.linspace(0.0, 4.0, 401)
    u = 0.05 * np.sin(np.pi * t)
    force = 1e6 * 0.06 * np.tanh(20.0 * np.cos(np.pi * t))
    write_test_record(path, test_record_from_arrays(u, force, time=t, normal_load=np.full(t.size, 1e6)),
                      units="SI")
    return path


def test_a_smoothed_coulomb_loop_keeps_delta_f_below_f_max_and_is_saved(tmp_path):
    record = _smoothed_coulomb(tmp_path / "sine.csv")
    saved = tmp_path / "bearing.json"
    assert main(["diagnose", str(record), "--json", str(tmp_path / "d.json"), "--report",
                 str(tmp_path / "report"), "--quiet", "--max-effects", "0",
                 "--save-bearing", str(saved)]) == 0
    parameters = json.loads((tmp_path / "d.json").read_text())["parameters"]
    assert 0 <= parameters["delta_f"] <= parameters["f_max"], parameters
    friction = load_bearing(saved).friction
    assert 0 <= float(friction.delta_f) < float(friction.f_max)
    assert float(friction.f_max) == pytest.approx(parameters["f_max"], rel=1e-12)


def test_the_ratio_goes_in_and_out_of_the_optimiser_and_holds_what_is_held():
    """A free delta_f is its ratio times f_max; a held one stays at its start whatever the
    ratio; a known delta_f bounds a fitted f_max from below."""
    from identification.discovery._augmented import PARAMETER_NAMES
    from identification.discovery._batch_fit import _physical, _ratio_search, _ratio_starts
    from identification.discovery._effects import EFFECT_NAMES

    start = np.array([[{"f_max": 0.1, "delta_f": 0.04}.get(n, 1.0) for n in PARAMETER_NAMES]])
    inner = _ratio_starts(start)
    assert inner["delta_ratio"] == pytest.approx(0.4) and "delta_f" not in inner
    i, j = PARAMETER_NAMES.index("delta_f"), PARAMETER_NAMES.index("f_max")
    params = {k: np.asarray(v[0]) for k, v in inner.items()} | {"f_max": np.asarray(0.2), "delta_ratio": np.asarray(0.7)}
    free = np.ones(len(PARAMETER_NAMES))
    assert float(_physical(params, start[0], free)["delta_f"]) == pytest.approx(0.14)
    free[i] = 0.0
    assert float(_physical(params, start[0], free)["delta_f"]) == pytest.approx(0.04)
    actives = np.ones((1, len(EFFECT_NAMES)))
    low = np.array([[{"f_max": 0.01, "delta_f": 0.04}.get(n, 1.0) for n in PARAMETER_NAMES]])
    starts, bounds = _ratio_search(low, free[None, :], actives)
    assert bounds["f_max"][0] == pytest.approx(0.04) and starts[0, j] > 0.04
    assert bounds["delta_ratio"] == (0.0, 1.0)
