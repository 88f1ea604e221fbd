"""The building's storey results and pelicun demand files under a vertical ground component.

The superstructure is rigid vertically, so the vertical record acts through the isolators'
normal load N = W max(1 + a_v / g, 0) alone; the storey drifts and level accelerations stay
horizontal. Reference: the full response histories of `simulate_history` of each motion
built into the building with the public `with_vertical_motion` (drifts and total
accelerations taken with NumPy from the saved states), and the horizontal-only run, which a
vertical record of zeros reproduces (the CLI's summary and demand file too) to `ROUNDING`."""

import json

import jax
import numpy as np
import pytest

from teflon_jax import simulate_history, uniform_signal
from teflon_jax.cli import main
from teflon_jax.excitation import StochasticGroundMotion, VerticalGroundMotion
from teflon_jax.studies import monte_carlo, monte_carlo_motion
from teflon_jax.systems import (
    isolated_structure,
    with_vertical_component,
)
from teflon_jax.tables import load_table2
from teflon_jax.units import PSI, STANDARD_GRAVITY

DURATION = 3.0
N = 2
ROUNDING = 1e-9
"""Relative tolerance between the runs with and without a vertical record of zeros. Their
steps are the same bit for bit from the same state (N = W exactly,
`test_montecarlo_vertical_two.test_a_zero_vertical_record_steps_bit_for_bit`), but the two
runs are compiled as different programs, whose fused arithmetic may round a last bit
differently; the building's stick-slip carries such a bit to about 3e-13 of a level
acceleration over the run (two components, four seconds)."""


def _model():
    return StochasticGroundMotion(peak_ground_acceleration=0.5 * STANDARD_GRAVITY, duration=DURATION,
                                  time_step=0.01, rise_time=0.5, strong_motion_duration=1.5)


def test_storey_peaks_under_the_vertical_component_are_the_direct_simulations():
    """vertical_ratio 2: each motion's peak storey drifts and level accelerations equal those of
    the saved history of that motion simulated with its vertical record (1e-8), its uplift
    time is the history's, and the history without the vertical record has other storey
    peaks (so a run that ignored the component would fail)."""
    structure = isolated_structure("building", time_step=0.005, pressure=2000 * PSI, isolation_period=1.5)
    height = load_table2().storey_height

    def run(build, motions):
        return monte_carlo(build, motions, N, key=jax.random.key(7), chunk_size=N, devices=jax.devices()[:1],
                           storey_height=height)

    motions = VerticalGroundMotion(_model(), 2.0)
    loaded = run(with_vertical_component(structure), motions)
    assert loaded.converged.all() and loaded.n_uplifted > 0
    for i in range(N):
        rows = np.asarray(monte_carlo_motion(motions, jax.random.key(7), i))
        system = with_vertical_component(structure)((uniform_signal(rows[0], 0.01), uniform_signal(rows[1], 0.01)))
        history = simulate_history(system, DURATION)
        u = np.asarray(history.displacement)
        np.testing.assert_allclose(loaded.storey_drift[i], np.abs(np.diff(u, axis=1)).max(axis=0) / height,
                                   rtol=1e-8)
        np.testing.assert_allclose(loaded.floor_acceleration[i],
                                   np.abs(np.asarray(history.total_acceleration)).max(axis=0), rtol=1e-8)
        assert loaded.uplift_time[i] == pytest.approx(float(history.uplift_time), abs=1e-12)
    horizontal = np.asarray(simulate_history(structure(uniform_signal(rows[0], 0.01)), DURATION).displacement)
    assert not np.allclose(loaded.storey_drift[-1], np.abs(np.diff(horizontal, axis=1)).max(axis=0) / height,
                           rtol=1e-3)


@pytest.mark.parametrize("components", [1, pytest.param(2, marks=pytest.mark.slow)])
def test_cli_storeys_and_demand_file_with_a_zero_vertical_ratio(tmp_path, capsys, components):
    """`montecarlo --structure building --pelicun-demands` (storey results on) with
    `--vertical-ratio 0`: the summary's storey results and statistics and the demand file are
    those of the run without the flag, and the summary says no motion lifted off and that the
    storey results are horizontal."""
    common = ["montecarlo", "--motions", "2", "--duration", "4s", "--strong-motion", "1.5s", "--structure",
              "building", "--storeys", "--components", str(components), "--no-progress"]
    assert main([*common, "--json", str(tmp_path / "a.json"), "--pelicun-demands", str(tmp_path / "a.csv")]) == 0
    assert main([*common, "--vertical-ratio", "0", "--json", str(tmp_path / "b.json"),
                 "--pelicun-demands", str(tmp_path / "b.csv")]) == 0
    printed = capsys.readouterr().out
    plain, loaded = (json.loads((tmp_path / name).read_text()) for name in ("a.json", "b.json"))
    for part in ("storeys", "statistics"):
        _assert_same_numbers(loaded["levels"][0][part], plain["levels"][0][part])
    _assert_same_csv(tmp_path / "b.csv", tmp_path / "a.csv")
    assert loaded["levels"][0]["uplift"]["n_uplifted"] == 0 and "horizontal" in loaded["vertical"]["storeys"]
    assert "uplift (N <= 0), motions per level: 0.3g: 0/2" in printed


