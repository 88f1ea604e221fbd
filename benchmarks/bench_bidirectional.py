"""B6: bidirectional records per second, against the uniaxial rate and against OpenSees.

The rigid mass (T = 2.5 s springs, 5 % damping) and the Table 2 building (T_b = 2.5 s) on
UF / 1000 psi bearings with Table 1's breakaway, under pairs of 40 s Clough-Penzien motions
(records at 0.01 s, structure steps 2.5 ms): records per second of one vmapped, jitted call
on 256 pairs (a Monte Carlo chunk per device; `--quick`: 8 pairs of 10 s, where the cost per
step of the loop's kernels, not the arithmetic, sets the rate) for the bidirectional systems
(x and y components) and for the uniaxial ones (x only), and
the OpenSees peers in 3D, the rigid mass and the building (`flatSliderBearing` with
`VelDependent` friction under both components, Newmark + modified Newton at the same step),
on the first pairs of the same set, one record after another in one process. OpenSees has no
breakaway, so its peaks are set beside ours computed without breakaway on the same pairs
(peak resultant base displacement and peak resultant base shear ratio, the total horizontal
force above the bearings over the weight, both read after every step), per record, with the
differences ours / OpenSees - 1 in per cent (`disp_difference_pct`, `shear_difference_pct`).
OpenSees' `records_per_s` counts the wall time of the transient analyses, `records_per_cpu_s`
the process CPU time of the whole peer calls (model builds and gravity steps included).
Compile time and run time are reported apart; run times are the best of `REPEATS`, in wall
and in process CPU time (the CPU ratio is the fairer one on a machine shared with others).

Usage: `python benchmarks/bench_bidirectional.py [--quick]`; prints and returns a dict.
"""

import argparse
import json
import math
import pathlib
import platform
import sys
import time

import jax
import jax.numpy as jnp
import numpy as np

from teflon_jax.bearing import paper_bearing
from teflon_jax.excitation import StochasticGroundMotion, sample, uniform_signal
from teflon_jax.structures import superstructure_matrices
from teflon_jax.systems import (
    rigid_mass,
    simulate_history,
    six_storey_building,
)
from teflon_jax.tables import interface_parameters, load_table2
from teflon_jax.units import INCH, PSI, STANDARD_GRAVITY

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))

RECORD_STEP = 0.01
TIME_STEP = 0.0025
PERIOD = 2.5
REPEATS = 2
WEIGHT = 1.0e5


def _bearing():
    params, b = interface_parameters("UF", 1000 * PSI)
    return params, b, paper_bearing(params, breakaway_ratio=b)


def _pairs(n, duration):
    motion = StochasticGroundMotion(peak_ground_acceleration=0.3 * STANDARD_GRAVITY, duration=duration,
                                    time_step=RECORD_STEP, rise_time=2.0,
                                    strong_motion_duration=min(10.0, 0.5 * duration))
    acc = np.asarray(sample(motion, jax.random.PRNGKey(6), 2 * n))
    return acc[:n], acc[n:]


def _peak_function(kind, bidirectional, duration):
    _, _, bearing = _bearing()

    def one(ax, ay):
        gx, gy = uniform_signal(ax, RECORD_STEP), uniform_signal(ay, RECORD_STEP)
        if bidirectional:
            if kind == "rigid":
                s = rigid_mass(components=2, weight=WEIGHT, bearing=bearing, ground_acceleration=gx, ground_y=gy,
                                             time_step=TIME_STEP, isolation_period=PERIOD, damping_ratio=0.05)
            else:
                s = six_storey_building(components=2, bearing=bearing, ground_acceleration=gx, ground_y=gy, time_step=TIME_STEP,
                                           isolation_period=PERIOD)
            r = simulate_history(s, duration, throw=False)
            n = s.mass.shape[0] // 2
            return jnp.max(jnp.hypot(r.displacement[:, 0], r.displacement[:, n])), r.result._value
        if kind == "rigid":
            s = rigid_mass(weight=WEIGHT, bearing=bearing, ground_acceleration=gx, time_step=TIME_STEP,
                           isolation_period=PERIOD, damping_ratio=0.05)
        else:
            s = six_storey_building(bearing=bearing, ground_acceleration=gx, time_step=TIME_STEP,
                                    isolation_period=PERIOD)
        r = simulate_history(s, duration, throw=False)
        return jnp.max(jnp.abs(r.displacement[:, 0])), r.result._value

    return jax.jit(jax.vmap(one))


