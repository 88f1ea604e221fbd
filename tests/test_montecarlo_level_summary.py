"""What `teflon-jax montecarlo` writes and prints with the level flags (`--storeys`, several
`--pga` levels): one level's peaks at the top of the summary and on the console as
a run without the flags has them, the same top-level keys (the devices and the run's speed
among them) but for those of the levels, and each level's motions as a range that reads as one."""

import contextlib
import io
import json
import re

import pytest

from teflon_jax.cli import main

COMMON = ["montecarlo", "--motions", "2", "--duration", "3s", "--strong-motion", "1s", "--no-progress"]
LEVEL_ONLY = {"motions_per_level", "levels", "fragility"}
"""The top-level keys a run with a level flag writes and a plain run does not: the levels'
entries and the limits' fragilities."""
SPEED = {"devices", "device_kind", "wall_s", "compile_s", "records_per_s", "records_per_s_after_first_chunk"}


@pytest.fixture(scope="module")
def plain_and_limit(tmp_path_factory):
    """{"plain": (JSON, printed), "limit": (JSON, printed)}: the same two motions without a
    level flag and with --limit base_disp=1in (one level)."""
    folder, runs = tmp_path_factory.mktemp("summaries"), {}
    for name, flags in (("plain", []), ("limit", ["--limit", "base_disp=1in"])):
        printed = io.StringIO()
        with contextlib.redirect_stdout(printed):
            assert main([*COMMON, *flags, "--json", str(folder / f"{name}.json")]) == 0
        runs[name] = json.loads((folder / f"{name}.json").read_text()), printed.getvalue()
    return runs


def _peak_lines(printed: str) -> list[str]:
    """The printed lines of the base peaks' statistics, without their indentation."""
    return [line.strip() for line in printed.splitlines() if re.match(r"\s*(base_disp_\w+|base_shear_ratio): ", line)]


def _printed_statistics(stats) -> list[str]:
    """The peak lines a Monte Carlo prints of `statistics` (inches)."""
    return [f"{name}: " + ", ".join(f"{k} {v:.4g}{' in' if name.startswith('base_disp') else ''}"
                                   for k, v in values.items() if k != "n") for name, values in stats.items()]


def test_one_level_keeps_the_plain_runs_statistics_and_prints_them(plain_and_limit):
    """One level with a level flag (--limit): the summary's top-level `statistics` are the
    plain run's (same motions, to rounding), the console prints the same peak lines, and the
    level's motions are {"first", "last", "count"}."""
    (plain, plain_out), (limit, limit_out) = plain_and_limit["plain"], plain_and_limit["limit"]
    assert limit["statistics"].keys() == plain["statistics"].keys()
    for name, values in plain["statistics"].items():
        assert limit["statistics"][name] == pytest.approx(values, rel=1e-9)
    assert limit["levels"][0]["statistics"] == limit["statistics"]
    assert limit["levels"][0]["motions"] == {"first": 0, "last": 1, "count": 2}
    assert len(_peak_lines(plain_out)) == 2 and _peak_lines(limit_out) == _peak_lines(plain_out)


def test_one_level_writes_the_plain_runs_keys_with_its_devices_and_speed(plain_and_limit):
    """One level with --limit: the summary's top-level keys are the plain run's and
    `LEVEL_ONLY`; the devices and the speed are there, `records_per_s` the runs over the time
    less compilation as in the plain run, and the first printed line names the devices as the
    plain run's does."""
    (plain, plain_out), (limit, limit_out) = plain_and_limit["plain"], plain_and_limit["limit"]
    assert set(plain) - set(limit) == set()
    assert set(limit) - set(plain) == LEVEL_ONLY
    assert SPEED <= set(plain)
    for payload in (plain, limit):
        assert payload["records_per_s"] == pytest.approx(
            payload["n_motions"] / (payload["wall_s"] - payload["compile_s"]), rel=1e-12)
        assert payload["records_per_s_after_first_chunk"] is None  # one chunk of 2 motions
    assert (limit["devices"], limit["device_kind"]) == (plain["devices"], plain["device_kind"])
    assert plain_out.startswith(f"2 motions on {plain['devices']} device(s) in ")
    assert limit_out.startswith(f"2 motions at 1 level(s) on {limit['devices']} device(s) in ")


def test_the_motions_pga_is_a_list_of_the_levels_in_every_run(plain_and_limit):
    """`motions.pga_g` has one shape in every run: the list of the --pga levels [g], one value
    with or without a level flag (`test_each_level_prints_its_peaks_and_names_its_motions`: two)."""
    (plain, _), (limit, _) = plain_and_limit["plain"], plain_and_limit["limit"]
    assert isinstance(plain["motions"]["pga_g"], list) and len(plain["motions"]["pga_g"]) == 1
    assert limit["motions"]["pga_g"] == plain["motions"]["pga_g"]
    assert plain["motions"]["pga_g"][0] == pytest.approx(limit["motions"]["pga_levels"]["values"][0], rel=1e-12)


def test_storeys_write_and_print_the_peaks_at_the_top(tmp_path, capsys):
    """The building with --storeys: `statistics` at the top of the summary (those of its one
    level), their peak lines printed as a plain run prints them, then the storeys' lines."""
    assert main([*COMMON, "--structure", "building", "--storeys", "--json", str(tmp_path / "s.json")]) == 0
    printed = capsys.readouterr().out
    payload = json.loads((tmp_path / "s.json").read_text())
    assert payload["statistics"] == payload["levels"][0]["statistics"]
    assert _peak_lines(printed) == _printed_statistics(payload["statistics"])
    drift = payload["levels"][0]["storeys"]["storey_drift_p50"]
    assert "storey drift ratio, storeys 1-6: p50 " + " ".join(f"{d:.3%}" for d in drift) + "; max " in printed
    assert "level acceleration [g], levels 0-6: p50 " in printed


def test_each_level_prints_its_peaks_and_names_its_motions(tmp_path, capsys):
    """Two --pga levels on the rigid mass: each level's motions are a range
    (level j: motions 2j to 2j + 1), its peak lines are printed under its heading with the
    values of its `statistics`, and no top-level `statistics` mixes the levels."""
    assert main([*COMMON, "--pga", "0.2g,0.4g", "--json", str(tmp_path / "l.json")]) == 0
    printed = capsys.readouterr().out
    payload = json.loads((tmp_path / "l.json").read_text())
    assert "statistics" not in payload
    assert payload["motions"]["pga_g"] == pytest.approx([0.2, 0.4], rel=1e-12)
    assert SPEED <= set(payload) and payload["records_per_s_after_first_chunk"] > 0  # a chunk per level
    assert payload["records_per_s"] == pytest.approx(4 / (payload["wall_s"] - payload["compile_s"]), rel=1e-12)
    for j, (entry, level) in enumerate(zip(payload["levels"], ("0.2g", "0.4g"))):
        assert entry["motions"] == {"first": 2 * j, "last": 2 * j + 1, "count": 2}
        assert f"  {level} (motions {2 * j} to {2 * j + 1}, 2 runs converged):" in printed
    assert _peak_lines(printed) == [line for entry in payload["levels"]
                                    for line in _printed_statistics(entry["statistics"])]
