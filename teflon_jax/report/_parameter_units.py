"""How fitted bearing parameters are shown: the paper's symbol and the unit of each, one table
for the command line and the plots."""

from ..units import INCH

PARAMETER_SYMBOLS = {
    "f_max": ("f_max", None),
    "delta_f": ("Df", None),
    "rate_a": ("a", "slowness"),
    "yield_disp": ("Y", "length"),
    "breakaway_ratio": ("b", None),
    "f_max_perpendicular": ("f_max (T)", None),
    "delta_f_perpendicular": ("Df (T)", None),
    "rate_a_perpendicular": ("a (T)", "slowness"),
}
"""Fitted parameter -> (symbol of Constantinou, Mokha & Reinhorn 1990, Eqs. 1, 3, 17, in words;
dimension: None for a ratio, "length" or "slowness")."""


def parameter_unit(name: str, length: tuple[str, float] = ("in", INCH)) -> tuple[str, float]:
    """(unit, SI value of one unit) in which parameter `name` is shown: the output `length`
    (name, SI factor) for Y, s/in for a with inch lengths and s/m otherwise (a is per metre in
    SI output, the paper's s/in in US output), ("", 1.0) for ratios and unknown names."""
    dimension = PARAMETER_SYMBOLS.get(name, (name, None))[1]
    if dimension == "length":
        return length
    if dimension == "slowness":
        return ("s/in", 1.0 / INCH) if length[0] == "in" else ("s/m", 1.0)
    return "", 1.0
