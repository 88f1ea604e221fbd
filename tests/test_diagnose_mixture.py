"""`diagnose --mixture bic`: the compositions a search fitted, weighed by BIC, and the bearing
file's mixture that `montecarlo --bearing` draws from.

The records come from the independent generator of `test_discovery.py`."""

import json
import math

import numpy as np
import pytest
from test_discovery import UF_1000_T, generate_record

from identification.discovery import (
    composition_bic,
    composition_weights,
    discover_effects,
    discovery_mixture,
)
from teflon_jax.cli import main
from teflon_jax.formats import load_bearing_mixture, save_bearing, write_test_record
from teflon_jax.units import INCH


def test_the_weights_are_exp_of_minus_half_the_bic_above_the_lowest_normalised():
    bic = np.array([103.0, 100.0, 100.0 + 2 * math.log(9.0), 160.0])
    w = composition_weights(bic)
    expected = np.exp(-(bic - 100.0) / 2)
    np.testing.assert_allclose(w, expected / expected.sum(), rtol=1e-14)
    assert math.isclose(w.sum(), 1.0, rel_tol=1e-15)
    assert w[1] == w.max() and w[1] / w[2] == pytest.approx(9.0, rel=1e-12)
    np.testing.assert_allclose(composition_weights([5.0, 5.0]), [0.5, 0.5], rtol=0)
    np.testing.assert_allclose(composition_weights([1e6, 1e6 + 2 * math.log(3.0)]), [0.75, 0.25], rtol=1e-9)
    with pytest.raises(ValueError, match="finite"):
        composition_weights([1.0, float("nan")])


def test_the_bic_is_n_eff_ln_of_the_mean_square_plus_ln_n_eff_per_constant():
    rng = np.random.default_rng(0)
    residuals = [rng.standard_normal(400) * s for s in (1.0, 0.5)]
    bic = composition_bic(residuals, [2, 5], 150.0)
    for r, p, b in zip(residuals, (2, 5), bic):
        assert b == pytest.approx(150.0 * math.log(np.mean(r**2)) + p * math.log(150.0), rel=1e-12)
    with pytest.raises(ValueError, match="n_eff"):
        composition_bic(residuals, [2, 5], 1.0)


def test_a_noise_free_record_of_the_baseline_weighs_no_composition_by_its_rounding():
    """A noise-free record of Eq. 1 (the simulator on the analytic motion): the baseline and
    the candidates that contain it (wear, asymmetry) all fit it to rounding, far below the
    fits' tolerance `RESOLUTION`. Their BIC differ by p_c ln(n_eff) alone, so that the two
    candidates of one constant more weigh the same and the baseline most; before the floor,
    ln(SSR) of rounding-level sums of squares set their weights apart."""
    from types import SimpleNamespace

    from test_fit import _synthetic

    from identification.discovery._rounds import RESOLUTION

    row = SimpleNamespace(f_max=0.10, delta_f=0.05, rate_a=0.6 / INCH, breakaway_ratio=None)
    result = discover_effects(_synthetic(row, 0, noise=0.0, cycles=2, fs=300.0),
                              candidates=["breakaway", "wear", "asymmetry"])
    mixture = discovery_mixture(result, draws=100)
    rows = {frozenset(r["effects"]) - {"velocity_dependence"}: r for r in mixture.table}
    base, wear, asymmetry = rows[frozenset()], rows[frozenset({"wear"})], rows[frozenset({"asymmetry"})]
    assert max(r["nrmse"] for r in (base, wear, asymmetry)) < RESOLUTION / 2, mixture.table
    assert base["selected"] and base["weight"] == max(r["weight"] for r in mixture.table)
    step = math.log(mixture.effective_samples)
    for r in (wear, asymmetry):
        assert r["delta_bic"] == pytest.approx((r["free_parameters"] - base["free_parameters"]) * step,
                                               rel=1e-9), mixture.table
    assert wear["weight"] == pytest.approx(asymmetry["weight"], rel=1e-9)