def _rate(kind, bidirectional, ax, ay, duration):
    fn = _peak_function(kind, bidirectional, duration)
    start = time.perf_counter()
    jax.block_until_ready(fn(ax, ay))
    compile_s = time.perf_counter() - start
    best, best_cpu = math.inf, math.inf
    for _ in range(REPEATS):
        start, start_cpu = time.perf_counter(), time.process_time()
        peaks, results = jax.block_until_ready(fn(ax, ay))
        best = min(best, time.perf_counter() - start)
        best_cpu = min(best_cpu, time.process_time() - start_cpu)
    return {"records_per_s": ax.shape[0] / best, "run_s": best, "cpu_s": best_cpu,
            "records_per_cpu_s": ax.shape[0] / best_cpu, "compile_and_first_run_s": compile_s,
            "failed": int(np.sum(np.asarray(results) != 0)), "peaks_m": np.asarray(peaks).tolist()}


def opensees_rigid_mass_3d(ax, ay, dt, *, weight, f_max, delta_f, rate_a, yield_disp, period, damping_ratio,
                           time_step):
    """Rigid mass on a 3D `flatSliderBearing` (VelDependent friction, elastic-perfectly-plastic
    slider with initial stiffness f_min W / Y, circular interaction of the two shear
    components) with springs and dampers in x and y; both components as UniformExcitation.

    **Returns:** (peak resultant displacement [m], peak resultant base shear ratio [-], wall [s])."""
    from _opensees_models import (
        import_opensees,  # beside this file; preloads the wheel's BLAS
    )

    ops = import_opensees()
    m = weight / STANDARD_GRAVITY
    k = m * (2 * math.pi / period) ** 2
    c = 2 * damping_ratio * math.sqrt(k * m)
    f_min = f_max - delta_f
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    ops.node(1, 0.0, 0.0, 0.0)
    ops.node(2, 0.0, 0.0, 0.0)
    ops.fix(1, 1, 1, 1, 1, 1, 1)
    ops.fix(2, 0, 0, 0, 1, 1, 1)
    ops.mass(2, m, m, m, 0.0, 0.0, 0.0)
    ops.frictionModel("VelDependent", 1, f_min, f_max, rate_a)
    ops.uniaxialMaterial("Elastic", 1, 1.0e3 * weight / yield_disp)
    ops.uniaxialMaterial("Elastic", 2, 1.0)
    ops.element("flatSliderBearing", 1, 1, 2, 1, f_min * weight / yield_disp, "-P", 1, "-T", 2, "-My", 2,
                "-Mz", 2, "-orient", 0.0, 0.0, 1.0, 1.0, 0.0, 0.0)
    ops.uniaxialMaterial("Elastic", 3, k)
    ops.uniaxialMaterial("Viscous", 4, c, 1.0)
    ops.element("zeroLength", 2, 1, 2, "-mat", 3, 3, "-dir", 1, 2)
    ops.element("zeroLength", 3, 1, 2, "-mat", 4, 4, "-dir", 1, 2)
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(2, 0.0, 0.0, -weight, 0.0, 0.0, 0.0)
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", 1e-12, 50)
    ops.algorithm("Newton")
    ops.integrator("LoadControl", 1.0)
    ops.analysis("Static")
    if ops.analyze(1) != 0:
        raise RuntimeError("OpenSees: gravity step did not converge.")
    ops.loadConst("-time", 0.0)
    ops.wipeAnalysis()
    for tag, values in ((2, ax), (3, ay)):
        ops.timeSeries("Path", tag, "-dt", float(dt), "-values", *np.append(values, values[-1]).tolist())
    ops.pattern("UniformExcitation", 2, 1, "-accel", 2)
    ops.pattern("UniformExcitation", 3, 2, "-accel", 3)
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", 1e-10, 50)
    ops.algorithm("ModifiedNewton", "-initial")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    n_steps = int(round((len(ax) - 1) * dt / time_step))
    disp, shear = 0.0, 0.0
    start = time.perf_counter()
    for i in range(n_steps):
        if ops.analyze(1, time_step) != 0:
            ops.algorithm("Newton")
            if ops.analyze(1, time_step) != 0:
                raise RuntimeError(f"OpenSees: step {i} did not converge.")
            ops.algorithm("ModifiedNewton", "-initial")
        t = (i + 1) * time_step
        ux, uy = ops.nodeDisp(2, 1), ops.nodeDisp(2, 2)
        gx, gy = np.interp(t, dt * np.arange(len(ax)), ax), np.interp(t, dt * np.arange(len(ay)), ay)
        tx, ty = ops.nodeAccel(2, 1) + gx, ops.nodeAccel(2, 2) + gy
        disp = max(disp, math.hypot(ux, uy))
        shear = max(shear, m * math.hypot(tx, ty) / weight)
    wall = time.perf_counter() - start
    ops.wipe()
    return disp, shear, wall


