"""Independent peer models in OpenSees for the benchmarks and the cross-check tests.

Two models, both in SI units (m, N, s, kg) and both driven by a ground acceleration
record sampled at a constant time step:

- `rigid_mass_on_slider`: one rigid mass on a flat sliding bearing, optionally with a
  linear restoring spring and a viscous dashpot (Constantinou, Mokha & Reinhorn 1990,
  Figs. 7-10).
- `building_on_sliders`: the condensed model of the paper's six-storey frame on sliding
  bearings plus linear rubber springs (Constantinou, Mokha & Reinhorn 1990, Fig. 11).

What the OpenSees bearing is, and how it differs from teflon-jax
-----------------------------------------------------------------
The bearing is OpenSees' `flatSliderBearing` element (FlatSliderSimple2d, written by
A. Schellenberg) with the `VelDependent` friction model, whose friction coefficient is

    mu(v) = muFast - (muFast - muSlow) exp(-transRate |v|)

i.e. Eq. 1 of the paper, mu_s = f_max - delta_f exp(-a |v|), with muFast = f_max,
muSlow = f_max - delta_f and transRate = a [s/m] (OpenSees evaluates it with the velocity
in the model's units, here m/s). The shear force follows an elastic-perfectly-plastic law
with initial stiffness k_init and yield force mu(v) N, solved by a return map: the sharp
(Coulomb with elastic stick) limit of the paper's Bouc-Wen law (Eqs. 3-4), not the smooth
Bouc-Wen loop itself. By default k_init = (f_max - delta_f) W / Y, the initial tangent
dF/dU = mu_s(0) W A / Y of the Bouc-Wen law at Z = 0 with A = 1. The element has no
breakaway friction (Eq. 17 of the paper): compare with breakaway_ratio = 1.

The normal load N is applied as a vertical (gravity) load in a static step before the
transient analysis; the element reads its normal force from its axial spring.

Integration: Newmark average acceleration (gamma = 1/2, beta = 1/4) at the record's time
step, optionally subdivided `n_sub` times, with a `NormDispIncr` test at 1e-6 Y. The
default algorithm is modified Newton with the initial (elastic) tangent. Plain Newton
with the element's tangent (k_init while sticking, 0 while sliding, no d mu / dv term)
often cycles between stick and slip at record steps such as 0.02 s: on El Centro the
six-storey model needed a fallback in 39 % of the steps with Newton and in none with
modified Newton (Newton and others stay available through `algorithm=`). A step that
fails is retried with Newton, KrylovNewton, NewtonLineSearch and modified Newton, then
with ten sub-steps; only if all of these fail is it forced through with a fixed number of
iterations and counted in `n_failed`. `n_fallback` counts the steps that needed a retry.

Accuracy: stick-slip needs short steps. On El Centro (0.02 s), peak base displacement of
the six-storey model changed by 6 % from n_sub = 1 to 32 and by 0.2 % from 8 to 32; the
rigid mass changed by 16 % and 0.8 %. Use n_sub >= 8 at 0.02 s for percent-level answers.

OpenSees keeps one global model per process: these functions `wipe()` it on entry and
are not thread-safe. The wall time of the transient analysis (`wall_s`) is reported apart
from the time to build the model and apply gravity (`build_s`).
"""

import ctypes
import importlib
import importlib.util
import math
import pathlib
import time

import numpy as np

from teflon_jax.units import STANDARD_GRAVITY

# The shared libraries shipped in `openseespylinux/lib`, in dependency order.
_BUNDLED_LIBS = (
    "libquadmath.so.0",
    "libgfortran.so.4",
    "libgomp.so.1",
    "libblas.so.3",
    "liblapack.so.3",
)

_OPENSEES = None
_MAX_ITER = 50  # iterations per step before a fallback is tried


