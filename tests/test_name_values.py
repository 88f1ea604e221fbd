"""The one reader of the NAME=VALUE flags `--fixed` (fit) and `--known` (diagnose, and fit
--effects through --fixed): items split at commas, in one flag or repeated, each value a
quantity with the unit of its parameter, converted to SI; a malformed item or an unknown name
refused naming the flag as the command calls it."""

import pytest

from teflon_jax.cli import main
from teflon_jax.cli._common import name_value_items, parse_name_values
from teflon_jax.units import INCH

DIMENSIONS = {"f_max": "dimensionless", "yield_disp": "length", "rate_a": "slowness"}


def test_items_of_one_flag_and_of_the_repeated_flag_are_the_same():
    assert name_value_items("yield_disp=0.005in,rate_a=0.6s/in") == ["yield_disp=0.005in", "rate_a=0.6s/in"]
    assert name_value_items(["yield_disp=0.005in", "rate_a=0.6s/in,"]) == ["yield_disp=0.005in", "rate_a=0.6s/in"]
    assert name_value_items(None) == [] and name_value_items([]) == []


def test_values_in_si():
    """0.005 in = 0.005 x 0.0254 m; 0.6 s/in = 0.6 / 0.0254 s/m; a ratio as written."""
    values = parse_name_values(["yield_disp=0.005in,rate_a=0.6s/in", " f_max = 0.1"], DIMENSIONS, "--known")
    assert values == pytest.approx({"yield_disp": 0.005 * INCH, "rate_a": 0.6 / INCH, "f_max": 0.1}, rel=1e-15)


@pytest.mark.parametrize("flag", ["--fixed", "--known"])
@pytest.mark.parametrize("text, message", [
    ("yield_disp", "{flag}: expected NAME=VALUE (e.g. rate_a=0.6s/in), got 'yield_disp'."),
    ("yeld_disp=0.005in", "{flag}: unknown parameter 'yeld_disp'; the parameters are f_max, yield_disp, rate_a."),
    ("yield_disp=0.005", "{flag} yield_disp: '0.005' has no unit"),
    ("rate_a=0.6in", "{flag} rate_a: 'in' is a unit of length"),
])
def test_a_bad_item_is_refused_naming_the_flag(flag, text, message):
    with pytest.raises(ValueError) as error:
        parse_name_values(text, DIMENSIONS, flag)
    assert message.format(flag=flag) in str(error.value)


def test_fit_effects_reads_the_repeated_fixed_flag(tmp_path, capsys):
    """`fit --effects` takes --fixed as fit does (a list of the repeated flag's texts) and
    refuses an unknown constant, naming --fixed, before any fit."""
    record = tmp_path / "r.csv"
    assert main(["simulate-test", "--out", str(record), "--cycles", "1"]) == 0
    capsys.readouterr()
    code = main(["fit", str(record), "--effects", "backlash", "--json", str(tmp_path / "f.json"),
                 "--fixed", "yield_disp=0.005in", "--fixed", "gap=1in"])
    assert code == 2
    assert "--fixed: unknown parameter 'gap'; the parameters are f_max, yield_disp" in capsys.readouterr().err
    assert not (tmp_path / "f.json").exists()