def _slider_3d(ops, tag, i_node, j_node, *, f_max, delta_f, rate_a, yield_disp, normal_load):
    """3D `flatSliderBearing` from i_node (ground) to j_node: local x (axial) = global Z,
    shear in global X and Y, VelDependent friction, k_init = f_min W / Y, rigid axially
    (shortens by Y / 1000 under W); rotations are fixed at both nodes."""
    f_min = f_max - delta_f
    ops.frictionModel("VelDependent", tag, f_min, f_max, rate_a)
    ops.uniaxialMaterial("Elastic", tag, 1.0e3 * normal_load / yield_disp)
    ops.uniaxialMaterial("Elastic", tag + 1, 1.0)
    ops.element("flatSliderBearing", tag, i_node, j_node, tag, f_min * normal_load / yield_disp,
                "-P", tag, "-T", tag + 1, "-My", tag + 1, "-Mz", tag + 1,
                "-orient", 0.0, 0.0, 1.0, 1.0, 0.0, 0.0)


def opensees_building_3d(ax, ay, dt, *, f_max, delta_f, rate_a, yield_disp, period, damping_ratio, time_step,
                         histories=False):
    """The Table 2 building in 3D on one `flatSliderBearing` (VelDependent friction, elastic-
    perfectly-plastic with a circular slip surface, k_init = f_min W / Y) carrying the total
    weight W, with rubber springs of period T_b and a dashpot of ratio zeta_b in x and y;
    both components as UniformExcitation.

    The superstructure is the one teflon-jax builds (`six_storey_building` in x and in y):
    floor masses, fixed-base stiffness K_s and classically damped C_s (2 % in every mode) of
    `superstructure_matrices(load_table2())`, reproduced exactly in each direction by
    `zeroLength` elements between floors and from each floor to the base: -K_ij, -C_ij
    between floors i and j, row sums sum_j K_ij, sum_j C_ij from floor i to the base (an
    `Elastic` material with stiffness and damping coefficient, in directions 1 and 2).
    The rubber springs k_b = M_tot (2 pi / T_b)^2 and dashpot c_b = 2 zeta_b (2 pi / T_b) M_tot
    act between ground and base, as in `six_storey_building`; no Rayleigh damping. Floors are
    held vertically; the base carries the vertical (gravity) load W, applied statically first.

    Newmark average acceleration at `time_step` [s] (record `dt` [s] linearly interpolated
    by the Path series), modified Newton with the initial tangent; a step that fails is
    retried as `_opensees_models` does (Newton, Krylov-Newton, line search, ten sub-steps).

    **Returns:** (peak resultant base displacement [m], peak resultant base shear ratio [-],
    wall time of the transient analysis [s]), read after every step: the shear is the total
    horizontal force on the structure above the bearings, |sum_j m_j a_j^total| over base and
    floors, over its weight W. With `histories=True` a fourth item, a dict of the histories
    `time`, `base` (n, 2) [m] and `force_ratio` (n, 2) [-].
    """
    from _opensees_models import _step, import_opensees  # beside this file

    ops = import_opensees()
    data = load_table2()
    floor_masses, k_s, c_s, _ = superstructure_matrices(data)
    base_mass = data.base_weight / STANDARD_GRAVITY
    total_mass = data.total_weight / STANDARD_GRAVITY
    weight = float(data.total_weight)
    omega_b = 2 * math.pi / period
    k_b, c_b = total_mass * omega_b**2, 2 * damping_ratio * omega_b * total_mass
    n = floor_masses.size
    ground, base, floors = 1, 2, [3 + j for j in range(n)]
    masses = np.concatenate([[base_mass], floor_masses])
    tol = 1.0e-6 * yield_disp
    ops.wipe()
    ops.logFile("/dev/null", "-noEcho")
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    for node in (ground, base, *floors):
        ops.node(node, 0.0, 0.0, 0.0)
    ops.fix(ground, 1, 1, 1, 1, 1, 1)
    ops.fix(base, 0, 0, 0, 1, 1, 1)
    ops.mass(base, base_mass, base_mass, 0.0, 0.0, 0.0, 0.0)
    for node, m in zip(floors, floor_masses):
        ops.fix(node, 0, 0, 1, 1, 1, 1)
        ops.mass(node, float(m), float(m), 0.0, 0.0, 0.0, 0.0)
    _slider_3d(ops, 1, ground, base, f_max=f_max, delta_f=delta_f, rate_a=rate_a, yield_disp=yield_disp,
               normal_load=weight)
    links = [(ground, base, k_b, c_b)]
    links += [(base, floors[i], k_s[i].sum(), c_s[i].sum()) for i in range(n)]
    links += [(floors[i], floors[j], -k_s[i, j], -c_s[i, j]) for i in range(n) for j in range(i + 1, n)]
    for tag, (i_node, j_node, k, c) in enumerate(links, start=10):
        ops.uniaxialMaterial("Elastic", tag, float(k), float(c))
        ops.element("zeroLength", tag, i_node, j_node, "-mat", tag, tag, "-dir", 1, 2)
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(base, 0.0, 0.0, -weight, 0.0, 0.0, 0.0)
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", tol, 50)
    ops.algorithm("Newton")
    ops.integrator("LoadControl", 1.0)
    ops.analysis("Static")
    if ops.analyze(1) != 0:
        raise RuntimeError("OpenSees: gravity step did not converge.")
    ops.loadConst("-time", 0.0)
    ops.wipeAnalysis()
    for tag, values in ((2, ax), (3, ay)):
        ops.timeSeries("Path", tag, "-dt", float(dt), "-values", *np.append(values, values[-1]).tolist())
    ops.pattern("UniformExcitation", 2, 1, "-accel", 2)
    ops.pattern("UniformExcitation", 3, 2, "-accel", 3)
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", tol, 50)
    algorithm = ("ModifiedNewton", "-initial")
    ops.algorithm(*algorithm)
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    n_steps = int(round((len(ax) - 1) * dt / time_step))
    times = time_step * np.arange(n_steps + 1)
    record_times = dt * np.arange(len(ax))
    gx, gy = np.interp(times, record_times, ax), np.interp(times, record_times, ay)
    nodes = (base, *floors)
    disp = np.zeros((n_steps + 1, 2))
    force = np.zeros((n_steps + 1, 2))
    counts = {"fallback": 0, "failed": 0}
    start = time.perf_counter()
    for i in range(1, n_steps + 1):
        _step(ops, time_step, tol, algorithm, counts)
        disp[i] = ops.nodeDisp(base, 1), ops.nodeDisp(base, 2)
        force[i] = (sum(m * ops.nodeAccel(node, 1) for m, node in zip(masses, nodes)) + total_mass * gx[i],
                    sum(m * ops.nodeAccel(node, 2) for m, node in zip(masses, nodes)) + total_mass * gy[i])
    wall = time.perf_counter() - start
    ops.wipe()
    if counts["failed"]:
        raise RuntimeError(f"OpenSees: {counts['failed']} steps of the building did not converge.")
    ratio = force / weight
    peaks = (float(np.max(np.hypot(*disp.T))), float(np.max(np.hypot(*ratio.T))), wall)
    if histories:
        return (*peaks, {"time": times, "base": disp, "force_ratio": ratio})
    return peaks


