"""The vertical ground component in the Monte Carlo with two horizontal components and on series
(triple, double) pendulums: a vertical record of zeros leaves the horizontal-only peaks as they
were; each generated motion run in the Monte Carlo gives the peaks and the uplift time that a
direct simulation of that motion gives; the uplift counted per motion is the time with
1 + a_v / g <= 0 of the generated vertical record (a closed form of the record); an isolator
lifted off for the whole run carries no shear, so the rigid mass stays at rest and the base
moves by the ground's displacement; and what still cannot be run is refused by flag."""

import json
import pathlib

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from histories import planar_histories

from teflon_jax.bearing import concave_surface
from teflon_jax.cli import main
from teflon_jax.excitation import (
    StochasticGroundMotion,
    TwoComponentGroundMotion,
    VerticalGroundMotion,
    uniform_signal,
)
from teflon_jax.formats import load_isolator
from teflon_jax.studies import (
    bidirectional_isolated_structure,
    monte_carlo,
    monte_carlo_motion,
)
from teflon_jax.systems import (
    initial_state,
    isolated_structure,
    peak_response,
    simulate_history,
    triple_structure,
    with_vertical_component,
    with_vertical_motion,
)
from teflon_jax.units import STANDARD_GRAVITY

BENCHMARKS = pathlib.Path(__file__).resolve().parents[1] / "benchmarks"
DURATION = 4.0
N = 3
ROUNDING = 1e-12
"""Relative tolerance between the Monte Carlo runs with and without a vertical record of
zeros. Their steps are the same bit for bit from the same state (N = W exactly:
`test_a_zero_vertical_record_steps_bit_for_bit`), but the two runs are compiled as different
programs (the vertical one reads a third record), whose fused arithmetic may round a last bit
differently: a peak of the single pendulum's two-component run differs by one unit in the
last place (1.4e-17 m of 0.077 m)."""
PEAKS = ("base_disp", "base_shear_ratio", "smooth_base_disp", "smooth_base_shear_ratio", "converged", "pga")


def _horizontal(components, pga=0.4):
    model = StochasticGroundMotion(peak_ground_acceleration=pga * STANDARD_GRAVITY, duration=DURATION,
                                   time_step=0.01, rise_time=0.5, strong_motion_duration=2.0)
    return TwoComponentGroundMotion(model) if components == 2 else model


def _structure(isolator, components, kind="rigid"):
    build = bidirectional_isolated_structure if components == 2 else isolated_structure
    if isolator in ("triple-fp", "double-fp"):
        pendulum = load_isolator(BENCHMARKS / f"{isolator.split('-')[0]}_isolator.json")
        return build(kind, isolator=pendulum, time_step=0.005)
    options = {"isolator": concave_surface(2.0)} if isolator == "single-fp" else {"isolation_period": 2.5}
    return build(kind, **options)


def _run(structure, motions):
    return monte_carlo(structure, motions, N, key=jax.random.key(11), chunk_size=N, devices=jax.devices()[:1])


@pytest.mark.parametrize("isolator, components, kind", [
    ("triple-fp", 1, "rigid"),
    pytest.param("double-fp", 2, "rigid", marks=pytest.mark.slow),
    pytest.param("flat", 1, "rigid", marks=pytest.mark.slow),
    pytest.param("single-fp", 2, "rigid", marks=pytest.mark.slow),
    pytest.param("flat", 2, "building", marks=pytest.mark.slow),
    pytest.param("triple-fp", 2, "building", marks=pytest.mark.slow),
])
def test_a_zero_vertical_ratio_gives_the_horizontal_only_peaks(isolator, components, kind):
    """vertical_ratio = 0 draws a vertical record of zeros: N = W at every step, the horizontal
    components are the ones drawn without it, and every peak is the horizontal-only run's to
    `ROUNDING` (convergence flags exactly); no motion uplifts."""
    structure = _structure(isolator, components, kind)
    plain = _run(structure, _horizontal(components))
    loaded = _run(with_vertical_component(structure), VerticalGroundMotion(_horizontal(components), 0.0))
    for name in PEAKS:
        np.testing.assert_allclose(getattr(loaded, name), getattr(plain, name), rtol=ROUNDING, atol=0,
                                   err_msg=name)
    assert plain.uplift_time is None and np.array_equal(loaded.uplift_time, np.zeros(N))
    assert loaded.attrs["vertical_ratio"] == 0.0 and loaded.attrs.get("components") == (2 if components == 2
                                                                                        else None)