def _leaves(value, path=""):
    """[(path, leaf)] of a JSON value, depth first."""
    if isinstance(value, dict):
        return [leaf for key in value for leaf in _leaves(value[key], f"{path}.{key}")]
    if isinstance(value, list):
        return [leaf for i, item in enumerate(value) for leaf in _leaves(item, f"{path}[{i}]")]
    return [(path, value)]


def _assert_same_numbers(loaded, plain):
    """The JSON values `loaded` and `plain` alike: the same paths and texts, numbers to `ROUNDING`."""
    loaded, plain = _leaves(loaded), _leaves(plain)
    assert [path for path, _ in loaded] == [path for path, _ in plain]
    numbers = [(path, a, b) for (path, a), (_, b) in zip(loaded, plain) if isinstance(b, float)]
    texts = [(a, b) for (_, a), (_, b) in zip(loaded, plain) if not isinstance(b, float)]
    assert [a for a, _ in texts] == [b for _, b in texts]
    np.testing.assert_allclose([a for _, a, _ in numbers], [b for _, _, b in numbers], rtol=ROUNDING, atol=0,
                               err_msg=", ".join(path for path, _, _ in numbers[:3]))


def _assert_same_csv(loaded, plain):
    """Two CSV files alike: the same lines but for numbers, which agree to `ROUNDING`."""
    rows = [[line.split(",") for line in path.read_text().splitlines()] for path in (loaded, plain)]
    assert [len(r) for r in rows[0]] == [len(r) for r in rows[1]]
    for row_loaded, row_plain in zip(*rows):
        for a, b in zip(row_loaded, row_plain):
            try:
                np.testing.assert_allclose(float(a), float(b), rtol=ROUNDING, atol=0)
            except ValueError:  # a header or a text cell
                assert a == b


def test_cli_demand_files_per_level_with_the_vertical_component(tmp_path):
    """`--pga 0.3g,0.8g --vertical-ratio 2 --pelicun-demands d.csv --out mc.nc` on the building:
    each level's demand file holds that level's motions' peaks from the results file, which
    has each motion's uplift time (some lift off at 0.8g; the demands are those runs', uplift
    included), and the summary notes that the demands are horizontal."""
    import xarray as xr

    assert main(["montecarlo", "--motions", "2", "--duration", "4s", "--strong-motion", "1.5s", "--structure",
                 "building", "--pga", "0.3g,0.8g", "--vertical-ratio", "2", "--no-progress",
                 "--json", str(tmp_path / "v.json"), "--pelicun-demands", str(tmp_path / "d.csv"),
                 "--out", str(tmp_path / "mc.nc")]) == 0
    payload = json.loads((tmp_path / "v.json").read_text())
    with xr.open_dataset(tmp_path / "mc.nc") as data:
        drift, disp, uplift = (data[k].values for k in ("storey_drift", "base_disp", "uplift_time"))
    for j in range(2):
        rows = np.arange(2 * j, 2 * j + 2)
        table = np.genfromtxt(tmp_path / f"d-level{j + 1}.csv", delimiter=",", skip_header=2)[:, 1:]
        header = (tmp_path / f"d-level{j + 1}.csv").read_text().splitlines()[0].split(",")[1:]
        for storey in range(drift.shape[1]):  # pelicun: storey j lies below floor j + 1 (ground: 1)
            np.testing.assert_allclose(table[:, header.index(f"1-PID-{storey + 2}-1")], drift[rows, storey],
                                       rtol=1e-9)
        np.testing.assert_allclose(table[:, header.index("1-BRD-1-1")], disp[rows] / 0.0254, rtol=1e-9)
        assert payload["levels"][j]["uplift"]["uplifted_motions"] == rows[uplift[rows] > 0].tolist()
    assert payload["levels"][1]["uplift"]["n_uplifted"] > 0
    assert "horizontal" in payload["vertical"]["pelicun_demands"]