def import_opensees():
    """Import `openseespy.opensees`, preloading the shared libraries bundled with it.

    The Linux wheel of openseespy ships libblas, liblapack, libgfortran, libgomp and
    libquadmath in `openseespylinux/lib` but does not put them on the loader path, so a
    plain import fails unless `LD_LIBRARY_PATH` names that folder. Loading them first with
    `RTLD_GLOBAL` lets the import succeed without environment variables.

    **Returns:** the `openseespy.opensees` module.

    **Raises:** `ImportError` saying what to do when openseespy is missing or cannot be
    loaded.
    """
    global _OPENSEES
    if _OPENSEES is not None:
        return _OPENSEES
    spec = importlib.util.find_spec("openseespylinux")
    lib_dir = (
        pathlib.Path(spec.origin).parent / "lib"
        if spec is not None and spec.origin is not None
        else None
    )
    load_errors = []
    if lib_dir is not None:
        for name in _BUNDLED_LIBS:
            path = lib_dir / name
            if not path.exists():
                continue
            try:
                ctypes.CDLL(str(path), mode=ctypes.RTLD_GLOBAL)
            except OSError as error:  # a system copy may still satisfy the import
                load_errors.append(f"{name}: {error}")
    try:
        module = importlib.import_module("openseespy.opensees")
    except (ImportError, RuntimeError) as error:
        hint = lib_dir if lib_dir is not None else "<site-packages>/openseespylinux/lib"
        details = f"; preloading failed for {'; '.join(load_errors)}" if load_errors else ""
        raise ImportError(
            f"cannot import openseespy ({error}{details}). Install it with "
            "`pip install openseespy` (extra `peer` of teflon-jax); if it is installed, "
            "install the system BLAS/LAPACK with `apt-get install libblas3 liblapack3` "
            f"or set LD_LIBRARY_PATH={hint}."
        ) from error
    _OPENSEES = module
    return module


def _check_record(ground_acc, dt, n_sub):
    acc = np.asarray(ground_acc, dtype=float)
    if acc.ndim != 1 or acc.size < 2:
        raise ValueError(
            f"ground_acc: expected a 1-D array of at least 2 samples [m/s^2], got shape "
            f"{acc.shape}."
        )
    bad = np.flatnonzero(~np.isfinite(acc))
    if bad.size:
        raise ValueError(
            f"ground_acc: sample {bad[0]} is {acc[bad[0]]}; the record must be finite."
        )
    if not (isinstance(dt, (int, float, np.floating)) and math.isfinite(dt) and dt > 0):
        raise ValueError(f"dt: the time step must be a positive number [s], got {dt!r}.")
    if not (isinstance(n_sub, (int, np.integer)) and n_sub >= 1):
        raise ValueError(
            f"n_sub: sub-steps per record step must be an integer >= 1, got {n_sub!r}."
        )
    return acc


def _check_friction(f_max, delta_f, rate_a, yield_disp):
    if not (math.isfinite(f_max) and f_max > 0):
        raise ValueError(f"f_max: must be a positive friction coefficient, got {f_max!r}.")
    if not (math.isfinite(delta_f) and 0 <= delta_f < f_max):
        raise ValueError(
            f"delta_f: must satisfy 0 <= delta_f < f_max = {f_max} (OpenSees needs a "
            f"positive friction at zero velocity, f_max - delta_f > 0), got {delta_f!r}."
        )
    if not (math.isfinite(rate_a) and rate_a >= 0):
        raise ValueError(f"rate_a: must be >= 0 [s/m], got {rate_a!r}.")
    if not (math.isfinite(yield_disp) and yield_disp > 0):
        raise ValueError(f"yield_disp: must be a positive length [m], got {yield_disp!r}.")


def _check_nonnegative(value, name, unit):
    if not (math.isfinite(value) and value >= 0):
        raise ValueError(f"{name}: must be a finite number >= 0 [{unit}], got {value!r}.")


def _add_slider(
    ops, *, tag, i_node, j_node, f_max, delta_f, rate_a, k_init, normal_load, yield_disp
):
    """flatSliderBearing from i_node (ground) to j_node: vertical axis, shear along x."""
    ops.frictionModel("VelDependent", tag, f_max - delta_f, f_max, rate_a)
    # Axial spring: shortens by yield_disp / 1000 under the normal load.
    ops.uniaxialMaterial("Elastic", tag, 1.0e3 * normal_load / yield_disp)
    ops.uniaxialMaterial("Elastic", tag + 1, 1.0)  # rotation: both nodes are fixed in rz
    # -orient: local x (axial) = global Y, local y (shear) = -global X.
    ops.element(
        "flatSliderBearing",
        tag,
        i_node,
        j_node,
        tag,
        k_init,
        "-P",
        tag,
        "-Mz",
        tag + 1,
        "-orient",
        0.0,
        1.0,
        0.0,
        -1.0,
        0.0,
        0.0,
    )