@pytest.mark.last_bit
@pytest.mark.parametrize("isolator, kind", [("single-fp", "rigid"), pytest.param("flat", "building",
                                                                              marks=pytest.mark.slow)])
def test_a_zero_vertical_record_steps_bit_for_bit(isolator, kind):
    """Two components: each step of the structure with a vertical record of zeros (load factor
    1 + 0 / g = 1, N = W exactly, the pendulum's change of stiffness (1 - 1) W / R = 0) from a
    state gives, bit for bit, the state and acceleration of the horizontal-only structure's
    step from that state, over 200 steps of a random two-component record."""
    rng = np.random.default_rng(3)
    ax, ay = (uniform_signal(4.0 * rng.standard_normal(201), 0.01) for _ in range(2))
    structure = _structure(isolator, 2, kind)
    plain = structure((ax, ay))
    loaded = with_vertical_component(structure)(((ax, ay), uniform_signal(np.zeros(201), 0.01)))

    def stepper(system):
        def step(y, a, t1):
            at = system.at_load(None if system.vertical_acceleration is None else system.load_factor(t1))
            y1, _ = at.newmark_update(y, a, system.ground(t1))
            return y1, at.acceleration_at(system.ground(t1), y1)
        return jax.jit(step)

    step_plain, step_loaded = stepper(plain), stepper(loaded)
    y = initial_state(plain)
    a = plain.acceleration_at(plain.ground(0.0), y)
    for k in range(1, 201):
        t1 = k * float(plain.time_step)
        y1, a1 = step_plain(y, a, t1)
        y1_loaded, a1_loaded = step_loaded(y, a, t1)
        for name in y1:
            np.testing.assert_array_equal(y1_loaded[name], y1[name], err_msg=f"{name} at step {k}")
        np.testing.assert_array_equal(a1_loaded, a1, err_msg=f"acceleration at step {k}")
        y, a = y1, a1
    assert float(jnp.max(jnp.abs(y["u"]))) > 1e-3  # the bearings slid


def _uplift_of_record(vertical, record_step, time_step, n_steps):
    """dt times the steps k = 1..n whose end has 1 + a_v(k dt) / g <= 0, a_v the record
    interpolated linearly (as a `Signal` reads it)."""
    t = np.arange(1, n_steps + 1) * time_step
    a_v = np.interp(t, record_step * np.arange(vertical.size), vertical)
    return np.sum(1 + a_v / STANDARD_GRAVITY <= 0) * time_step


@pytest.mark.parametrize("isolator, components", [
    ("triple-fp", 1),
    pytest.param("double-fp", 2, marks=pytest.mark.slow),
    pytest.param("triple-fp", 2, marks=pytest.mark.slow),
    pytest.param("double-fp", 1, marks=pytest.mark.slow),
])
def test_series_pendulum_vertical_runs_are_the_direct_simulations(isolator, components):
    """Each motion i of the Monte Carlo (`monte_carlo_motion`: x, (y), vertical), built into the
    structure by the public `with_vertical_motion` and simulated step by step with every state
    kept, gives the Monte Carlo's peak displacement and shear (1e-12) and its uplift time; with
    a vertical peak 2.5 times the horizontal one some motions lift off, and the uplift time is
    the record's time with 1 + a_v / g <= 0."""
    structure = _structure(isolator, components)
    motions = VerticalGroundMotion(_horizontal(components, pga=0.5), vertical_ratio=2.5)
    result = _run(with_vertical_component(structure), motions)
    assert result.converged.all() and np.all(np.isfinite(result.base_disp))
    pendulum = structure.pendulum
    dt, n_steps = structure.time_step, round(DURATION / structure.time_step)
    for i in range(N):
        rows = np.asarray(monte_carlo_motion(motions, jax.random.key(11), i))
        system = triple_structure("rigid", pendulum, uniform_signal(rows[0], 0.01), time_step=dt,
                                  newton_tolerance=structure.newton_tolerance)
        if components == 2:
            system = with_vertical_motion(system.with_y_component(uniform_signal(rows[1], 0.01)),
                                          uniform_signal(rows[-1], 0.01))
            _, x, _, _, acc, ok = (np.asarray(a) for a in planar_histories(system, DURATION))
            disp = np.hypot(x[:, 0, 0], x[:, 1, 0]).max()
            shear = np.hypot(acc[:, 0, 0], acc[:, 1, 0]).max() / STANDARD_GRAVITY
        else:
            response = simulate_history(with_vertical_motion(system, uniform_signal(rows[-1], 0.01)),
                                                 DURATION)
            ok = np.asarray(response.converged)
            disp = np.abs(np.asarray(response.displacement)[:, 0]).max()
            shear = np.abs(np.asarray(response.total_acceleration)[:, 0]).max() / STANDARD_GRAVITY
            assert float(response.uplift_time) == result.uplift_time[i]
        assert ok.all()
        assert result.base_disp[i] == pytest.approx(disp, rel=1e-12)
        assert result.base_shear_ratio[i] == pytest.approx(shear, rel=1e-12, abs=1e-15)
        assert result.uplift_time[i] == pytest.approx(_uplift_of_record(rows[-1], 0.01, dt, n_steps), abs=1e-12)
    assert result.n_uplifted > 0


