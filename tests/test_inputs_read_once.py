"""Each file a command's flags name is read once: `montecarlo` and `run` parse a `--bearing` file
(its bearing, posterior draws and unidentified constants) or an `--isolator-file` (its pendulum
and posterior draws) in one read, and take the draws, the bounds of `--property-factors` and what
the results say of the file from that read; `run --suite` reads each record once, also one that
several pairs name."""

import json
import pathlib

import jax
import numpy as np
import pytest
from test_double_fit import TRUE

import teflon_jax as tj
from teflon_jax.cli import main
from teflon_jax.formats import (
    BearingPosterior,
    IsolatorPosterior,
    save_bearing,
    write_isolator,
)
from teflon_jax.units import PSI

MONTE_CARLO = ["--no-compile-cache", "montecarlo", "--motions", "2", "--duration", "4s", "--strong-motion", "1.5s",
               "--no-progress"]


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """A bearing file with 8 posterior draws, a double pendulum's isolator file with 4, a suite
    of two pairs of short records (each record in both pairs) and that suite with one vertical
    component under both pairs."""
    jax.config.update("jax_enable_x64", True)
    folder = tmp_path_factory.mktemp("inputs")
    friction, b = tj.interface_parameters("UF", 1000 * PSI, "P")
    rng = np.random.default_rng(0)
    f_max = float(friction.f_max) * (1 + 0.1 * rng.standard_normal(8))
    draws = {"f_max": f_max, "delta_f": f_max * float(friction.delta_f / friction.f_max),
             "rate_a": float(friction.rate_a) * (1 + 0.1 * rng.standard_normal(8))}
    posterior = BearingPosterior(names=tuple(draws), draws=draws, effective_sample_size=dict.fromkeys(draws, 400.0),
                                 draws_before_thinning=32, thinning=4, chains=4, seed=0)
    save_bearing(folder / "bearing.json", tj.paper_bearing(friction, breakaway_ratio=b), posterior=posterior,
                 standard_errors={("friction", "rate_a"): np.inf})
    surface = {"bottom_f_max": [0.05, 0.051, 0.049, 0.052]}
    write_isolator(folder / "isolator.json", TRUE, posterior=IsolatorPosterior(
        names=tuple(surface), draws=surface, effective_sample_size={"bottom_f_max": 400.0}, draws_before_thinning=4,
        thinning=1, chains=2, seed=0))
    t = 0.01 * np.arange(301)
    acceleration = 0.3 * np.sin(2 * np.pi * t) * np.sin(np.pi * t / t[-1]) ** 2
    for i in range(2):
        (folder / f"x{i}.txt").write_text("time acc\n" + "\n".join(
            f"{ti:.4f} {(1 + 0.2 * i) * ai:.6e}" for ti, ai in zip(t, acceleration)) + "\n")
    (folder / "z.txt").write_text("time acc\n" + "\n".join(
        f"{ti:.4f} {0.3 * ai:.6e}" for ti, ai in zip(t, np.roll(acceleration, 50))) + "\n")
    (folder / "suite.csv").write_text("name,record_x,record_y,scale\np0,x0.txt,x1.txt,1\np1,x1.txt,x0.txt,1\n")
    (folder / "suite-z.csv").write_text("name,record_x,record_y,record_z,scale\n"
                                        "p0,x0.txt,x1.txt,z.txt,1\np1,x1.txt,x0.txt,z.txt,1\n")
    return folder


def _reads(monkeypatch, folder) -> dict:
    """{file name: times its text was read} of the files in `folder`: `pathlib.Path.read_text`
    counted, the real one reading each."""
    reads, read_text = {}, pathlib.Path.read_text

    def counted(self, *args, **kwargs):
        if self.resolve().parent == folder.resolve():
            reads[self.name] = reads.get(self.name, 0) + 1
        return read_text(self, *args, **kwargs)

    monkeypatch.setattr(pathlib.Path, "read_text", counted)
    return reads


