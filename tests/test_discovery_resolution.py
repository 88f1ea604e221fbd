"""The evidence of `diagnose` on a noise-free record of the model it starts from: the current
model predicts the left-out cycles to rounding, so a held-out gain 1 - CV_after / CV_before
would be a ratio of two rounding errors (and delta_bic the log of one). Below the fits'
resolution (`RESOLUTION` of the force scale) there is nothing to gain: the gain is 0, the change
is reported against the force scale, each sum of squares counts as that level, and no effect is
added (blocked cross-validation and BIC as in `identification.discovery`)."""

import json
import math

import numpy as np
import pytest
from test_discovery import UF_1000_P, generate_record

from identification.discovery import (
    active_mask,
    default_parameters,
    prepare_record,
    simulate_augmented,
)
from identification.discovery._rounds import candidate_evidence
from teflon_jax.cli import main
from teflon_jax.formats import test_record_from_arrays, write_test_record
from teflon_jax.units import INCH

TRUTH = {**UF_1000_P, "yield_disp": 0.004 * INCH}


def _plain_record():
    """Eq. 1 with Bouc-Wen (the paper1990 baseline) at `TRUTH`, by discovery's own simulator."""
    path = generate_record(noise=0.0, cycles=2, samples_per_cycle=400)
    data, _ = prepare_record(path)
    force = np.asarray(simulate_augmented({**default_parameters(), **TRUTH}, data,
                                          active_mask(("velocity_dependence",)))["force"])
    return test_record_from_arrays(path.ux, force, time=path.time, normal_load=path.normal_load,
                                   metadata={"contact_area": path.metadata["contact_area"]})


def test_rounding_errors_give_no_gain_and_no_evidence():
    """A candidate that halves or multiplies by 400 a held-out error of 1e-9 of the force scale
    gains nothing and is not worth its parameter; above the resolution the ratio is kept."""
    scale, n = 1e5, 800
    full = 1e-12 * scale * np.random.default_rng(0).standard_normal(n)
    ref_sse = n * (1e-9 * scale) ** 2
    for cv in (0.5e-9 * scale, 4e-7 * scale):
        e = candidate_evidence(ref_sse, 1e-9 * scale, full, cv, 1, scale)
        assert e["holdout_gain"] == 0.0 and e["nothing_to_gain"]
        assert e["holdout_improvement"] == pytest.approx(1e-9 - cv / scale)
        assert e["delta_bic"] < 0, e
    noisy = candidate_evidence(n * (0.02 * scale) ** 2, 0.02 * scale, full, 0.01 * scale, 1, scale)
    assert noisy["holdout_gain"] == pytest.approx(0.5) and not noisy["nothing_to_gain"]


def test_a_noise_free_record_of_the_plain_model_names_nothing(tmp_path, capsys):
    record = tmp_path / "plain.csv"
    write_test_record(record, _plain_record(), units="SI")
    out = tmp_path / "d.json"
    assert main(["diagnose", str(record), "--json", str(out), "--report", str(tmp_path / "report"),
                 "--candidates", "asymmetry,heating"]) == 0
    said = capsys.readouterr().err
    document = json.loads(out.read_text())
    assert document["effects_added"] == [] and document["conclusion"] == "no missing effect"
    for name in ("f_max", "delta_f", "rate_a"):  # the batched fit recovers its own model
        assert document["parameters"][name] == pytest.approx(TRUTH[name], rel=1e-6), name
    refused = document["refused_candidates"]
    assert set(refused) == {"asymmetry", "heating"}
    for name, e in refused.items():
        assert math.isfinite(e["holdout_gain"]) and -1.0 <= e["holdout_gain"] <= 1.0, (name, e)
        assert e["nothing_to_gain"] and abs(e["holdout_improvement"]) < 1e-4, (name, e)
        assert e["delta_bic"] < 10, (name, e)
    assert "held-out gain nothing to gain" in said
    assert "nothing to gain" in (tmp_path / "report" / "report.md").read_text()