def test_two_component_uplift_is_the_records_time_below_minus_g():
    """Flat sliders under two horizontal components and a strong vertical one: the uplift time
    of each motion is that of its generated vertical record, the peaks stay finite, and the
    peak ground acceleration is the horizontal resultant's."""
    motions = VerticalGroundMotion(_horizontal(2, pga=0.5), vertical_ratio=2.5)
    structure = _structure("flat", 2)
    result = _run(with_vertical_component(structure), motions)
    n_steps = round(DURATION / structure.time_step)
    for i in range(N):
        rows = np.asarray(monte_carlo_motion(motions, jax.random.key(11), i))
        assert result.uplift_time[i] == pytest.approx(
            _uplift_of_record(rows[2], 0.01, structure.time_step, n_steps), abs=1e-12)
        assert result.pga[i] == pytest.approx(np.hypot(rows[0], rows[1]).max(), rel=1e-15)
    assert result.n_uplifted > 0 and result.converged.all()
    assert np.all(np.isfinite(result.base_disp)) and np.all(np.isfinite(result.base_shear_ratio))


def _ground_displacement(a, dt):
    """Displacement [m] of a ground acceleration `a` [m/s^2] linear over each step of `dt` [s],
    from rest: u_{k+1} = u_k + dt v_k + dt^2 (2 a_k + a_{k+1}) / 6, v_{k+1} = v_k + dt (a_k + a_{k+1}) / 2."""
    u, v = np.zeros(a.size), np.zeros(a.size)
    for k in range(a.size - 1):
        u[k + 1] = u[k] + dt * v[k] + dt**2 * (2 * a[k] + a[k + 1]) / 6
        v[k + 1] = v[k] + dt * (a[k] + a[k + 1]) / 2
    return u


@pytest.mark.slow
def test_an_isolator_lifted_off_throughout_carries_no_shear():
    """a_v = -2 g for the whole run: N = 0 at every step, so the double pendulum transmits no
    force in either direction; the rigid mass stays at rest, the peak force on it is zero and
    the base's peak displacement is the ground's, |(u_gx, u_gy)| (integrated exactly for a
    ground linear over each step), with the whole run counted as uplift."""
    pendulum = load_isolator(BENCHMARKS / "double_isolator.json")
    dt, duration = 0.005, 2.0
    t = dt * np.arange(round(duration / dt) + 1)
    ax, ay = 3.0 * np.sin(2 * np.pi * 1.3 * t), 2.0 * np.cos(2 * np.pi * 0.7 * t) - 2.0
    system = triple_structure("rigid", pendulum, uniform_signal(ax, dt), time_step=dt)
    lifted = with_vertical_motion(system.with_y_component(uniform_signal(ay, dt)),
                                  uniform_signal(np.full(t.size, -2 * STANDARD_GRAVITY), dt))
    peaks = peak_response(lifted, duration)
    ground = np.hypot(_ground_displacement(ax, dt), _ground_displacement(ay, dt)).max()
    assert bool(peaks.converged)
    assert float(peaks.base_shear_ratio) < 1e-12
    # the step carries the force beyond the reference spring W / R_ref linearly over the step,
    # so the spring's cancellation is exact at the steps' ends only: second order in dt
    assert float(peaks.base_disp) == pytest.approx(ground, rel=2e-5)
    assert float(peaks.uplift_time) == pytest.approx(duration, rel=1e-12)
    with pytest.raises(ValueError, match="radius"):
        with_vertical_motion(system, uniform_signal(ax, dt), radius=2.0)
    with pytest.raises(ValueError, match="vertical_acceleration"):
        with_vertical_motion(system, ax)


