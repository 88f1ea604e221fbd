"""A surface's parts beyond Eq. 1 in the isolator file: read, written back, run from the command
line, kept through a design and a fit's parameters, and refused by key where a surface cannot
take them.

Peers: the `SurfaceParts` built in Python (the file must give the same bearing test to
rounding), and the closed form of a surface's breakaway (the first peak b mu W of a slow test on
the slipperier surface).
"""

import copy
import json

import jax
import numpy as np
import pytest

from identification.bearing_fit import series_with_parameters
from teflon_jax.bearing import (
    BoucWen,
    DirectionAsymmetry,
    DoublePendulum,
    FrictionalHeating,
    SurfaceParts,
    coulomb_friction,
)
from teflon_jax.cli import main
from teflon_jax.formats import isolator_from_dict, isolator_to_dict, read_test_record
from teflon_jax.systems import imposed_path_test, sampled_path

MU_BOTTOM, MU_TOP = 0.05, 0.08


def _entry(value, unit):
    return {"value": value, "unit": unit}


def _document(**bottom_parts):
    def surface(radius, mu):
        return {"radius": _entry(radius, "m"), "capacity": _entry(0.5, "m"),
                "friction": {"f_max": _entry(mu, "1"), "delta_f": _entry(0.0, "1"), "rate_a": _entry(0.0, "s/m")}}

    document = {"format": "teflon-jax isolator", "format_version": 1, "isolator": "double-fp",
                "surfaces": {"bottom": surface(1.0, MU_BOTTOM), "top": surface(2.0, MU_TOP)},
                "yield_disp": _entry(0.01, "mm")}
    document["surfaces"]["bottom"].update(copy.deepcopy(bottom_parts))
    return document


PARTS = {"breakaway": {"ratio": _entry(1.5, "1")},
         "asymmetry": {"asymmetry": _entry(0.1, "1")},
         "wear": {"change": _entry(-0.2, "1"), "reference_travel": _entry(10, "cm")},
         "friction_perpendicular": {"f_max": _entry(0.04, "1"), "delta_f": _entry(0.0, "1"),
                                    "rate_a": _entry(0.0, "s/in")},
         "lay": {"angle": _entry(30, "deg")},
         "pressure_dependence": {"exponent": _entry(0.3, "1"), "reference_load": _entry(150, "kN"),
                                 "contact_area": _entry(100, "cm^2"), "contact_pressure": _entry(20, "MPa")}}


def _heating(pressure_mpa):
    """A surface's heating entry at the contact pressure `pressure_mpa` [MPa]."""
    return {"contact_area": _entry(0.05, "m^2"), "contact_pressure": _entry(pressure_mpa, "MPa"),
            "heat_scale": _entry(1, "1"), "conductivity": _entry(16.2, "W/(m K)"),
            "diffusivity": _entry(4.4, "mm^2/s"), "initial_temperature": _entry(20, "degC")}


def _force(pendulum):
    t = np.linspace(0.0, 100.0, 2001)
    return np.asarray(jax.jit(imposed_path_test)(pendulum, sampled_path(t, 0.01 * np.sin(2 * np.pi * t / 50.0), 1e6)).force)


def test_the_files_parts_are_the_surface_parts_and_are_written_back():
    read = isolator_from_dict(_document(**PARTS), where="dfp.json")
    part = read.parts()[0]
    assert read.parts()[1] is None
    assert float(part.breakaway_ratio) == 1.5 and float(part.asymmetry.asymmetry) == 0.1
    assert float(part.wear.reference_travel) == pytest.approx(0.1)
    assert float(part.friction_perpendicular.f_max) == 0.04
    assert float(part.lay_angle) == pytest.approx(np.pi / 6)
    assert float(part.pressure_dependence.reference_load) == pytest.approx(150e3)
    assert float(read.bottom_pressure) == pytest.approx(20e6)
    again = isolator_from_dict(json.loads(json.dumps(isolator_to_dict(read))), where="written.json")
    np.testing.assert_allclose(_force(again), _force(read), rtol=1e-14, atol=1e-9)
    built = DoublePendulum(bottom_radius=1.0, top_radius=2.0, bottom_capacity=0.5, top_capacity=0.5,
                           bottom_friction=coulomb_friction(MU_BOTTOM), top_friction=coulomb_friction(MU_TOP),
                           hysteresis=BoucWen(1e-5), surface_parts=(SurfaceParts(
                               breakaway_ratio=1.5, asymmetry=DirectionAsymmetry(0.1)), None))
    one = isolator_from_dict(_document(breakaway=PARTS["breakaway"], asymmetry=PARTS["asymmetry"]), where="f")
    np.testing.assert_allclose(_force(one), _force(built), rtol=1e-14, atol=1e-9)


