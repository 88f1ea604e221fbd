"""`fit` and `simulate-test` read what differs between isolators from one table
(`teflon_jax.cli._isolator_table`): a row for every isolator of the registry, and every flag a
row refuses or needs is refused by name, with exit status 2, before any work."""

import pathlib

import pytest

from teflon_jax.bearing import ISOLATORS
from teflon_jax.cli._isolator_table import FIT_ROWS, TEST_ROWS
from teflon_jax.cli._main import main

EXAMPLES = pathlib.Path(__file__).parents[1] / "benchmarks"
START = {"triple-fp": EXAMPLES / "triple_isolator.json", "double-fp": EXAMPLES / "double_isolator.json"}
VALUES = {"isolator_file": None, "save_isolator": "fitted.json", "bayes": "posterior", "effects": "backlash",
          "fixed": "f_max=0.1", "starts": "3", "save_bearing": "bearing.json", "radius": "88in",
          "reference_load": "1000kN"}
"""A value of each flag a row names (an isolator file: the example of the row's isolator)."""


def _flags(isolator, names, tmp_path):
    flags = []
    for name in names:
        value = VALUES[name] or START.get(isolator, START["triple-fp"])
        value = tmp_path / value if name in ("save_isolator", "save_bearing", "bayes") else value
        flags += ["--" + name.replace("_", "-"), str(value)]
    return flags


def test_every_isolator_of_the_registry_has_one_row_of_each_command():
    assert tuple(FIT_ROWS) == ISOLATORS
    assert tuple(TEST_ROWS) == ISOLATORS


def _run(capsys, argv):
    code = main(argv)
    return code, capsys.readouterr().err


FIT_REFUSED = [(isolator, name) for isolator, row in FIT_ROWS.items() for name, _ in row.refuses]


@pytest.mark.parametrize("isolator, name", FIT_REFUSED)
def test_fit_refuses_by_name_each_flag_its_isolator_cannot_take(isolator, name, tmp_path, capsys):
    needed = [n for n, _ in FIT_ROWS[isolator].requires]
    argv = ["fit", str(tmp_path / "record.csv"), "--isolator", isolator, "--json", str(tmp_path / "f.json"),
            *_flags(isolator, needed + [name], tmp_path)]
    code, err = _run(capsys, argv)
    flag = "--" + name.replace("_", "-")
    assert code == 2 and f"teflon-jax fit: error: {flag}: " in err, err
    assert not (tmp_path / "f.json").exists()


@pytest.mark.parametrize("isolator", [i for i, row in FIT_ROWS.items() if row.requires])
def test_fit_needs_the_flags_its_isolator_starts_from(isolator, tmp_path, capsys):
    code, err = _run(capsys, ["fit", str(tmp_path / "record.csv"), "--isolator", isolator, "--json",
                              str(tmp_path / "f.json")])
    flag = "--" + FIT_ROWS[isolator].requires[0][0].replace("_", "-")
    assert code == 2 and f"teflon-jax fit: error: {flag}: --isolator {isolator} " in err, err


TEST_RULES = [(isolator, name, refused) for isolator, row in TEST_ROWS.items()
              for rules, refused in ((row.refuses, True), (row.requires, False)) for name, _ in rules]


@pytest.mark.parametrize("isolator, name, refused", TEST_RULES)
def test_simulate_refuses_a_flag_its_isolator_cannot_take_and_needs_its_own(isolator, name, refused,
                                                                             tmp_path, capsys):
    row = TEST_ROWS[isolator]
    given = [n for n, _ in row.requires if n != name] + [name] * refused
    out = tmp_path / "record.csv"
    code, err = _run(capsys, ["simulate-test", "--isolator", isolator, "--normal-load", "500kip", "--out",
                              str(out), *_flags(isolator, given, tmp_path)])
    flag = "--" + name.replace("_", "-")
    assert code == 2 and flag in err.splitlines()[-1], err
    assert ("needs" in err) != refused, err
    assert not out.exists()
