"""The vertical ground component over several intensity levels (`monte_carlo_levels`, `montecarlo
--pga L1,L2 --limit`) and in the bounding analysis (`monte_carlo(design=bounding_design(...))`,
`--property-factors`): a vertical record of zeros leaves every level's (every case's) peaks,
counts and statistics as the horizontal-only run's, bit for bit; at each
level the vertical component's peak is `vertical_ratio` times that level's, so the uplift time
of every motion is the time its vertical record, drawn again from a model built at that level,
spends at 1 + a_v / g <= 0, and more motions lift off at the higher level; and a friction-only
rigid mass, whose horizontal-only shear cannot exceed f_max W, carries up to f_max N > f_max W
under the vertical component."""

import json

import jax
import numpy as np
import pytest
import xarray as xr

from teflon_jax.cli import main
from teflon_jax.excitation import (
    StochasticGroundMotion,
    TwoComponentGroundMotion,
    VerticalGroundMotion,
)
from teflon_jax.studies import (
    bounding_design,
    monte_carlo,
    monte_carlo_levels,
    monte_carlo_motion,
    motions_at_level,
)
from teflon_jax.systems import isolated_structure, with_vertical_component
from teflon_jax.units import STANDARD_GRAVITY

DURATION = 3.0
N = 3
LEVELS = (0.3 * STANDARD_GRAVITY, 1.0 * STANDARD_GRAVITY)
PEAKS = ("base_disp", "base_shear_ratio", "smooth_base_disp", "smooth_base_shear_ratio", "converged", "pga")


def _horizontal(pga):
    return StochasticGroundMotion(peak_ground_acceleration=pga, duration=DURATION, time_step=0.01, rise_time=0.5,
                                  strong_motion_duration=1.5)


def _levels(structure, motions):
    return monte_carlo_levels(structure, motions, LEVELS, N, key=jax.random.key(5), chunk_size=N,
                              devices=jax.devices()[:1])


def _uplift_of_record(vertical, record_step, time_step, n_steps):
    """dt times the steps k = 1..n whose end has 1 + a_v(k dt) / g <= 0, a_v the record
    interpolated linearly (as a `Signal` reads it)."""
    t = np.arange(1, n_steps + 1) * time_step
    a_v = np.interp(t, record_step * np.arange(vertical.size), vertical)
    return np.sum(1 + a_v / STANDARD_GRAVITY <= 0) * time_step


def test_each_levels_uplift_is_its_vertical_records_and_grows_with_the_level():
    """Motion j N + i of level j is drawn from a model built at that level from scratch (its
    vertical peak vertical_ratio times the level): the Monte Carlo's uplift time of every motion
    is the time that record spends with 1 + a_v / g <= 0 (a vertical component left at the
    first level's peak, or dropped, would not match at the second level), and more motions
    lift off at the higher level."""
    ratio = 1.5
    structure = isolated_structure("rigid", isolation_period=2.5)
    result, index = _levels(with_vertical_component(structure), VerticalGroundMotion(_horizontal(LEVELS[0]), ratio))
    dt, n_steps = structure.time_step, round(DURATION / structure.time_step)
    counts = []
    for j, level in enumerate(LEVELS):
        at_level = VerticalGroundMotion(_horizontal(level), ratio)
        for i in np.flatnonzero(index == j):
            rows = np.asarray(monte_carlo_motion(at_level, jax.random.key(5), int(i)))
            assert result.uplift_time[i] == pytest.approx(_uplift_of_record(rows[1], 0.01, dt, n_steps), abs=1e-12)
            assert result.pga[i] == pytest.approx(np.abs(rows[0]).max(), rel=1e-15)
        counts.append(int(np.sum(result.uplift_time[index == j] > 0)))
    assert counts[0] < counts[1] and result.converged.all()
    # the public helper gives the model built at the level, with two horizontal components too
    for wrap in (lambda m: m, TwoComponentGroundMotion):
        same = motions_at_level(VerticalGroundMotion(wrap(_horizontal(LEVELS[0])), ratio), LEVELS[1])
        built = VerticalGroundMotion(wrap(_horizontal(LEVELS[1])), ratio)
        np.testing.assert_array_equal(monte_carlo_motion(same, jax.random.key(5), 4),
                                      monte_carlo_motion(built, jax.random.key(5), 4))