@pytest.mark.parametrize("flags, named", [
    ([*MONTE_CARLO, "--bearing", "{folder}/bearing.json"], "bearing.json"),
    ([*MONTE_CARLO, "--bearing", "{folder}/bearing.json", "--bearing-draws", "2"], "bearing.json"),
    ([*MONTE_CARLO, "--bearing", "{folder}/bearing.json", "--property-factors", "posterior"], "bearing.json"),
    ([*MONTE_CARLO, "--bearing", "{folder}/bearing.json", "--property-factors", "0.8,1.2"], "bearing.json"),
    ([*MONTE_CARLO, "--isolator", "double-fp", "--isolator-file", "{folder}/isolator.json"], "isolator.json"),
    (["--no-compile-cache", "run", "--record-units", "g", "--suite", "{folder}/suite.csv", "--bearing",
      "{folder}/bearing.json", "--property-factors", "posterior"], "bearing.json"),
    (["--no-compile-cache", "run", "--record-units", "g", "--record-x", "{folder}/x0.txt", "--bearing",
      "{folder}/bearing.json"], "bearing.json"),
], ids=["montecarlo-draws", "montecarlo-nested", "bounding-posterior", "bounding-factors", "montecarlo-isolator-file",
        "suite-bounding", "run"])
def test_each_named_file_is_parsed_once(files, tmp_path, capsys, monkeypatch, flags, named):
    """The command runs (its JSON written, the bearing file's draws or bounds taken, its
    unidentified rate_a warned of once) on one read of the file it names."""
    argv = [f.format(folder=files) for f in flags] + ["--json", str(tmp_path / "out.json")]
    reads = _reads(monkeypatch, files)
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 0, err
    assert reads[named] == 1, reads
    assert err.count("friction.rate_a = ") == (named == "bearing.json"), err
    inputs = json.loads((tmp_path / "out.json").read_text())["inputs"]
    assert any(entry["path"].endswith(named) for entry in inputs["files"])
    if named == "bearing.json":  # a bearing without heating or pressure dependence replaces --pressure
        assert inputs["replaced"].get("--pressure", "").startswith("--bearing")


@pytest.mark.parametrize("suite, extra", [("suite-z.csv", []), ("suite.csv", ["--property-factors", "0.85,1.3"])],
                         ids=["vertical", "bounding"])
def test_each_suite_record_is_read_once(files, tmp_path, capsys, monkeypatch, suite, extra):
    """`run --suite` reads each record file once (the column reader counted, the real one reading
    it), though each is named by both pairs, and runs both pairs on what it read: the pairs'
    peaks differ as their records do (p1 is p0 with x and y swapped, the resultant the same)."""
    from teflon_jax import formats

    reads, read_two_column = {}, formats.read_two_column

    def counted(path, *args, **kwargs):
        reads[pathlib.Path(path).name] = reads.get(pathlib.Path(path).name, 0) + 1
        return read_two_column(path, *args, **kwargs)

    monkeypatch.setattr(formats, "read_two_column", counted)
    out = tmp_path / "out.json"
    code = main(["--no-compile-cache", "run", "--record-units", "g", "--suite", str(files / suite), *extra,
                 "--json", str(out)])
    assert code == 0, capsys.readouterr().err
    named = {"x0.txt", "x1.txt"} | ({"z.txt"} if suite == "suite-z.csv" else set())
    assert reads == dict.fromkeys(named, 1), reads
    payload = json.loads(out.read_text())
    pairs = payload["pairs"] if not extra else payload["cases"]["nominal"]["pairs"]
    p0, p1 = pairs["p0"], pairs["p1"]
    assert p0["base_disp_x_m"] == pytest.approx(p1["base_disp_y_m"], rel=1e-6)
    assert p0["base_disp_x_m"] != pytest.approx(p0["base_disp_y_m"], rel=1e-3)
