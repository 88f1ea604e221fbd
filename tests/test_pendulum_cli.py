"""`--isolator single-fp --radius R` of `teflon-jax run` and `montecarlo`: the friction
pendulum runs as the spring of period 2 pi sqrt(R / g), and bad input is refused by name
before any record is read."""

import json
import math

import numpy as np
import pytest

from teflon_jax.cli import main
from teflon_jax.units import INCH, STANDARD_GRAVITY


def _two_column(path, dt=0.01, n=801, peak=0.4, frequency=0.7):
    t = dt * np.arange(n)
    a = peak * np.sin(2 * np.pi * frequency * t) * np.sin(np.pi * t / t[-1]) ** 2
    path.write_text("time acc\n" + "\n".join(f"{ti:.4f} {ai:.6e}" for ti, ai in zip(t, a)) + "\n")
    return path


def _peaks(tmp_path, capsys, name, *flags):
    x = _two_column(tmp_path / "x.txt")
    y = _two_column(tmp_path / "y.txt", peak=0.3, frequency=0.9)
    out = tmp_path / f"{name}.json"
    code = main(["run", "--record-x", str(x), "--record-y", str(y), "--record-units", "g",
                 "--json", str(out), *flags])
    capsys.readouterr()
    assert code == 0
    return json.loads(out.read_text())


@pytest.mark.slow
def test_run_on_a_pendulum_is_the_spring_of_its_period(tmp_path, capsys):
    radius = 88 * INCH
    period = 2 * math.pi * math.sqrt(radius / STANDARD_GRAVITY)
    pendulum = _peaks(tmp_path, capsys, "fp", "--isolator", "single-fp", "--radius", "88in")
    spring = _peaks(tmp_path, capsys, "spring", "--isolation-period", f"{period!r}s")
    assert pendulum["isolator"] == "single-fp" and pendulum["radius_m"] == pytest.approx(radius, rel=1e-12)
    assert spring["isolator"] == "flat" and spring["radius_m"] is None
    for key in ("base_disp_resultant_m", "base_shear_ratio_resultant"):
        np.testing.assert_allclose(pendulum["peak"][key], spring["peak"][key], rtol=1e-12)
    # the restoring force adds W d / R to the friction: the base shear exceeds the friction
    assert pendulum["peak"]["base_shear_ratio_resultant"] > pendulum["peak"]["friction_force_ratio_resultant"]


@pytest.mark.parametrize("flags, message", [
    (["--isolator", "single-fp", "--radius", "0in"], "--radius: must be > 0in"),
    (["--isolator", "single-fp", "--radius", "-3m"], "--radius: must be > 0"),
    (["--radius", "88in"], "--radius: applies to --isolator single-fp only"),
    (["--isolator", "single-fp"], "--radius: --isolator single-fp needs the radius"),
    (["--isolator", "single-fp", "--radius", "88in", "--isolation-period", "3s"],
     "--isolation-period: conflicts with --isolator single-fp"),
    (["--isolator", "single-fp", "--radius", "88"], "--radius"),
])
@pytest.mark.parametrize("command", ["run", "montecarlo"])
def test_bad_pendulum_flags_are_refused_naming_the_flag_before_any_work(command, flags, message, capsys,
                                                                        tmp_path):
    missing = ["--record-x", str(tmp_path / "missing.AT2")] if command == "run" else ["--motions", "2"]
    assert main([command, *missing, *flags]) == 2
    err = capsys.readouterr().err
    assert message in err and "missing.AT2" not in err


@pytest.mark.parametrize("command", ["run", "montecarlo"])
def test_unknown_isolator_is_refused(command, capsys):
    with pytest.raises(SystemExit) as exit_info:
        main([command, "--isolator", "curved"])
    assert exit_info.value.code == 2
    assert "--isolator" in capsys.readouterr().err


def test_montecarlo_runs_a_pendulum(tmp_path, capsys):
    out = tmp_path / "mc.json"
    code = main(["montecarlo", "--motions", "2", "--duration", "6s", "--strong-motion", "2s", "--isolator",
                 "single-fp", "--radius", "1m", "--no-progress", "--json", str(out)])
    assert code == 0
    design = json.loads(out.read_text())["design"]
    assert design["isolator"] == "single-fp" and design["radius_m"] == 1.0
    np.testing.assert_allclose(design["isolation_period_s"], 2 * math.pi / math.sqrt(STANDARD_GRAVITY), rtol=1e-12)
    assert design["isolation_damping"] == 0.0