def test_the_help_names_the_mixture_flags():
    from teflon_jax.cli._main import _parser

    parser = _parser(only="diagnose")
    sub = next(a for a in parser._actions if a.dest == "command").choices["diagnose"]
    text = sub.format_help()
    assert "--mixture {bic}" in text and "--mixture-draws K" in text


@pytest.mark.parametrize("flags, message", [
    (["--mixture-draws", "500"], "--mixture-draws: applies with --mixture bic only"),
    (["--mixture", "bic", "--mixture-draws", "50"], "--mixture-draws: must be at least 100"),
    (["--mixture", "bic", "--isolator", "double-fp", "--isolator-file", "{start}"],
     "--mixture: not with --isolator double-fp"),
])
def test_mixture_flags_that_cannot_run_are_refused_before_any_work(tmp_path, capsys, flags, message):
    start = tmp_path / "start.json"
    start.write_text("{}")
    flags = [f.format(start=start) for f in flags]
    code = main(["diagnose", str(tmp_path / "not-read.csv"), "--json", str(tmp_path / "d.json"),
                 "--report", str(tmp_path / "rep"), "--quiet", *flags])
    assert code == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "d.json").exists()


def _breakaway_record(noise, seed=3):
    """Test No. 191's protocol (0.5 in at 0.03 Hz, Table 1's T row) with b = 3 (Eq. 17)."""
    return generate_record(amplitude=0.5 * INCH, frequency=0.03, friction=UF_1000_T, breakaway_ratio=3.0,
                           samples_per_cycle=200, noise=noise, seed=seed)


def _weights(mixture) -> dict:
    return {frozenset(row["effects"]): row["weight"] for row in mixture.table}


@pytest.mark.parametrize("noise", [0.0, pytest.param(0.015, marks=pytest.mark.slow)])
def test_the_weights_favour_the_composition_the_record_was_made_with(noise):
    """A record made with breakaway (Eq. 17), without noise and with 1.5 % noise: the
    composition of Eq. 1 with breakaway carries most of the weight, and Eq. 1 alone none; the
    other candidates, which the record does not have, each carry less than it."""
    result = discover_effects(_breakaway_record(noise), candidates=["breakaway", "wear", "asymmetry"])
    mixture = discovery_mixture(result, draws=200)
    weights = _weights(mixture)
    true = weights[frozenset({"velocity_dependence", "breakaway"})]
    assert true == max(weights.values()) and true > 0.5, mixture.table
    assert weights[frozenset({"velocity_dependence"})] < 1e-6
    assert math.isclose(sum(weights.values()), 1.0, rel_tol=1e-12)
    chosen = next(row for row in mixture.table if row["selected"])
    assert set(chosen["effects"]) == {"velocity_dependence", "breakaway"} and chosen["in_mixture"]
    # the file's mixture: the compositions of weight >= 0.001, renormalised, each with draws
    kept = mixture.mixture
    assert math.isclose(kept.weights.sum(), 1.0, rel_tol=1e-12)
    heaviest = kept.compositions[0]
    assert set(heaviest.effects) == {"velocity_dependence", "breakaway"}
    b = heaviest.posterior.draws["breakaway_ratio"]
    assert abs(np.median(b) - 3.0) < 0.1 and b.size == 200


def _twin_record(noise=0.015, seed=4, cycles=3, samples_per_cycle=150, frequency=0.16, change=-0.25):
    """Friction falling with travel, 1 + change x (x the travel over its total), and a measured
    temperature that makes the heating law k_T(T) / k_T(T0) (Kumar et al. 2015) the same factor:
    wear and heating with a measured temperature are one law on this record."""
    n = int(cycles * samples_per_cycle) + 1
    t = np.linspace(0.0, cycles / frequency, n)
    ux = 1.0 * INCH * np.sin(2 * math.pi * frequency * t)
    travel = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(ux)))])
    k0 = 0.7 ** (20.0 / 50.0) + 0.4  # k_T(20 degC) / 0.79
    temperature = 50.0 * np.log((1 + change * travel / travel[-1]) * k0 - 0.4) / math.log(0.7)
    return generate_record(cycles=cycles, samples_per_cycle=samples_per_cycle, frequency=frequency,
                           noise=noise, seed=seed, temperature_scale=1.0,
                           temperature=lambda s: float(np.interp(s, t, temperature)))