def _initial_stiffness(given, f_min, normal_load, yield_disp):
    """k_init [N/m] of the slider: `given` (checked > 0), or f_min W / Y by default."""
    if given is None:
        return f_min * normal_load / yield_disp
    if not (math.isfinite(given) and given > 0):
        raise ValueError(f"initial_stiffness: must be a positive stiffness [N/m], got {given!r}.")
    return given


def _apply_gravity(ops, node, normal_load, tol):
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(node, 0.0, -normal_load, 0.0)
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", tol, _MAX_ITER)
    ops.algorithm("Newton")
    ops.integrator("LoadControl", 1.0)
    ops.analysis("Static")
    if ops.analyze(1) != 0:
        raise RuntimeError("OpenSees: the static gravity step did not converge.")
    ops.loadConst("-time", 0.0)
    ops.wipeAnalysis()


def _setup_transient(ops, acc, dt, tol, algorithm):
    # One extra sample holds the last value, so that round-off in the accumulated analysis
    # time cannot step past the end of the path (where OpenSees returns 0).
    values = np.append(acc, acc[-1])
    ops.timeSeries("Path", 2, "-dt", float(dt), "-values", *values.tolist())
    ops.pattern("UniformExcitation", 2, 1, "-accel", 2)
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", tol, _MAX_ITER)
    ops.algorithm(*algorithm)
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")


_FALLBACKS = (
    ("Newton",),
    ("KrylovNewton",),
    ("NewtonLineSearch", 0.8),
    ("ModifiedNewton", "-initial"),
)


def _check_algorithm(algorithm):
    if not (isinstance(algorithm, tuple) and algorithm and isinstance(algorithm[0], str)):
        raise ValueError(
            f"algorithm: expected a tuple of OpenSees algorithm arguments such as "
            f"('ModifiedNewton', '-initial') or ('Newton',), got {algorithm!r}."
        )
    return algorithm


def _step(ops, dt_sub, tol, algorithm, counts):
    """Advance one analysis step with fallbacks; update counts['fallback'/'failed']."""
    if ops.analyze(1, dt_sub) == 0:
        return
    counts["fallback"] += 1
    for fallback in _FALLBACKS:
        if fallback == algorithm:
            continue
        ops.algorithm(*fallback)
        ok = ops.analyze(1, dt_sub)
        ops.algorithm(*algorithm)
        if ok == 0:
            return
    failed = False
    for _ in range(10):
        if ops.analyze(1, dt_sub / 10.0) != 0:
            failed = True
            ops.test("FixedNumIter", _MAX_ITER)
            ops.analyze(1, dt_sub / 10.0)
            ops.test("NormDispIncr", tol, _MAX_ITER)
    counts["failed"] += failed