def test_simulate_test_runs_a_surfaces_breakaway_from_the_file(tmp_path, capsys):
    (tmp_path / "dfp.json").write_text(json.dumps(_document(breakaway=PARTS["breakaway"])))
    code = main(["simulate-test", "--isolator", "double-fp", "--isolator-file", str(tmp_path / "dfp.json"),
                 "--normal-load", "100kN", "--amplitude", "5mm", "--frequency", "0.01Hz", "--cycles", "1",
                 "--samples-per-cycle", "2000", "--out", str(tmp_path / "dfp.csv")])
    assert code == 0, capsys.readouterr().err
    record = read_test_record(tmp_path / "dfp.csv")
    force = np.asarray(record.fx) / np.asarray(record.normal_load)
    assert np.max(force[: len(force) // 8]) == pytest.approx(1.5 * MU_BOTTOM, abs=3e-4)


def test_a_design_and_a_fits_parameters_keep_the_surfaces_heating_and_parts():
    heated = _document(breakaway=PARTS["breakaway"])
    heated["surfaces"]["top"]["heating"] = _heating(30)
    pendulum = isolator_from_dict(heated, where="dfp.json")
    for changed in (pendulum.designed({"radius_scale": 1.1}),
                    series_with_parameters(pendulum, {"bottom_f_max": 0.06})):
        assert changed.parts() == pendulum.parts()
        assert isinstance(changed.top_heating, FrictionalHeating) and float(changed.top_pressure) == 30e6


@pytest.mark.parametrize("part, value, message", [
    ("backlash", {"gap": _entry(1, "mm")}, "surfaces.bottom.backlash: a gap in series with the bearing belongs"),
    ("stack", {"interfaces_in_series": _entry(2, "1")}, "surfaces.bottom.stack"),
    ("hysteresis", {"yield_disp": _entry(1, "mm")}, "surfaces.bottom.hysteresis"),
    ("breakaway", {"ratio": _entry(0.5, "1")}, r"surfaces.bottom.breakaway.ratio: must be >= 1"),
    ("lay", {"angle": _entry(30, "deg")}, "surfaces.bottom.lay: the lay of the steel matters only"),
    ("asymmetry", {"asymmetry": _entry(1.5, "1")}, "surfaces.bottom.asymmetry.asymmetry"),
    ("wear", {"change": _entry(-0.2, "1")}, r"surfaces.bottom.wear: missing \['reference_travel'\]"),
    ("breakaway", {"ratio": _entry(2.0, "m")}, "surfaces.bottom.breakaway.ratio"),
])
def test_a_part_a_surface_cannot_take_is_refused_by_key(part, value, message):
    with pytest.raises(ValueError, match=message):
        isolator_from_dict(_document(**{part: value}), where="dfp.json")


def test_a_misspelt_part_is_refused_with_the_parts_a_surface_takes():
    """A part's name that is off by a letter: the message lists the optional parts beside the
    required keys, and names the part it is closest to."""
    with pytest.raises(ValueError) as error:
        isolator_from_dict(_document(breakway=PARTS["breakaway"]), where="dfp.json")
    message = str(error.value)
    assert "surfaces.bottom: unknown ['breakway']" in message
    assert "optional heating, breakaway, " in message and "'breakway' is not 'breakaway'" in message
    with pytest.raises(ValueError, match=r"unknown \['spin'\] \(expected radius.*nothing is defaulted\)\.$"):
        isolator_from_dict(_document(spin=PARTS["breakaway"]), where="dfp.json")


def test_two_contact_pressures_of_one_surface_are_refused():
    document = _document(pressure_dependence=PARTS["pressure_dependence"])
    document["surfaces"]["bottom"]["heating"] = _heating(25)
    with pytest.raises(ValueError, match="pressure_dependence.contact_pressure: .* differs from heating"):
        isolator_from_dict(document, where="dfp.json")