@pytest.mark.slow
def test_the_weights_split_between_compositions_the_record_cannot_tell_apart():
    result = discover_effects(_twin_record(), candidates=["heating", "wear"])
    weights = _weights(discovery_mixture(result, draws=200))
    heating = weights[frozenset({"velocity_dependence", "heating"})]
    wear = weights[frozenset({"velocity_dependence", "wear"})]
    assert 0.3 < heating < 0.7 and 0.3 < wear < 0.7, weights
    assert heating + wear > 0.9


@pytest.mark.slow  # a search, then Monte Carlo programs for each composition and a bearing: ~1.5 min
def test_montecarlo_draws_from_the_mixture_diagnose_saved(tmp_path, capsys):
    record = tmp_path / "twin.csv"
    write_test_record(record, _twin_record())
    found, diagnosis = tmp_path / "found.json", tmp_path / "d.json"
    code = main(["diagnose", str(record), "--candidates", "heating,wear", "--json", str(diagnosis),
                 "--report", str(tmp_path / "rep"), "--save-bearing", str(found), "--mixture", "bic",
                 "--mixture-draws", "150", "--quiet"])
    assert code == 0, capsys.readouterr().err
    document = json.loads(diagnosis.read_text())["mixture"]
    assert document["criterion"] == "bic"
    assert math.isclose(sum(row["weight"] for row in document["compositions"]), 1.0, rel_tol=1e-12)
    mixture = load_bearing_mixture(found)
    assert {c.label for c in mixture.compositions} >= {"velocity_dependence+heating", "velocity_dependence+wear"}
    assert "Compositions weighed by their evidence" in (tmp_path / "rep" / "report.md").read_text()
    out = tmp_path / "mc.json"
    motions = ["montecarlo", "--motions", "6", "--duration", "4s", "--strong-motion", "2s", "--no-progress"]
    code = main([*motions, "--bearing", str(found), "--json", str(out), "--out", str(tmp_path / "mc.csv"),
                 "--bearing-seed", "2"])
    assert code == 0, capsys.readouterr().err
    entry = json.loads(out.read_text())["bearing_mixture"]
    counts = mixture.motion_counts(6, seed=2)
    assert entry["mixture_motions"] == counts.tolist()
    assert entry["composition"] == np.repeat(np.arange(mixture.size), counts).tolist()
    assert len(entry["bearing_draw"]) == 6
    for c, composition in enumerate(entry["compositions"]):
        assert composition["effects"] == list(mixture.compositions[c].effects)
        assert composition["motions"] == counts[c]
    # the last motion ran its composition's draw: the same peak as that one bearing on that motion
    c, k = entry["composition"][-1], entry["bearing_draw"][-1]
    one = save_bearing(tmp_path / "one.json", mixture.compositions[c].posterior.bearing(
        mixture.compositions[c].bearing, k))
    assert main([*motions, "--bearing", str(one), "--json", str(tmp_path / "one-mc.json"),
                 "--out", str(tmp_path / "one.csv")]) == 0
    mixed, alone = (np.genfromtxt(tmp_path / name, delimiter=",", names=True) for name in ("mc.csv", "one.csv"))
    assert mixed["base_disp_m"][-1] == pytest.approx(alone["base_disp_m"][-1], rel=1e-9)
    assert mixed["pga_m_s2"][-1] == alone["pga_m_s2"][-1]
