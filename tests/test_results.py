"""Tests of Monte Carlo results as files: an xarray Dataset with units, NetCDF that reads back
into the same object, the CSV peak table, and honest refusals (format, place)."""

import jax
import numpy as np
import pytest
import xarray

from teflon_jax.excitation import StochasticGroundMotion
from teflon_jax.studies import MonteCarloResult, check_output_path, monte_carlo
from teflon_jax.systems import isolated_structure
from teflon_jax.units import PSI


@pytest.fixture(scope="module")
def result():
    model = StochasticGroundMotion(peak_ground_acceleration=3.0, duration=3.0, time_step=0.01,
                                   rise_time=0.5, strong_motion_duration=1.5)
    structure = isolated_structure("rigid", time_step=0.01, isolation_period=1.5)
    return monte_carlo(structure, model, 5, key=jax.random.key(3), chunk_size=5,
                       design={"isolation_period": [1.2, 2.4], "pressure": [1000 * PSI, 2000 * PSI]})


def test_netcdf_round_trips_every_variable_with_its_units(result, tmp_path):
    path = result.save(tmp_path / "mc.nc")
    expected = result.to_dataset()
    with xarray.open_dataset(path) as stored:
        assert set(stored.data_vars) == set(expected.data_vars)
        for name, variable in expected.data_vars.items():
            np.testing.assert_array_equal(stored[name].values, variable.values)
            assert stored[name].dtype == variable.dtype, name
            assert stored[name].dims == variable.dims
            assert stored[name].attrs["units"] == variable.attrs["units"], name
            assert stored[name].attrs["long_name"] == variable.attrs["long_name"]
        assert stored["base_disp"].attrs["units"] == "m"
        assert stored["pga"].attrs["units"] == "m s-2"
        assert stored["design_pressure"].attrs["units"] == "Pa"
        assert stored.attrs["duration_s"] == pytest.approx(3.0)
    back = MonteCarloResult.open(path)
    for name in ("base_disp", "base_shear_ratio", "smooth_base_disp", "smooth_base_shear_ratio",
                 "converged", "pga"):
        np.testing.assert_array_equal(getattr(back, name), getattr(result, name))
    assert back.dims == ("design", "motion") and back.attrs == result.attrs
    np.testing.assert_array_equal(back.design["pressure"], result.design["pressure"])
    assert back.percentiles() == result.percentiles()


def test_csv_peak_table(result, tmp_path):
    path = result.to_csv(tmp_path / "peaks.csv")
    header = path.read_text().splitlines()[0].split(",")
    assert header[:4] == ["design", "motion", "isolation_period", "pressure"]
    table = np.genfromtxt(path, delimiter=",", skip_header=1, dtype=None, encoding=None)
    assert len(table) == 10  # 2 variants x 5 motions
    disp = np.array([row[header.index("base_disp_m")] for row in table])
    np.testing.assert_allclose(disp, result.base_disp.reshape(-1), rtol=1e-15)


def test_output_places_and_formats_are_checked_before_computing(tmp_path):
    with pytest.raises(ValueError, match="unknown results format '.xlsx'"):
        check_output_path(tmp_path / "out.xlsx")
    with pytest.raises(ValueError, match="folder .* does not exist"):
        check_output_path(tmp_path / "missing" / "out.nc")
    a_file = tmp_path / "a_file"
    a_file.write_text("")
    with pytest.raises(ValueError, match="cannot write results"):
        check_output_path(a_file / "out.nc")
