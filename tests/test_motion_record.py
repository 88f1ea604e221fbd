"""One reader per format: `simulate-test --motion-file` reads the test-record CSV through
`formats.read_motion_record`, the reader `read_test_record` is built on; and one table of the
units fitted parameters are shown in, shared by `teflon-jax fit` and the fit plot."""

import numpy as np
import pytest

from teflon_jax.cli._isolator_table import _shown
from teflon_jax.cli._main import main
from teflon_jax.excitation import TabulatedBiaxialMotion
from teflon_jax.formats import read_motion_record, read_test_record
from teflon_jax.report import parameter_unit
from teflon_jax.units import INCH

FILE = """# source: a hand-written path
# direction: T
time [s],ux [in],uy [mm]
0.0,0.0,0.0
0.5,1.0,5.0
1.0,0.0,10.0
1.5,-1.0,5.0
2.0,0.0,0.0
"""


def test_motion_file_is_read_by_the_test_record_reader(tmp_path):
    path = tmp_path / "path.csv"
    path.write_text(FILE)
    motion = read_motion_record(path)
    tested = tmp_path / "tested.csv"  # the same path with the force a test measures
    tested.write_text("\n".join(line + (",fx [kip]" if line.startswith("time") else ",0" * line[0].isdigit())
                                for line in FILE.splitlines()) + "\n")
    record = read_test_record(tested)
    np.testing.assert_array_equal(read_motion_record(tested).ux, motion.ux)  # a test's own file replays it
    np.testing.assert_allclose(motion.ux, record.ux)
    np.testing.assert_allclose(motion.uy, record.uy)
    np.testing.assert_allclose(motion.ux[1], 1.0 * INCH, rtol=1e-15)
    np.testing.assert_allclose(motion.uy[2], 10e-3, rtol=1e-15)
    assert isinstance(motion, TabulatedBiaxialMotion)
    np.testing.assert_allclose(motion.displacement(0.25), [0.5 * INCH, 2.5e-3], rtol=1e-12)


@pytest.mark.parametrize("text, message", [
    ("time [s],ux\n0,0\n1,1\n", "line 1: column 'ux' has no unit"),
    ("time [s],uy [in]\n0,0\n1,1\n", "missing required column(s) 'ux'"),
    ("ux [in],fx [kip]\n0,0\n1,1\n", "missing required column(s) 'time'"),
    ("time [s],ux [in]\n0,0\n1,nan\n", "line 3, column 'ux'"),
    ("time [s],ux [in]\n0,0\n0,1\n", "line 3, column 'time': time must increase strictly"),
])
def test_bad_motion_files_are_refused_with_file_line_and_column(tmp_path, text, message, capsys):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(ValueError, match="bad.csv"):
        read_motion_record(path)
    assert main(["simulate-test", "--motion-file", str(path), "--out", str(tmp_path / "o.csv")]) == 2
    err = capsys.readouterr().err
    assert "bad.csv" in err and message in err


def test_a_motion_file_whose_rows_miss_a_header_cell_is_refused_naming_the_header(tmp_path, capsys):
    path = tmp_path / "m.csv"
    path.write_text("# direction: P\ntime [s],ux [in],uy [in]\n0,0,0\n0.1,0.5\n0.2,1,1\n")
    out = tmp_path / "b.csv"
    assert main(["simulate-test", "--motion-file", str(path), "--out", str(out)]) == 2
    assert (f"{path}, line 4: 2 cell(s) but the header (line 2) has 3 columns (time, ux, uy); make the header and "
            "every row hold the same number of cells.") in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.parametrize("column, hint", [("y [in]", ", or name it 'uy' if it is the displacement along y."),
                                          ("force [N]", ".")])
def test_a_column_the_motion_does_not_take_is_refused_not_left_out(tmp_path, capsys, column, hint):
    path = tmp_path / "m.csv"
    path.write_text(f"time [s],ux [in],{column}\n0,0,0\n0.1,0.5,0.5\n0.2,1,1\n0.3,0.5,0.5\n0.4,0,0\n")
    out = tmp_path / "b.csv"
    assert main(["simulate-test", "--motion-file", str(path), "--out", str(out)]) == 2
    name = column.split()[0]
    assert (f"{path}, line 1, column '{name}': an imposed motion takes only the columns 'time', 'ux', "
            f"'uy' ('uy' for a biaxial path), so this one would be left out; remove it{hint}") in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.parametrize("flags", [["--amplitude", "1in"], ["--frequency", "1Hz"], ["--cycles", "5"],
                                   ["--pattern", "eight"], ["--samples-per-cycle", "100"],
                                   ["--isolator", "single-fp", "--radius", "2m", "--normal-load", "100kN",
                                    "--cycles", "2"]])
def test_a_generated_motions_flag_beside_a_motion_file_is_refused(tmp_path, capsys, flags):
    path = tmp_path / "path.csv"
    path.write_text(FILE)
    out = tmp_path / "out.csv"
    assert main(["simulate-test", "--motion-file", str(path), *flags, "--out", str(out)]) == 2
    flag = flags[-2]
    assert (f"{flag}: shapes a generated motion, and --motion-file {path} gives the motion, saved at its own "
            f"samples; leave {flag} out.") in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.slow
def test_simulate_test_runs_the_motion_file(tmp_path):
    path = tmp_path / "path.csv"
    path.write_text(FILE)
    out = tmp_path / "out.csv"
    assert main(["simulate-test", "--motion-file", str(path), "--out", str(out)]) == 0
    written = read_test_record(out)
    np.testing.assert_allclose(written.ux[[0, -1]], 0.0, atol=1e-12)
    assert np.max(np.abs(written.ux)) == pytest.approx(INCH, rel=1e-8)  # written with 9 digits
    assert np.max(np.abs(written.uy)) == pytest.approx(10e-3, rel=1e-8)  # written with 9 digits


def test_parameters_are_shown_in_one_table_of_units():
    assert parameter_unit("yield_disp", ("in", INCH)) == ("in", INCH)
    assert parameter_unit("rate_a", ("in", INCH)) == ("s/in", 1 / INCH)
    assert parameter_unit("rate_a_perpendicular", ("mm", 1e-3)) == ("s/m", 1.0)
    assert parameter_unit("f_max", ("mm", 1e-3)) == ("", 1.0)
    assert _shown("yield_disp", 0.005 * INCH, 0.001 * INCH, True) == "yield_disp = 0.005 +- 0.001 in"
    assert _shown("rate_a", 100.0, 2.0, False) == "rate_a = 100 +- 2 s/m"
    assert _shown("rate_a", 100.0 / INCH * INCH, 2.0, True) == f"rate_a = {100 * INCH:.5g} +- {2 * INCH:.2g} s/in"
