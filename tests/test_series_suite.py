"""Record suites on triple and double friction pendulums: `run --suite --isolator triple-fp|double-fp
--isolator-file FILE` runs every pair through the series model under two components, with the
bounding cases of `--property-factors` scaling every surface's friction.

Peers: the rigid mass's equilibrium (its total horizontal force is the isolator's force, so the
base shear read from the accelerations equals the largest bearing force over W), the single
`run` of each pair, and an isolator file whose friction was scaled by hand; the physical order
of the bounding cases (more friction, less displacement).
"""

import json
import pathlib

import jax.numpy as jnp
import numpy as np
import pytest
from histories import planar_histories

from teflon_jax.cli import main
from teflon_jax.excitation import uniform_signal
from teflon_jax.formats import load_isolator
from teflon_jax.studies import bidirectional_isolated_structure, suite_peaks
from teflon_jax.units import STANDARD_GRAVITY

BENCHMARKS = pathlib.Path(__file__).resolve().parents[1] / "benchmarks"
DT = 0.01


def _motions(count=2, seconds=6.0, seed=5, scale=1.0):
    t = DT * np.arange(int(seconds / DT) + 1)
    rng = np.random.default_rng(seed)
    envelope = np.sin(np.pi * t / t[-1]) ** 2
    return [(0.35 * scale * STANDARD_GRAVITY * envelope * np.sin(2 * np.pi * 0.6 * t + rng.uniform(0, 6)),
             0.25 * scale * STANDARD_GRAVITY * envelope * rng.normal(size=t.size)) for _ in range(count)]


def _write_pairs(folder, motions):
    rows = []
    for i, pair in enumerate(motions):
        for axis, a in zip("xy", pair):
            t = DT * np.arange(a.size)
            (folder / f"{axis}{i}.txt").write_text(
                "time acc\n" + "\n".join(f"{ti:.4f} {ai / STANDARD_GRAVITY:.9e}" for ti, ai in zip(t, a)) + "\n")
        rows.append(f"p{i},x{i}.txt,y{i}.txt,1\n")
    (folder / "suite.csv").write_text("name,record_x,record_y,scale\n" + "".join(rows))
    return folder / "suite.csv"


@pytest.mark.slow
def test_triple_suite_base_shear_is_the_isolator_force_over_the_weight():
    """Rigid mass on triple pendulums: m a_total = -F_isolator, so the suite's base shear (from
    the accelerations) is max |F| / W of each pair's own histories, and its displacements are
    the histories' peaks."""
    structure = bidirectional_isolated_structure("rigid", isolator=load_isolator(BENCHMARKS / "triple_isolator.json"),
                                                 time_step=0.005)
    motions = _motions()
    ax, ay = (np.stack([m[k] for m in motions]) for k in (0, 1))
    duration = (ax.shape[1] - 1) * DT

    def build(gx, gy):
        return structure((gx, gy))

    result = suite_peaks(build, ["a", "b"], ax, ay, DT, duration)
    assert result.converged.all()
    for i, (x, y) in enumerate(motions):
        system = structure((uniform_signal(jnp.asarray(x), DT), uniform_signal(jnp.asarray(y), DT)))
        _, state, force, _, _, ok = (np.asarray(a) for a in planar_histories(system, duration))
        weight = float(np.sum(system.mass)) * STANDARD_GRAVITY
        assert ok.all()
        np.testing.assert_allclose(result.peaks["base_shear_ratio_resultant"][i],
                                   np.hypot(force[:, 0], force[:, 1]).max() / weight, rtol=1e-9)
        np.testing.assert_allclose(result.peaks["base_disp_resultant_m"][i],
                                   np.hypot(state[:, 0, 0], state[:, 1, 0]).max(), rtol=1e-12)
        np.testing.assert_allclose(result.peaks["base_disp_y_m"][i], np.abs(state[:, 1, 0]).max(), rtol=1e-12)
    assert result.peaks["base_disp_resultant_m"].min() > 0.02  # the pendulums slid


@pytest.mark.slow
def test_double_suite_matches_the_run_of_each_pair(tmp_path, capsys):
    suite = _write_pairs(tmp_path, _motions(seconds=5.0, seed=9))
    isolator = ["--isolator", "double-fp", "--isolator-file", str(BENCHMARKS / "double_isolator.json")]
    assert main(["run", "--suite", str(suite), "--record-units", "g", *isolator,
                 "--json", str(tmp_path / "s.json")]) == 0
    rows = (tmp_path / "s.csv").read_text().splitlines()
    header = rows[0].split(",")
    for i in range(2):
        assert main(["run", "--record-x", str(tmp_path / f"x{i}.txt"), "--record-y", str(tmp_path / f"y{i}.txt"),
                     "--record-units", "g", *isolator, "--json", str(tmp_path / f"r{i}.json")]) == 0
        peak = json.loads((tmp_path / f"r{i}.json").read_text())["peak"]
        row = dict(zip(header, next(r for r in rows if r.startswith(f"p{i},")).split(",")))
        for key in ("base_disp_resultant_m", "base_disp_x_m", "base_disp_y_m", "base_shear_ratio_resultant"):
            assert float(row[key]) == pytest.approx(peak[key], rel=1e-5), key


@pytest.mark.slow  # four compilations of the triple pendulum's suite (about 60 s on two cores)
def test_triple_suite_bounding_scales_every_surface_friction(tmp_path, capsys):
    """The upper-bound case is the nominal suite of a file whose f_max and delta_f were
    multiplied by 1.25 on every surface; the lower bound slides farthest."""
    suite = _write_pairs(tmp_path, _motions(seconds=5.0, seed=3, scale=0.5))  # short of the restrainers
    document = json.loads((BENCHMARKS / "triple_isolator.json").read_text())
    for surface in document["surfaces"].values():
        for key in ("f_max", "delta_f"):
            surface["friction"][key]["value"] *= 1.25
    (tmp_path / "upper.json").write_text(json.dumps(document))
    common = ["run", "--suite", str(suite), "--record-units", "g", "--isolator", "triple-fp"]
    assert main([*common, "--isolator-file", str(BENCHMARKS / "triple_isolator.json"),
                 "--property-factors", "0.8,1.25", "--json", str(tmp_path / "b.json")]) == 0
    assert main([*common, "--isolator-file", str(tmp_path / "upper.json"), "--json", str(tmp_path / "u.json")]) == 0
    cases = json.loads((tmp_path / "b.json").read_text())["cases"]
    by_hand = json.loads((tmp_path / "u.json").read_text())
    key = "base_disp_resultant_m"
    assert cases["upper"]["summary"][key]["mean"] == pytest.approx(by_hand["summary"][key]["mean"], rel=1e-12)
    means = {case: cases[case]["summary"][key]["mean"] for case in cases}
    assert means["upper"] < means["nominal"] < means["lower"]