def test_bounding_cases_with_the_vertical_component():
    """Friction-only rigid mass (no restoring force, no damping), the three bounding cases of
    f_max: horizontal only, the force on the mass mu(v) W Z stays at or below f_max W in every
    case; with a strong vertical component N reaches above W, some runs carry more than
    f_max W, and none more than f_max W (1 + max a_v / g); the uplift time, the record's
    alone, is the same in the three cases."""
    structure = isolated_structure("rigid", isolation_period=None, isolation_damping=0.0)
    design = bounding_design(structure, lower=0.8, upper=1.25)
    f_max = design["f_max"][:, None]

    def run(build, motions):
        return monte_carlo(build, motions, N, key=jax.random.key(3), design=design, chunk_size=N,
                           devices=jax.devices()[:1])

    horizontal = _horizontal(0.6 * STANDARD_GRAVITY)
    plain = run(structure, horizontal)
    assert np.all(plain.base_shear_ratio <= f_max * (1 + 1e-9))
    motions = VerticalGroundMotion(horizontal, 1.2)
    loaded = run(with_vertical_component(structure), motions)
    peak_up = np.array([np.asarray(monte_carlo_motion(motions, jax.random.key(3), i))[1].max() for i in range(N)])
    assert loaded.converged.all()
    assert np.any(loaded.base_shear_ratio > f_max * 1.01)
    assert np.all(loaded.base_shear_ratio <= f_max * (1 + peak_up / STANDARD_GRAVITY) * (1 + 1e-9))
    assert loaded.uplift_time.shape == (3, N) and np.all(loaded.uplift_time == loaded.uplift_time[0])


FRICTION_ONLY = ["montecarlo", "--motions", "3", "--duration", "4s", "--strong-motion", "1.5s",
                 "--isolation-period", "none", "--isolation-damping", "0", "--no-progress"]


def _assert_same_to_rounding(got, want, where="cases"):
    """Nested dicts with the same keys, equal strings and integers, and floats equal to 1e-12
    relative (the two runs compile different programs, so the last bits may differ)."""
    if isinstance(want, dict):
        assert isinstance(got, dict) and got.keys() == want.keys(), where
        for key in want:
            _assert_same_to_rounding(got[key], want[key], f"{where}.{key}")
    elif isinstance(want, float):
        assert got == pytest.approx(want, rel=1e-12, abs=1e-15), where
    else:
        assert got == want, where


def _f_max():
    """f_max of the default bearing (UF PTFE at 1000 psi, Table 1)."""
    structure = isolated_structure("rigid", isolation_period=None)
    return float(structure.table().at(structure.pressure)[0].f_max)


@pytest.mark.last_bit
def _same_to_rounding(a, b):
    """`a` and `b` (nested lists and dicts of numbers, strings, None) equal, numbers to 1e-12."""
    if isinstance(a, dict):
        assert a.keys() == b.keys()
        for key in a:
            _same_to_rounding(a[key], b[key])
    elif isinstance(a, list):
        assert len(a) == len(b)
        for x, y in zip(a, b):
            _same_to_rounding(x, y)
    elif isinstance(a, float):
        assert a == pytest.approx(b, rel=1e-12, abs=1e-300)
    else:
        assert a == b


