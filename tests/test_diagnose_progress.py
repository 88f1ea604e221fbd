"""`teflon-jax diagnose` says what it will do and roughly how long before the search, a line as
each batched fit returns (each candidate's residual and evidence), and the times it took, on
stderr; stdout stays as it was (empty).

The fast case stands the batched Levenberg-Marquardt call in for a stub that returns its starts
(no compile of the solver): the lines and their order are the command's, whatever the fits
find. The slow case runs the real search on a short record."""

import json
import re

import numpy as np
import pytest
from test_discovery import generate_record

from identification.discovery import _progress, _rounds
from teflon_jax.cli import main
from teflon_jax.formats import write_test_record

CANDIDATES = ("breakaway", "wear")


def _stub_fit_batch(starts, free, actives, weights, data, scale, *, max_steps=200):
    """`fit_batch` without the solver: each member stays at its start, with a Jacobian of full
    rank so that the standard errors exist."""
    starts = np.asarray(starts, float)
    b, p = starts.shape
    n = np.size(data.stack(np.asarray(data.force), np.asarray(data.force_y)))
    jacobian = np.random.default_rng(0).standard_normal((b, n, p))
    return starts, np.zeros(b), jacobian, np.ones(b, bool), np.ones(b, int)


def _record(tmp_path):
    path = tmp_path / "record.csv"
    write_test_record(path, generate_record(cycles=2, samples_per_cycle=40, noise=0.01, seed=4))
    return path


def _diagnose(tmp_path, capsys, *flags):
    out = tmp_path / "d.json"
    code = main(["diagnose", str(_record(tmp_path)), "--json", str(out), "--report",
                 str(tmp_path / "report"), "--candidates", ",".join(CANDIDATES), "--max-effects",
                 "1", "--max-samples", "40", *flags])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    return captured, json.loads(out.read_text())


def _in_order(lines, patterns):
    """The index of the first line matching each pattern, in turn; fails naming the one missing."""
    at, found = 0, []
    for pattern in patterns:
        hit = next((i for i in range(at, len(lines)) if re.search(pattern, lines[i])), None)
        assert hit is not None, f"no line /{pattern}/ after line {at} of\n" + "\n".join(lines)
        found.append(hit)
        at = hit + 1
    return found


def _check_lines(err, document):
    lines = err.splitlines()
    plan = (r"^plan: \d+ samples; baseline paper1990, then up to 1 round over 2 candidates "
            r"\(breakaway, wear\), .*; at most 2 batched calls of 9 fits: (about [\d.]+ (s|min)"
            r"|under a second) on two CPU cores")
    found = _in_order(lines, [
        r"^teflon-jax diagnose .*record\.csv: loading JAX",
        plan,
        r"^not tried: .*pressure_dependence.*\(the report says why\)$",
        r"^baseline paper1990: fitting from 9 starts",
        r"^baseline paper1990: nrmse \d\.\d{4}$",
        r"^baseline paper1990 took [\d.]+ s; at most 1 more call: ",
        r"^round 1: trying breakaway, wear, each added to paper1990\.\.\.$",
        r"^  (breakaway|wear): nrmse \d\.\d{4} -> \d\.\d{4}, delta_bic -?[\d.]+, held-out gain",
        r"^  (breakaway|wear): nrmse",
        r"^round 1: delta_bic breakaway -?[\d.]+, wear -?[\d.]+$",
        r"^round 1 took [\d.]+ s$",
        r"^search done in [\d.]+ s$",
        r"^writing .*d\.json, .*report\.md and its figures\.\.\.$",
        r"; search [\d.]+ s, total [\d.]+ s\. Wrote .*d\.json and .*report\.md\.$",
    ])
    assert found[-1] == len(lines) - 1, "the result's line is the last"
    assert {lines[found[7]].split(":")[0].strip(), lines[found[8]].split(":")[0].strip()} == set(CANDIDATES)
    # the plan's work is the work done: 2 calls of 9 fits (the model and 2 candidates, 3 fits each)
    assert document["fit_convergence"]["fits"] == 2 * 9


def test_the_plan_each_round_and_the_times_are_said_on_stderr_before_the_result(
        tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(_rounds, "fit_batch", _stub_fit_batch)
    captured, document = _diagnose(tmp_path, capsys)
    assert captured.out == ""
    _check_lines(captured.err, document)
    quiet, _ = _diagnose(tmp_path, capsys, "--quiet")
    assert quiet.out == "" and quiet.err == ""


def test_the_estimate_grows_with_the_work_and_leaves_out_a_compile_already_done(monkeypatch):
    said = []
    monkeypatch.setattr(_progress, "_COMPILED", set())
    seconds = {}
    for members, samples in ((9, 100), (18, 100), (18, 1000)):
        said.clear()
        progress = _progress.Progress(said.append, _progress.Cost(40.0, 1e-3), ("x", members, samples),
                                      members, samples, label="paper1990")
        progress.plan("work", 3, [])
        seconds[members, samples] = re.search(r"about ([\d.]+) (s|min)", said[0]).groups()
        assert "compiling the fit once" in said[0]
    assert seconds[9, 100] == ("40", "s")  # 40 + 3 x 9 x 100 x 1e-3 = 42.7 s, to 10 s
    assert seconds[18, 100] == ("50", "s")  # 45.4 s
    assert seconds[18, 1000] == ("1.6", "min")  # 94 s
    progress.called()
    said.clear()
    again = _progress.Progress(said.append, _progress.Cost(40.0, 1e-3), ("x", 18, 1000), 18, 1000,
                               label="paper1990")
    again.plan("work", 3, [])
    assert "compiling" not in said[0] and "about 50 s" in said[0]  # 3 x 18 x 1000 x 1e-3 = 54 s


@pytest.mark.slow  # the batched fit's compile: ~30 s on two idle cores, a minute on busy ones
def test_the_real_search_says_the_same_lines(tmp_path, capsys):
    captured, document = _diagnose(tmp_path, capsys)
    assert captured.out == ""
    _check_lines(captured.err, document)
