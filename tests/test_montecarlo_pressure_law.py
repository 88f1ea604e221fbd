"""A Monte Carlo whose vertical components take some runs' contact pressure beyond where
Table 1's extended end segments give Eq. 1 constants: those runs are flagged
(`beyond_pressure_law`) and kept out of the statistics, and the others go on, where a single run
(`run`, `peak_response`) stops with an error.

Peer: each motion's own run, whose law stops it at the first step beyond the table; the runs
that stay inside keep their peaks."""

import json

import jax
import numpy as np
import pytest

from teflon_jax.bearing import paper_bearing
from teflon_jax.cli._main import main
from teflon_jax.excitation import (
    StochasticGroundMotion,
    VerticalGroundMotion,
    uniform_signal,
)
from teflon_jax.studies import (
    MonteCarloResult,
    bidirectional_isolated_structure,
    monte_carlo,
    monte_carlo_distributed,
    monte_carlo_motion,
)
from teflon_jax.systems import (
    flag_pressure_law,
    isolated_structure,
    peak_response,
    with_vertical_component,
)
from teflon_jax.tables import interface_parameters
from teflon_jax.units import PSI, STANDARD_GRAVITY

DT, DURATION, COUNT = 0.01, 6.0, 8
MODEL = VerticalGroundMotion(
    StochasticGroundMotion(peak_ground_acceleration=2.0 * STANDARD_GRAVITY, duration=DURATION, time_step=DT,
                           rise_time=0.5, strong_motion_duration=3.0),
    vertical_ratio=2.0)
BEYOND = "beyond where Table 1's extended end segments give Eq. 1 constants"


def test_runs_beyond_the_table_are_flagged_and_the_others_go_on(tmp_path):
    """UF PTFE at 2500 psi under vertical components of 4 g nominal peak: the runs the Monte Carlo
    flags are exactly those whose own run stops at Table 1's law; the others' peaks equal their
    own runs' (to 1e-12: the batched program rounds apart); the flagged runs are left out of the statistics and of `converged`,
    and the flags survive the results file."""
    structure = with_vertical_component(isolated_structure("rigid", pressure=2500 * PSI, time_step=0.005))
    key = jax.random.key(7)
    result = monte_carlo(structure, MODEL, COUNT, key=key, chunk_size=4)
    beyond = np.asarray(result.beyond_pressure_law)
    assert 0 < beyond.sum() < COUNT  # some runs inside, some beyond: both kinds are checked
    for index in range(COUNT):
        horizontal, vertical = (uniform_signal(row, DT) for row in np.asarray(monte_carlo_motion(MODEL, key, index)))
        system = structure((horizontal, vertical))
        if beyond[index]:
            with pytest.raises(Exception, match=BEYOND):
                jax.block_until_ready(peak_response(system, DURATION))
        else:
            run = peak_response(system, DURATION)
            assert bool(run.converged)
            np.testing.assert_allclose(result.base_disp[index], run.base_disp, rtol=1e-12)
    assert np.array_equal(result.converged, ~beyond)
    assert result.percentiles()["base_disp_m"]["n"] == COUNT - beyond.sum()
    result.save(tmp_path / "mc.nc")
    np.testing.assert_array_equal(MonteCarloResult.open(tmp_path / "mc.nc").beyond_pressure_law, beyond)


@pytest.mark.parametrize("components", [1, 2])
def test_the_law_is_checked_at_the_records_first_sample(components):
    """A vertical record that starts at s = N / W = 6 (UF PTFE at 2500 psi: beyond Table 1's
    extension) and is 0 after: the first step reads the law there, so a single run stops and
    a flagged run (`flag_pressure_law`) is reported beyond the law; starting at s = 4 (inside)
    both run, the flagged one within the law. In one and in two horizontal components."""
    build = isolated_structure if components == 1 else bidirectional_isolated_structure
    structure = with_vertical_component(build("rigid", pressure=2500 * PSI, time_step=0.005))
    time = np.arange(0.0, 2.0, 0.01)
    horizontal = uniform_signal(0.3 * STANDARD_GRAVITY * np.sin(2 * np.pi * time), 0.01)
    if components == 2:
        horizontal = (horizontal, uniform_signal(0.15 * STANDARD_GRAVITY * np.sin(2 * np.pi * time), 0.01))
    for start, inside in ((4.0, True), (6.0, False)):
        vertical = np.zeros_like(time)
        vertical[0] = (start - 1.0) * STANDARD_GRAVITY
        system = structure((horizontal, uniform_signal(vertical, 0.01)))
        assert bool(system.pressure_table.valid_at(system.bearing, start)) == inside
        assert bool(peak_response(flag_pressure_law(system), 1.9)["within_pressure_law"]) == inside
        if inside:
            assert bool(peak_response(system, 1.9).converged)
        else:
            with pytest.raises(Exception, match=BEYOND):
                jax.block_until_ready(peak_response(system, 1.9))