def _peer_function(kind, duration):
    """Our peaks (resultant base displacement [m], resultant base shear ratio [-]) without
    breakaway, read after every step as the OpenSees peers read theirs: jitted, vmapped."""
    params, _, _ = _bearing()
    bearing = paper_bearing(params)  # no breakaway: OpenSees' VelDependent has none

    def one(ax, ay):
        gx, gy = uniform_signal(ax, RECORD_STEP), uniform_signal(ay, RECORD_STEP)
        if kind == "rigid":
            s = rigid_mass(components=2, weight=WEIGHT, bearing=bearing, ground_acceleration=gx, ground_y=gy,
                                         time_step=TIME_STEP, isolation_period=PERIOD, damping_ratio=0.05)
        else:
            s = six_storey_building(components=2, bearing=bearing, ground_acceleration=gx, ground_y=gy, time_step=TIME_STEP,
                                       isolation_period=PERIOD, isolation_damping=0.05)
        r = simulate_history(s, duration, throw=False)
        total = r.total_acceleration
        force = jnp.einsum("tn,n,nd->td", total, s.mass, s.influence)
        weight = jnp.sum(s.mass * s.influence[:, 0]) * STANDARD_GRAVITY
        n = s.mass.shape[0] // 2
        return (jnp.max(jnp.hypot(r.displacement[:, 0], r.displacement[:, n])), jnp.max(jnp.hypot(force[:, 0], force[:, 1])) / weight,
                r.result._value)

    return jax.jit(jax.vmap(one))


