"""Design under two horizontal ground components (`design --components 2`).

The flat sliders' group is isotropic (Park's biaxial Z, Eq. 1 at the resultant sliding
speed), so a set of motions that all shake along one line at an angle to x gives the design's
responses of the same motions along x in one component: the smoothed and true peak base
displacement (resultant) and base shear, and their derivatives in the design variables, to
the planar solve's tolerance. The command draws two-component motions, designs on their
resultant peaks and refuses what does not apply.
References: Park, Wen & Ang (1986); Constantinou, Mokha & Reinhorn (1990), J. Struct. Eng.
116(2), Eqs. 1, 8-9.
"""

import json

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from teflon_jax.cli import main
from teflon_jax.excitation import StochasticGroundMotion, sample
from teflon_jax.studies import bidirectional_isolated_structure, expected_response
from teflon_jax.studies._design import response_derivatives
from teflon_jax.systems import isolated_structure
from teflon_jax.units import PSI

DT = 0.01
ANGLE = 0.6  # rad, the line the motions shake along
DESIGN = {"isolation_period": 2.5, "pressure": 1400 * PSI}
SETTINGS = {"ptfe": "UF", "isolation_damping": 0.05, "pressure": 1000 * PSI, "isolation_period": 2.0,
            "time_step": 0.0025, "newton_tolerance": 0.0}


@pytest.fixture(scope="module")
def along_a_line():
    """(records along x (2, nt), the same along the line at `ANGLE` (2, 2, nt))."""
    model = StochasticGroundMotion(peak_ground_acceleration=4.0, duration=4.0, time_step=DT, rise_time=1.0,
                                   strong_motion_duration=2.0)
    records = sample(model, jax.random.key(3), 2)
    return records, jnp.stack([np.cos(ANGLE) * records, np.sin(ANGLE) * records], 1)


def _structures():
    """The design's structures of one and of two components (`cli._design`'s settings)."""
    one = isolated_structure("rigid", split_at_turn=False, linear_rule="newmark", **SETTINGS)
    return one, bidirectional_isolated_structure("rigid", **SETTINGS)


def test_a_design_along_a_line_responds_as_the_one_component_design(along_a_line):
    """Every response of `expected_response` (smoothed and true peaks, their 95th
    percentiles, the largest peak) of the motions along the line equals the one-component
    responses along x, to the planar solve's tolerance."""
    records, turned = along_a_line
    one, two = _structures()
    a = jax.jit(lambda r: expected_response(one, DESIGN, r, DT))(records)
    b = jax.jit(lambda r: expected_response(two, DESIGN, r, DT))(turned)
    assert float(a["peak_disp"]) > 0.01 and bool(b["converged"])
    for key in ("shear", "disp", "peak_shear", "peak_disp", "disp_p95", "peak_disp_p95", "peak_disp_max"):
        np.testing.assert_allclose(float(b[key]), float(a[key]), rtol=1e-10, err_msg=key)


@pytest.mark.slow
def test_its_derivatives_are_the_one_component_ones(along_a_line):
    """The derivatives of the smoothed mean peaks in T_b and the pressure (one forward pass per
    variable, `response_derivatives`) along the line equal those of one component along x."""
    records, turned = along_a_line
    one, two = _structures()
    names = tuple(DESIGN)
    a = response_derivatives(one, records, DT, names)[1](DESIGN)[1]
    b = response_derivatives(two, turned, DT, names)[1](DESIGN)[1]
    for key in ("shear", "disp"):
        for name in names:
            assert abs(a[key][name]) > 0
            np.testing.assert_allclose(b[key][name], a[key][name], rtol=1e-8, err_msg=f"{key}, {name}")


def test_records_of_one_component_are_refused_by_a_structure_of_two(along_a_line):
    records, _ = along_a_line
    with pytest.raises(ValueError, match=r"records: need an \(N >= 1, 2, nt\): x and y array .* got shape \(2, 401\)"):
        expected_response(_structures()[1], DESIGN, records, DT)


@pytest.mark.parametrize("flag", [["--principal-angle", "30deg"], ["--minor-ratio", "0.5"]])
def test_a_second_components_flag_without_two_components_is_refused(flag, capsys):
    code = main(["--no-compile-cache", "design", "--motions", "2", "--no-progress", *flag])
    assert code == 2
    assert f"{flag[0]}: describes the second ground component; add --components 2." in capsys.readouterr().err


@pytest.mark.slow
def test_design_in_two_components_meets_its_limit_on_the_resultant_peaks(tmp_path):
    """`design --components 2`: BFGS ends with the mean true peak resultant base displacement
    within the limit, the gradient check passes, and the summary and sweep file say two
    components."""
    out = tmp_path / "d.json"
    argv = ["--no-compile-cache", "design", "--components", "2", "--motions", "2", "--duration", "6s",
            "--strong-motion", "3s", "--grid", "3", "--no-progress", "--json", str(out), "--out",
            str(tmp_path / "sweep.nc")]
    assert main(argv) == 0
    summary = json.loads(out.read_text())
    optimum = summary["optimum"]
    assert summary["components"] == 2
    assert optimum["mean_peak_base_disp_in"] <= 1.25
    assert optimum["converged"] and summary["gradient_rel_error"] <= summary["gradient_tolerance"]
    import xarray

    with xarray.open_dataset(tmp_path / "sweep.nc") as sweep:
        assert int(sweep.attrs["components"]) == 2


def test_the_forward_jacobian_is_jacfwds():
    """`forward_jacobian` (one tangent after the other) gives `jax.jacfwd`'s tree and values,
    with its aux, for outputs and inputs of several shapes."""
    from teflon_jax.studies._forward_jacobian import forward_jacobian

    def f(x):
        return {"a": x["p"] ** 2 * x["q"][0], "b": jnp.stack([jnp.sin(x["p"]), x["q"] @ x["q"]])}, 3 * x["p"]

    x = {"p": jnp.asarray(1.3), "q": jnp.asarray([0.5, 2.0])}
    (expected, aux), (found, found_aux) = jax.jacfwd(f, has_aux=True)(x), forward_jacobian(f, has_aux=True)(x)
    assert float(found_aux) == float(aux)
    for key in ("a", "b"):
        for name in ("p", "q"):
            assert found[key][name].shape == expected[key][name].shape
            np.testing.assert_allclose(found[key][name], expected[key][name], rtol=1e-15)