def test_the_law_is_read_only_as_far_as_the_run_reached():
    """Two components, UF PTFE at 2500 psi, a vertical record at s = 6 (beyond Table 1's
    extension) at t = 1.5 s alone: a run that balances every step up to there reads the law
    there and is reported beyond it; the same run with one Newton iteration per step has a
    step that does not balance before t = 1.4 s, and the loads after that step, never read
    (a single run stops there), do not put it beyond the law."""
    time = np.arange(0.0, 2.0, 0.01)
    horizontal = (uniform_signal(0.5 * STANDARD_GRAVITY * np.sin(2 * np.pi * time), 0.01),
                  uniform_signal(0.3 * STANDARD_GRAVITY * np.cos(2 * np.pi * time), 0.01))
    vertical = np.zeros_like(time)
    vertical[150] = 5.0 * STANDARD_GRAVITY
    outcomes = []
    for iterations in ({}, {"newton_iterations": 1}):
        structure = with_vertical_component(bidirectional_isolated_structure("rigid", pressure=2500 * PSI,
                                                                             time_step=0.005, **iterations))
        system = flag_pressure_law(structure((horizontal, uniform_signal(vertical, 0.01))))
        outcomes.append((bool(peak_response(system, 1.4).converged),
                         bool(peak_response(system, 1.9)["within_pressure_law"])))
    assert outcomes == [(True, False), (False, True)]


def test_without_a_pressure_law_nothing_is_flagged():
    """A given bearing whose friction does not follow Table 1 at the momentary pressure (its
    constants at 2500 psi, no pressure dependence) carries no `beyond_pressure_law`, under the
    same motions."""
    bearing = paper_bearing(interface_parameters("UF", 2500 * PSI)[0])
    structure = with_vertical_component(isolated_structure("rigid", bearing=bearing, time_step=0.005))
    result = monte_carlo(structure, MODEL, 2, key=jax.random.key(7))
    assert result.beyond_pressure_law is None and result.converged.all()


def test_the_command_names_the_runs_beyond_the_table_and_exits_one(tmp_path, capsys):
    """`montecarlo` under such motions (one level, then two): the runs beyond the table are named
    on stderr and in the JSON, the statistics rest on the others, the exit status is 1, and no
    run is blamed on the Newton solve."""
    common = ["montecarlo", "--motions", "8", "--duration", "6s", "--strong-motion", "3s", "--vertical-ratio", "2",
              "--pressure", "2500psi", "--seed", "7", "--no-progress"]
    code = main([*common, "--pga", "1.8g", "--json", str(tmp_path / "one.json"), "--out", str(tmp_path / "one.nc")])
    err = capsys.readouterr().err
    payload = json.loads((tmp_path / "one.json").read_text())
    beyond = np.flatnonzero(MonteCarloResult.open(tmp_path / "one.nc").beyond_pressure_law)
    assert code == 1 and 0 < beyond.size < 8
    assert payload["beyond_pressure_law"] == beyond.tolist() == payload["not_converged"]
    assert payload["statistics"]["base_disp_in"]["n"] == 8 - beyond.size
    assert (f"{beyond.size} of 8 runs (motion indices {', '.join(map(str, beyond))}) took the bearings' contact "
            "pressure beyond where Table 1's extended end segments give Eq. 1 constants") in err
    assert "Newton solve did not converge" not in err
    code = main([*common, "--pga", "1g,1.8g", "--json", str(tmp_path / "levels.json")])
    err = capsys.readouterr().err
    levels = json.loads((tmp_path / "levels.json").read_text())
    flagged = levels["beyond_pressure_law"]  # motions 8..15 are the second level's (none beyond at 1 g)
    assert code == 1 and flagged and min(flagged) >= 8 and flagged == levels["not_converged"]
    assert "took the bearings' contact pressure beyond" in err and "Newton solve did not converge" not in err


@pytest.mark.slow
def test_a_cluster_flags_the_same_runs(dask_cluster, tmp_path):
    """On a Dask cluster the flags and the converged runs' peaks are those of this process."""
    structure = with_vertical_component(isolated_structure("rigid", pressure=2500 * PSI, time_step=0.005))
    here = monte_carlo(structure, MODEL, COUNT, key=jax.random.key(7), chunk_size=4)
    there = monte_carlo_distributed(structure, MODEL, COUNT, seed=7, out=tmp_path / "mc.nc",
                                    scheduler=dask_cluster.scheduler_address, chunk_size=4)
    np.testing.assert_array_equal(there.beyond_pressure_law, here.beyond_pressure_law)
    np.testing.assert_array_equal(there.converged, here.converged)
    np.testing.assert_array_equal(there.base_disp[here.converged], here.base_disp[here.converged])