@pytest.mark.parametrize("flags, named", [
    (["--vertical-ratio", "-0.5"], "--vertical-ratio"),
    (["--vertical-frequency-ratio", "3"], "--vertical-frequency-ratio"),
])
def test_what_the_vertical_component_cannot_run_is_refused_by_flag(flags, named, capsys, tmp_path,
                                                                   monkeypatch):
    """Refused before any run, naming the flag: a negative ratio, and the vertical frequency
    ratio without a vertical component."""
    monkeypatch.chdir(tmp_path)
    ratio = [] if any(f.startswith("--vertical") for f in flags) else ["--vertical-ratio", "0.7"]
    assert main(["montecarlo", "--motions", "2", "--components", "2", *ratio, *flags, "--no-progress"]) == 2
    assert named in capsys.readouterr().err


@pytest.mark.slow
def test_cli_two_components_on_a_triple_pendulum_with_a_zero_vertical_ratio(tmp_path, capsys):
    """`montecarlo --components 2 --isolator triple-fp --vertical-ratio 0`: the statistics are
    the horizontal-only run's to rounding (the sliders' balance under N = 1 x W is a program of
    another form, whose iterates differ in their last bits), the summary says no motion lifted
    off."""
    common = ["montecarlo", "--motions", "2", "--duration", "4s", "--strong-motion", "2s", "--components", "2",
              "--isolator", "triple-fp", "--isolator-file", str(BENCHMARKS / "triple_isolator.json"),
              "--no-progress"]
    assert main([*common, "--json", str(tmp_path / "a.json")]) == 0
    assert main([*common, "--vertical-ratio", "0", "--json", str(tmp_path / "b.json")]) == 0
    printed = capsys.readouterr().out
    plain, loaded = (json.loads((tmp_path / name).read_text()) for name in ("a.json", "b.json"))
    assert loaded["statistics"].keys() == plain["statistics"].keys()
    for name, statistics in plain["statistics"].items():
        assert loaded["statistics"][name].keys() == statistics.keys()
        for key, value in statistics.items():
            assert loaded["statistics"][name][key] == pytest.approx(value, rel=1e-12, abs=0), f"{name} {key}"
    assert loaded["vertical"]["n_uplifted"] == 0 and "uplift (N <= 0): 0 motion(s)" in printed


@pytest.mark.slow
def test_the_dask_engine_runs_the_vertical_component(dask_cluster, tmp_path):
    """`monte_carlo_distributed` with two horizontal components and a vertical one: the file holds
    each motion's uplift time, and every peak equals the in-process run's with the same chunk
    size, bit for bit."""
    pytest.importorskip("distributed")
    from teflon_jax.studies import monte_carlo_distributed

    motions = VerticalGroundMotion(_horizontal(2, pga=0.5), vertical_ratio=2.5)
    structure = with_vertical_component(_structure("flat", 2))
    result = monte_carlo_distributed(structure, motions, N, seed=11, out=tmp_path / "mc.nc",
                                     scheduler=dask_cluster.scheduler_address, chunk_size=2)
    here = monte_carlo(structure, motions, N, key=jax.random.key(11), chunk_size=2, devices=jax.devices()[:1])
    for name in (*PEAKS, "uplift_time"):
        np.testing.assert_array_equal(getattr(result, name), getattr(here, name), err_msg=name)
    assert result.n_uplifted == here.n_uplifted > 0
    assert result.attrs["vertical_ratio"] == 2.5 and result.attrs["components"] == 2