def test_cli_levels_and_limits_with_a_zero_vertical_ratio(tmp_path):
    """`--pga 0.3g,1g --limit base_shear_ratio=1.02 f_max --limit base_disp=5cm` on a
    friction-only rigid mass: with `--vertical-ratio 0` every level's statistics and every
    limit's counts are those of the run without the flag, to rounding (its Table 1 bearing reads
    the table at s p = p, another sequence of operations); horizontal only the force on the
    mass mu(v) W Z cannot exceed f_max W, so no run exceeds the shear limit."""
    limit = f"base_shear_ratio={1.02 * _f_max():.6f}"
    common = [*FRICTION_ONLY, "--pga", "0.3g,1g", "--limit", limit, "--limit", "base_disp=5cm"]
    # exit 1: the shear limit's counts (none exceed) admit no fragility fit; all is written
    assert main([*common, "--json", str(tmp_path / "a.json")]) == 1
    assert main([*common, "--vertical-ratio", "0", "--json", str(tmp_path / "b.json")]) == 1
    plain, loaded = (json.loads((tmp_path / name).read_text()) for name in ("a.json", "b.json"))
    _same_to_rounding(loaded["fragility"], plain["fragility"])
    _same_to_rounding([lv["statistics"] for lv in loaded["levels"]], [lv["statistics"] for lv in plain["levels"]])
    assert plain["fragility"][limit]["n_exceed"] == [0, 0]
    assert [lv["uplift"]["n_uplifted"] for lv in loaded["levels"]] == [0, 0] and "uplift" not in plain["levels"][0]


def test_cli_levels_with_the_vertical_component(tmp_path, capsys):
    """`--vertical-ratio 1.2` with the same levels and limit: N reaches above W, so runs now
    exceed the shear limit; each level's uplifted motions in the summary are those whose
    `uplift_time` in the results file is > 0 at that level, more of them at 1g than at 0.3g,
    and the uplifted runs stay in the counts."""
    limit = f"base_shear_ratio={1.02 * _f_max():.6f}"
    out = tmp_path / "lv.nc"
    assert main([*FRICTION_ONLY, "--pga", "0.3g,1g", "--limit", limit, "--vertical-ratio", "1.2",
                 "--json", str(tmp_path / "v.json"), "--out", str(out)]) in (0, 1)  # 1: no fit, all written
    printed = capsys.readouterr().out
    payload = json.loads((tmp_path / "v.json").read_text())
    assert payload["fragility"][limit]["n_exceed"][1] > 0
    assert payload["fragility"][limit]["n_runs"] == [3, 3]
    with xr.open_dataset(out) as data:
        uplift, level = data["uplift_time"].values, data["intensity_level"].values
    counts = []
    for j, entry in enumerate(payload["levels"]):
        rows = np.flatnonzero(level == np.unique(level)[j])
        assert entry["uplift"]["uplifted_motions"] == rows[uplift[rows] > 0].tolist()
        assert entry["uplift"]["uplift_time_s"] == uplift[rows][uplift[rows] > 0].tolist()
        counts.append(entry["uplift"]["n_uplifted"])
    assert counts[0] < counts[1] and payload["vertical"]["n_uplifted"] == sum(counts)
    assert f"uplift (N <= 0), motions per level: 0.3g: {counts[0]}/3, 1g: {counts[1]}/3" in printed


@pytest.mark.parametrize("ratio", [pytest.param("0", marks=pytest.mark.slow), "1.2"])
def test_cli_property_factors_with_the_vertical_component(tmp_path, ratio):
    """`--property-factors 0.8,1.25` on the friction-only rigid mass: with `--vertical-ratio 0`
    the three cases' table is the run's without the flag (to rounding), and no case's peak shear exceeds its
    f_max; with 1.2 every case's largest peak shear is above its f_max (N > W) and the summary
    carries the vertical component's entry."""
    common = [*FRICTION_ONLY, "--pga", "0.6g", "--property-factors", "0.8,1.25"]
    assert main([*common, "--vertical-ratio", ratio, "--json", str(tmp_path / "v.json")]) == 0
    loaded = json.loads((tmp_path / "v.json").read_text())
    cases = loaded["cases"]
    assert loaded["vertical"]["vertical_ratio"] == float(ratio)
    if ratio == "0":
        assert main([*common, "--json", str(tmp_path / "a.json")]) == 0
        _assert_same_to_rounding(cases, json.loads((tmp_path / "a.json").read_text())["cases"])
        assert all(c["max"]["base_shear_ratio"] <= c["f_max"] * (1 + 1e-9) for c in cases.values())
        assert loaded["vertical"]["n_uplifted"] == 0
    else:
        assert all(c["max"]["base_shear_ratio"] > c["f_max"] * 1.01 for c in cases.values())