def rigid_mass_on_slider(
    ground_acc,
    dt,
    *,
    weight,
    f_max,
    delta_f,
    rate_a,
    yield_disp,
    spring_stiffness=0.0,
    damping_ratio=0.0,
    initial_stiffness=None,
    n_sub=1,
    algorithm=("ModifiedNewton", "-initial"),
    quiet=True,
):
    """Rigid mass on a velocity-dependent flat slider in OpenSees (independent peer).

    Equation of motion of the mass m = W / g relative to the ground (u = relative
    displacement, a_g = ground acceleration):

        m u'' + c u' + k u + F = -m a_g,   F = friction force of the bearing,

    with |F| <= mu(u') W, mu(v) = f_max - delta_f exp(-a |v|) (paper Eq. 1) and an elastic
    stick branch of stiffness k_init (see the module docstring).

    **Arguments:**

    - `ground_acc`: ground acceleration record a_g [m/s^2], 1-D, sampled every `dt`.
    - `dt`: time step of the record [s]; the analysis step is `dt / n_sub`.
    - `weight`: weight of the mass W [N], also the normal load on the bearing.
    - `f_max`: friction coefficient at large velocity f_max [-].
    - `delta_f`: f_max - f_min, with f_min the friction at zero velocity [-].
    - `rate_a`: rate parameter a of Eq. 1 [s/m].
    - `yield_disp`: Bouc-Wen yield displacement Y [m]; sets k_init (paper: 0.005 in).
    - `spring_stiffness`: linear restoring spring k [N/m] in parallel with the bearing.
    - `damping_ratio`: viscous damping ratio of the spring-mass mode, c = 2 zeta sqrt(k m)
      [-]; needs `spring_stiffness > 0`.
    - `initial_stiffness`: k_init [N/m]; default (f_max - delta_f) W / Y.
    - `n_sub`: analysis sub-steps per record step.
    - `algorithm`: OpenSees solution algorithm for every step, as the arguments of
      `ops.algorithm`; default modified Newton with the initial (elastic) tangent, which
      never cycles between stick and slip (module docstring).
    - `quiet`: send OpenSees' console output to /dev/null.

    **Returns:** a dict with `time` [s] (record grid, starting at 0), `displacement` u [m]
    and `velocity` u' [m/s] relative to the ground, `total_acceleration` u'' + a_g [m/s^2],
    `friction_force` F [N] (positive when it resists positive u, so m (u'' + a_g) =
    -F - k u - c u'), `n_fallback`, `n_failed` (steps), `wall_s` (transient analysis) and
    `build_s` (model and gravity) [s].

    **Reference:** Constantinou, Mokha & Reinhorn (1990), "Teflon bearings in base isolation
    II: Modeling", J. Struct. Eng. 116(2); OpenSees `flatSliderBearing` and
    `frictionModel VelDependent`.
    """
    acc = _check_record(ground_acc, dt, n_sub)
    algorithm = _check_algorithm(algorithm)
    if not (math.isfinite(weight) and weight > 0):
        raise ValueError(f"weight: must be a positive force [N], got {weight!r}.")
    _check_friction(f_max, delta_f, rate_a, yield_disp)
    _check_nonnegative(spring_stiffness, "spring_stiffness", "N/m")
    _check_nonnegative(damping_ratio, "damping_ratio", "-")
    if damping_ratio > 0 and spring_stiffness == 0:
        raise ValueError(
            "damping_ratio: a damping ratio needs a spring (spring_stiffness > 0) to "
            "define "
            "the mode it refers to; set damping_ratio=0 or give spring_stiffness."
        )
    initial_stiffness = _initial_stiffness(initial_stiffness, f_max - delta_f, weight, yield_disp)

    ops = import_opensees()
    mass = weight / STANDARD_GRAVITY
    tol = 1.0e-6 * yield_disp
    t0 = time.perf_counter()
    ops.wipe()
    if quiet:
        ops.logFile("/dev/null", "-noEcho")
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    ops.node(1, 0.0, 0.0)
    ops.node(2, 0.0, 0.0)
    ops.fix(1, 1, 1, 1)
    ops.fix(2, 0, 0, 1)
    ops.mass(2, mass, 0.0, 0.0)
    _add_slider(
        ops,
        tag=1,
        i_node=1,
        j_node=2,
        f_max=f_max,
        delta_f=delta_f,
        rate_a=rate_a,
        k_init=initial_stiffness,
        normal_load=weight,
        yield_disp=yield_disp,
    )
    if spring_stiffness > 0:
        dashpot = 2.0 * damping_ratio * math.sqrt(spring_stiffness * mass)
        ops.uniaxialMaterial("Elastic", 10, spring_stiffness, dashpot)
        ops.element("zeroLength", 10, 1, 2, "-mat", 10, "-dir", 1)
    _apply_gravity(ops, 2, weight, tol)
    _setup_transient(ops, acc, dt, tol, algorithm)
    build_s = time.perf_counter() - t0

    n = acc.size
    out = np.zeros((n, 4))
    counts = {"fallback": 0, "failed": 0}
    dt_sub = dt / n_sub
    t0 = time.perf_counter()
    for k in range(1, n):
        for _ in range(n_sub):
            _step(ops, dt_sub, tol, algorithm, counts)
        out[k] = (
            ops.nodeDisp(2, 1),
            ops.nodeVel(2, 1),
            ops.nodeAccel(2, 1),
            ops.eleResponse(1, "force")[3],
        )
    wall_s = time.perf_counter() - t0
    ops.wipe()
    return {
        "time": dt * np.arange(n),
        "displacement": out[:, 0],
        "velocity": out[:, 1],
        "total_acceleration": out[:, 2] + acc,
        "friction_force": out[:, 3],
        "n_fallback": counts["fallback"],
        "n_failed": counts["failed"],
        "wall_s": wall_s,
        "build_s": build_s,
    }


def _check_square(matrix, name, n, unit):
    arr = np.asarray(matrix, dtype=float)
    if arr.shape != (n, n):
        raise ValueError(
            f"{name}: expected a ({n}, {n}) matrix [{unit}] (one row per floor), got shape "
            f"{arr.shape}."
        )
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name}: contains non-finite entries.")
    scale = max(np.max(np.abs(arr)), np.finfo(float).tiny)
    if np.max(np.abs(arr - arr.T)) > 1e-9 * scale:
        raise ValueError(f"{name}: must be symmetric; symmetrise it, e.g. (K + K.T) / 2.")
    return arr


