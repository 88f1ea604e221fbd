"""What `fit` and `diagnose` save of what they found (`--save-isolator`, `--save-bearing`) is
checked before the first output is written: a series pendulum fitted from the record of one
whose inner and bottom surfaces have the same friction lands, by rounding, with the inner f_max
above the bottom's, which breaks the triple pendulum's order of regimes (inner <= bottom <=
top; Fenz & Constantinou 2008) that its isolator file must keep. The command then refuses the
file by its flag and leaves no JSON, report, plot or isolator file behind (exit status 2, as
for a refused input)."""

import dataclasses
import json

import pytest
from test_triple_fit import TRUE, _friction, _record

from teflon_jax.cli import main
from teflon_jax.formats import isolator_to_dict, write_test_record

EQUAL_INNER = dataclasses.replace(TRUE, inner_friction=_friction(0.06, 0.03, 20.0))
"""The inner surfaces with the bottom's friction: the order holds with equality only."""


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("order")
    start = folder / "start.json"
    start.write_text(json.dumps(isolator_to_dict(TRUE)))
    record = folder / "record.csv"
    write_test_record(record, _record(EQUAL_INNER), units="SI")
    return start, record


def test_fit_refuses_an_isolator_out_of_order_before_writing_anything(files, tmp_path, capsys):
    start, record = files
    out = tmp_path / "out"
    code = main(["fit", "--isolator", "triple-fp", "--isolator-file", str(start), str(record),
                 "--json", str(out / "fit.json"), "--plot", str(out / "fit.png"),
                 "--save-isolator", str(out / "fitted.json")])
    error = capsys.readouterr().err
    assert not out.exists(), sorted(p.name for p in out.iterdir())  # nor the folder made for them
    assert code == 2, error
    assert "--save-isolator" in error and "inner <= bottom <= top" in error and "Nothing was written" in error


def test_without_the_isolator_file_the_same_fit_writes_its_json(files, tmp_path, capsys):
    """The refusal is the file's: the fit itself converges, and says the order is broken."""
    start, record = files
    code = main(["fit", "--isolator", "triple-fp", "--isolator-file", str(start), str(record),
                 "--json", str(tmp_path / "fit.json")])
    assert code == 0
    warnings = json.loads((tmp_path / "fit.json").read_text())["warnings"]
    assert any("break the series model's order" in w for w in warnings), warnings


def test_diagnose_refuses_an_isolator_out_of_order_before_writing_anything(files, tmp_path, capsys):
    """The same with `diagnose --isolator triple-fp`, whose baseline is that series fit: before
    the refusal was checked first, the JSON and the report were written and then the isolator
    file failed."""
    start, record = files
    out = tmp_path / "out"
    code = main(["diagnose", "--isolator", "triple-fp", "--isolator-file", str(start), str(record),
                 "--json", str(out / "d.json"), "--report", str(out / "report"), "--quiet",
                 "--max-effects", "0", "--save-isolator", str(out / "fitted.json")])
    error = capsys.readouterr().err
    assert not out.exists(), sorted(p.name for p in out.rglob("*"))
    assert code == 2, error
    assert "--save-isolator" in error and "inner <= bottom <= top" in error


def test_fit_refuses_a_bearing_the_file_cannot_hold_before_writing_anything(tmp_path, capsys):
    """A flat slider's fit with delta_f held above what the record's friction reaches: f_max
    stops at its bound, delta_f, and a bearing file cannot hold delta_f = f_max (Eq. 1 at rest,
    f_max - delta_f, must be positive). `fit --save-bearing` refuses the file by its flag before
    the JSON, the plot or the bearing file is written; before the file was built and read back
    first, the JSON was written and then a bearing file that `--bearing` refuses."""
    from types import SimpleNamespace

    from test_fit import _synthetic

    from teflon_jax.units import INCH

    record = tmp_path / "record.csv"
    row = SimpleNamespace(f_max=0.10, delta_f=0.05, rate_a=0.6 / INCH, breakaway_ratio=None)
    write_test_record(record, _synthetic(row, 0, noise=0.0), units="SI")
    out = tmp_path / "out"
    out.mkdir()
    code = main(["fit", str(record), "--free", "f_max,rate_a,yield_disp", "--fixed", "delta_f=0.12",
                 "--json", str(out / "fit.json"), "--plot", str(out / "fit.png"),
                 "--save-bearing", str(out / "bearing.json")])
    error = capsys.readouterr().err
    assert code == 2, error
    assert sorted(out.iterdir()) == []
    assert "--save-bearing" in error and "delta_f: must be smaller than f_max" in error
    assert "Nothing was written" in error
