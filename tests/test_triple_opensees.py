"""The rigid mass and the Table 2 building on triple friction pendulums against OpenSees'
`TripleFrictionPendulum` element under the PEER RSN6 record (180 component, first 30 s, scaled
by 1 and by 2), one direction, with constant friction on every surface: the laws alike, the
two programs differ only in the shape of the stick-slip corner (`benchmarks/_opensees_triple.py`).

Measured (ours over OpenSees, minus 1; Y = uy = 0.5 mm, 2.5 ms on both sides): rigid mass
-0.64 % / -0.00 % (displacement / base shear) at x1, -0.94 % / -0.17 % at x2; building
-0.84 % / +0.35 % at x1, +0.38 % / +0.74 % at x2. At x2 the bearing runs through regimes I-IV
(the bottom surface up to 0.13 of its 0.25 m). Eq. 1 against `VelDependent`:
`benchmarks/bench_triple_opensees.py` (the laws differ in form there).

Can fail: with our outer friction 10 % higher (0.066, 0.11) every case is off by more than
2 % (displacement -4.0, +2.1, -2.2, +7.8 %; base shear +3.4, +6.4, +5.8, +8.9 %)."""

import importlib.util
import pathlib
import sys

import pytest

_PATH = pathlib.Path(__file__).resolve().parent.parent / "benchmarks" / "bench_triple_opensees.py"
try:
    _spec = importlib.util.spec_from_file_location("bench_triple_opensees", _PATH)
    bench = importlib.util.module_from_spec(_spec)
    _spec.loader.exec_module(bench)
    sys.modules["_opensees_triple"].import_opensees()
except ImportError as error:  # openseespy missing or its libraries cannot be loaded
    pytest.skip(f"OpenSees peer not available: {error}", allow_module_level=True)


@pytest.mark.parametrize("scale", [1.0, 2.0])
@pytest.mark.parametrize("kind", ["rigid", "building"])
def test_peaks_agree_with_opensees_triple_friction_pendulum(kind, scale, external_data):
    row = bench.compare(kind, "coulomb", scale, external_data)
    displacement, shear = row["difference"]
    assert abs(displacement) < 0.02
    assert abs(shear) < 0.02


@pytest.mark.parametrize("kind", ["rigid", "building"])
def test_two_components_agree_with_opensees(kind, external_data):
    """RSN6's 180 along x and 270 along y, Y = uy = 0.1 mm: resultant peaks (measured -0.44 % /
    -0.07 % rigid, -0.18 % / -0.05 % building; at 0.5 mm the rigid mass's displacement is
    -2.0 % off, the corner's share)."""
    row = bench.compare_two(kind, "coulomb-0.1mm", 1.0, external_data)
    displacement, shear = row["difference"]
    assert abs(displacement) < 0.02
    assert abs(shear) < 0.02