def _against_opensees(kind, ax, ay, duration):
    """OpenSees 3D on the pairs (ax, ay), one after the other in this process, and our peaks
    on the same pairs without breakaway; per-record differences (ours / OpenSees - 1) [%]."""
    params, _, _ = _bearing()
    friction = dict(f_max=float(params.f_max), delta_f=float(params.delta_f), rate_a=float(params.rate_a),
                    yield_disp=0.005 * INCH, period=PERIOD, damping_ratio=0.05, time_step=TIME_STEP)
    peer = opensees_rigid_mass_3d if kind == "rigid" else opensees_building_3d
    extra = {"weight": WEIGHT} if kind == "rigid" else {}
    start_cpu = time.process_time()
    runs = [peer(x, y, RECORD_STEP, **friction, **extra) for x, y in zip(ax, ay)]
    cpu = time.process_time() - start_cpu  # model builds included
    disp_os, shear_os, walls = (np.array(v) for v in zip(*runs))
    disp, shear, results = (np.asarray(v) for v in _peer_function(kind, duration)(jnp.asarray(ax), jnp.asarray(ay)))
    return {"records_per_s": len(runs) / walls.sum(), "records_per_cpu_s": len(runs) / cpu,
            "peaks_m": disp_os.tolist(),
            "shear_ratio_peaks": shear_os.tolist(), "ours_no_breakaway_peaks_m": disp.tolist(),
            "ours_no_breakaway_shear_ratio_peaks": shear.tolist(), "ours_failed": int(np.sum(results != 0)),
            "disp_difference_pct": (100 * (disp / disp_os - 1)).tolist(),
            "shear_difference_pct": (100 * (shear / shear_os - 1)).tolist(),
            "note": "OpenSees one record after another in one process; its VelDependent model has no "
                    "breakaway, so the peaks compared are ours without breakaway (the rates above use Table 1's)"}


def run_bidirectional_benchmark(quick: bool) -> dict:
    n, duration = (8, 10.0) if quick else (256, 40.0)  # full: a Monte Carlo chunk per device
    ax, ay = _pairs(n, duration)
    out = {"records": n, "duration_s": duration, "time_step_s": TIME_STEP, "machine": platform.processor()
           or platform.machine(), "jax": jax.__version__, "devices": str(jax.devices())}
    for kind in ("rigid", "building"):
        uni = _rate(kind, False, jnp.asarray(ax), jnp.asarray(ay), duration)
        bi = _rate(kind, True, jnp.asarray(ax), jnp.asarray(ay), duration)
        out[kind] = {"uniaxial": uni, "bidirectional": bi,
                     "bidirectional_over_uniaxial": bi["records_per_s"] / uni["records_per_s"],
                     "bidirectional_over_uniaxial_cpu": bi["records_per_cpu_s"] / uni["records_per_cpu_s"]}
    n_peer = 2 if quick else 8
    for kind in ("rigid", "building"):
        out[kind]["opensees_3d"] = _against_opensees(kind, ax[:n_peer], ay[:n_peer], duration)
    return out


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true")
    jax.config.update("jax_enable_x64", True)  # a script, not library code
    result = run_bidirectional_benchmark(parser.parse_args().quick)
    for kind in ("rigid", "building"):
        r = result[kind]
        for k in ("peaks_m",):
            r["uniaxial"].pop(k)
    print(json.dumps(result, indent=2))