def building_on_sliders(
    ground_acc,
    dt,
    *,
    floor_masses,
    stiffness,
    damping,
    base_mass,
    f_max,
    delta_f,
    rate_a,
    yield_disp,
    rubber_stiffness,
    rubber_damping_ratio=0.05,
    normal_load=None,
    initial_stiffness=None,
    n_sub=1,
    algorithm=("ModifiedNewton", "-initial"),
    quiet=True,
    slider=True,
):
    """Condensed multi-storey building on flat sliders and rubber springs in OpenSees.

    With `slider=False` the bearings are left out: the linear isolation system of Fig. 11
    (rubber springs and dashpot only; the base is then held vertically).

    Equations of motion (u_b = base displacement relative to the ground, u = floor
    displacements relative to the base, r = vector of ones):

        M u'' + C u' + K u = -M r (u_b'' + a_g)
        m_b u_b'' + c_b u_b' + K_b u_b + F = -m_b a_g + r^T (C u' + K u)

    i.e. the superstructure's fixed-base stiffness K and damping C (condensed lateral
    matrices, supplied by the caller), the base mass m_b, the rubber springs K_b with
    dashpot c_b = 2 zeta_b sqrt(K_b M_tot) (damping ratio zeta_b in the rigid-body mode,
    M_tot = m_b + sum(M)), and the sliding bearings' friction force F (module docstring).

    The full K and C are reproduced exactly, not approximated by a shear building: each
    off-diagonal entry K_ij becomes a `zeroLength` spring of stiffness -K_ij between
    floors i and j, and each row sum sum_j K_ij a spring from floor i to the base (these
    may be negative; OpenSees' Elastic material accepts that). C is split the same way
    into the damping coefficients `eta` of the same Elastic materials. All nodes share
    one location; floors move in x only, the base also moves vertically so that the
    bearing carries the normal load. Rayleigh damping is not used.

    **Arguments:**

    - `ground_acc`, `dt`, `n_sub`, `quiet`, `f_max`, `delta_f`, `rate_a`, `yield_disp`,
      `initial_stiffness`, `algorithm`: as in `rigid_mass_on_slider`.
    - `floor_masses`: masses of the floors above the base [kg], shape (n,).
    - `stiffness`: fixed-base lateral stiffness K [N/m], shape (n, n), symmetric.
    - `damping`: fixed-base damping matrix C [N s/m], shape (n, n), symmetric.
    - `base_mass`: mass of the base slab m_b [kg].
    - `rubber_stiffness`: total lateral stiffness of the rubber springs K_b [N/m] (they
      carry no vertical load); T_b = 2 pi sqrt(M_tot / K_b).
    - `rubber_damping_ratio`: viscous damping ratio zeta_b of the rigid-body mode [-]
      (no dashpot when K_b = 0, where that mode is not defined).
    - `normal_load`: total normal load on the bearings W [N]; default g M_tot.

    **Returns:** a dict with `time` [s]; `base_displacement`, `base_velocity` (relative to
    the ground) [m, m/s]; `base_total_acceleration` [m/s^2]; `floor_displacement`
    (relative to the base) [m] and `floor_total_acceleration` [m/s^2], shape (N, n);
    `base_shear` = sum_j m_j (total acceleration of floor j) [N], the first-storey shear;
    `friction_force` [N] (sign as in `rigid_mass_on_slider`); `n_fallback`, `n_failed`,
    `wall_s`, `build_s`.

    **Reference:** Constantinou, Mokha & Reinhorn (1990), J. Struct. Eng. 116(2), Fig. 11.
    """
    acc = _check_record(ground_acc, dt, n_sub)
    algorithm = _check_algorithm(algorithm)
    masses = np.asarray(floor_masses, dtype=float)
    if (
        masses.ndim != 1
        or masses.size < 1
        or not np.all(np.isfinite(masses))
        or np.any(masses <= 0)
    ):
        raise ValueError(
            "floor_masses: expected a 1-D array of positive masses [kg], got "
            f"{floor_masses!r}."
        )
    n = masses.size
    k_s = _check_square(stiffness, "stiffness", n, "N/m")
    c_s = _check_square(damping, "damping", n, "N s/m")
    if not (math.isfinite(base_mass) and base_mass > 0):
        raise ValueError(f"base_mass: must be a positive mass [kg], got {base_mass!r}.")
    _check_friction(f_max, delta_f, rate_a, yield_disp)
    _check_nonnegative(rubber_stiffness, "rubber_stiffness", "N/m")
    _check_nonnegative(rubber_damping_ratio, "rubber_damping_ratio", "-")
    total_mass = base_mass + masses.sum()
    if normal_load is None:
        normal_load = STANDARD_GRAVITY * total_mass
    elif not (math.isfinite(normal_load) and normal_load > 0):
        raise ValueError(f"normal_load: must be a positive force [N], got {normal_load!r}.")
    initial_stiffness = _initial_stiffness(initial_stiffness, f_max - delta_f, normal_load, yield_disp)

    ops = import_opensees()
    tol = 1.0e-6 * yield_disp
    ground, base = 1, 2
    floors = [3 + j for j in range(n)]
    t0 = time.perf_counter()
    ops.wipe()
    if quiet:
        ops.logFile("/dev/null", "-noEcho")
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    for node in (ground, base, *floors):
        ops.node(node, 0.0, 0.0)
    ops.fix(ground, 1, 1, 1)
    ops.fix(base, 0, 0 if slider else 1, 1)
    ops.mass(base, base_mass, 0.0, 0.0)
    for node, m in zip(floors, masses):
        ops.fix(node, 0, 1, 1)
        ops.mass(node, float(m), 0.0, 0.0)
    if slider:
        _add_slider(
        ops,
            tag=1,
            i_node=ground,
            j_node=base,
            f_max=f_max,
            delta_f=delta_f,
            rate_a=rate_a,
            k_init=initial_stiffness,
            normal_load=normal_load,
            yield_disp=yield_disp,
        )
    tag = 10
    if rubber_stiffness > 0:
        c_b = 2.0 * rubber_damping_ratio * math.sqrt(rubber_stiffness * total_mass)
        ops.uniaxialMaterial("Elastic", tag, float(rubber_stiffness), c_b)
        ops.element("zeroLength", tag, ground, base, "-mat", tag, "-dir", 1)
        tag += 1
    pairs = [(floors[i], base, k_s[i].sum(), c_s[i].sum()) for i in range(n)]
    pairs += [
        (floors[i], floors[j], -k_s[i, j], -c_s[i, j])
        for i in range(n)
        for j in range(i + 1, n)
    ]
    for i_node, j_node, k_ij, c_ij in pairs:
        if k_ij == 0 and c_ij == 0:
            continue
        ops.uniaxialMaterial("Elastic", tag, float(k_ij), float(c_ij))
        ops.element("zeroLength", tag, i_node, j_node, "-mat", tag, "-dir", 1)
        tag += 1
    if slider:
        _apply_gravity(ops, base, normal_load, tol)
    _setup_transient(ops, acc, dt, tol, algorithm)
    build_s = time.perf_counter() - t0

    n_rec = acc.size
    base_out = np.zeros((n_rec, 4))
    floor_disp = np.zeros((n_rec, n))
    floor_acc = np.zeros((n_rec, n))
    counts = {"fallback": 0, "failed": 0}
    dt_sub = dt / n_sub
    t0 = time.perf_counter()
    for k in range(1, n_rec):
        for _ in range(n_sub):
            _step(ops, dt_sub, tol, algorithm, counts)
        base_out[k] = (
            ops.nodeDisp(base, 1),
            ops.nodeVel(base, 1),
            ops.nodeAccel(base, 1),
            ops.eleResponse(1, "force")[3] if slider else 0.0,
        )
        floor_disp[k] = [ops.nodeDisp(node, 1) for node in floors]
        floor_acc[k] = [ops.nodeAccel(node, 1) for node in floors]
    wall_s = time.perf_counter() - t0
    ops.wipe()
    floor_total_acc = floor_acc + acc[:, None]
    return {
        "time": dt * np.arange(n_rec),
        "base_displacement": base_out[:, 0],
        "base_velocity": base_out[:, 1],
        "base_total_acceleration": base_out[:, 2] + acc,
        "floor_displacement": floor_disp - base_out[:, :1],
        "floor_total_acceleration": floor_total_acc,
        "base_shear": floor_total_acc @ masses,
        "friction_force": base_out[:, 3],
        "n_fallback": counts["fallback"],
        "n_failed": counts["failed"],
        "wall_s": wall_s,
        "build_s": build_s,
    }
