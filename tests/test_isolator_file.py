"""The isolator file of a triple friction pendulum and `simulate-test --isolator-file`: read in
any units, refused by key when incomplete or outside the series model, and simulated to the
closed-form backbone."""

import copy
import json

import numpy as np
import pytest

from teflon_jax.bearing import triple_pendulum_backbone
from teflon_jax.formats import isolator_from_dict, read_test_record
from teflon_jax.units import INCH


def _document():
    def surface(radius, capacity, mu):
        return {"radius": {"value": radius, "unit": "in"}, "capacity": {"value": capacity, "unit": "in"},
                "friction": {"f_max": {"value": mu, "unit": "1"}, "delta_f": {"value": 0.0, "unit": "1"},
                             "rate_a": {"value": 0.0, "unit": "s/in"}}}

    return {"format": "teflon-jax isolator", "format_version": 1, "isolator": "triple-fp",
            "surfaces": {"inner": surface(12.0, 2.0, 0.02), "bottom": surface(84.0, 12.0, 0.06),
                         "top": surface(84.0, 14.0, 0.10)},
            "yield_disp": {"value": 0.004, "unit": "in"}}


def test_the_file_reads_to_si():
    bearing = isolator_from_dict(_document())
    assert float(bearing.inner_radius) == pytest.approx(12 * INCH, rel=1e-15)
    assert float(bearing.top_capacity) == pytest.approx(14 * INCH, rel=1e-15)
    assert float(bearing.bottom_friction.f_max) == 0.06


def edited(document, path, value):
    """`document` with the entry at `path` (keys) set to `value`, or removed for None."""
    *keys, last = path
    target = document
    for key in keys:
        target = target[key]
    if value is None:
        del target[last]
    else:
        target[last] = value
    return document


def _edit(path, value):
    return edited(_document(), path, value)


@pytest.mark.parametrize("path, value, message", [
    (("surfaces", "inner", "radius"), 12.0, r"surfaces.inner.radius: write .* without a unit"),
    (("surfaces", "top", "capacity", "unit"), "kip", r"surfaces.top.capacity.unit"),
    (("surfaces", "bottom", "friction", "rate_a"), None, r"surfaces.bottom.friction: missing \['rate_a'\]"),
    (("surfaces", "middle"), {}, r"surfaces: unknown \['middle'\]"),
    (("surfaces", "inner", "radius", "value"), 100.0, "surfaces.bottom.radius: must be larger than surfaces.inner.radius"),
    (("surfaces", "inner", "friction", "f_max", "value"), 0.2, "inner <= bottom <= top"),
    (("surfaces", "top", "capacity", "value"), -1.0, "surfaces.top.capacity"),
    (("format_version",), 2, "format_version"),
    (("isolator",), "double-fp", "'isolator' must be"),
])
def test_a_bad_file_is_refused_by_key(path, value, message):
    with pytest.raises(ValueError, match=message):
        isolator_from_dict(_edit(path, value), where="tfp.json")


def test_a_key_given_twice_is_refused_with_its_line_and_object(tmp_path):
    from teflon_jax.formats import load_isolator

    path = tmp_path / "tfp.json"
    text = json.dumps(_document(), indent=1)
    path.write_text(text.replace('"capacity": {', '"radius": {"value": 20.0, "unit": "in"},\n"capacity": {', 1))
    line = text.splitlines().index(next(t for t in text.splitlines() if '"capacity"' in t)) + 1
    with pytest.raises(ValueError) as error:
        load_isolator(path)
    assert (f"{path}, line {line}, column 4: the key 'radius' appears a second time in 'surfaces.inner' "
            f"(first on line {line - 4}); JSON would keep only the last one") in str(error.value)


def _cli(tmp_path, capsys, *argv):
    from teflon_jax.cli import main

    code = main(["simulate-test", *map(str, argv)])
    return code, capsys.readouterr()


def test_simulate_test_writes_the_backbone(tmp_path, capsys):
    """A slow sine to 20 in on the file's bearing: the record's force at the peak displacement
    is the backbone's (regime IV at 20 in) within 1 %."""
    (tmp_path / "tfp.json").write_text(json.dumps(_document()))
    code, out = _cli(tmp_path, capsys, "--isolator-file", tmp_path / "tfp.json", "--normal-load",
                     "500kip", "--amplitude", "20in", "--frequency", "0.01Hz", "--cycles", "1",
                     "--samples-per-cycle", "4000", "--out", tmp_path / "tfp.csv")
    assert code == 0, out.err
    record = read_test_record(tmp_path / "tfp.csv")
    u, f = np.asarray(record.ux), np.asarray(record.fx) / np.asarray(record.normal_load)
    regimes, _ = triple_pendulum_backbone(isolator_from_dict(_document()))
    start, force0, slope = [r for r in regimes if r[0] <= u.max()][-1]
    closed = force0 + slope * (u.max() - start)
    assert f[np.argmax(u)] == pytest.approx(closed, rel=0.01)


def test_simulate_test_refuses_what_the_file_replaces(tmp_path, capsys):
    (tmp_path / "tfp.json").write_text(json.dumps(_document()))
    code, out = _cli(tmp_path, capsys, "--isolator-file", tmp_path / "tfp.json", "--ptfe", "15GF",
                     "--normal-load", "500kip")
    assert code == 2 and "--ptfe: the isolator comes from --isolator-file" in out.err
    code, out = _cli(tmp_path, capsys, "--isolator-file", tmp_path / "tfp.json")
    assert code == 2 and "--normal-load" in out.err
    bad = copy.deepcopy(_document())
    bad["surfaces"]["inner"]["radius"] = 12
    (tmp_path / "bad.json").write_text(json.dumps(bad))
    code, out = _cli(tmp_path, capsys, "--isolator-file", tmp_path / "bad.json", "--normal-load",
                     "500kip")
    assert code == 2 and "bad.json: surfaces.inner.radius" in out.err
