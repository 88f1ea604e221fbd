"""The rigid mass and the Table 2 building on OpenSees' `TripleFrictionPendulum` element, in one
horizontal direction: the independent peer of teflon-jax's triple friction pendulum.

The element (N. Dao, University of Nevada, Reno; OpenSees `TripleFrictionPendulum`) is the
series model of Fenz & Constantinou (2008) as three elastic-plastic sliders with kinematic
hardening: the inner pair (effective radius 2 L1), and the two outer surfaces (L2 - L1,
L3 - L1), each with its friction model (`Coulomb`, or `VelDependent`: mu = muFast - (muFast -
muSlow) exp(-transRate |v|), Eq. 1 with f_max = muFast, delta_f = muFast - muSlow, a =
transRate [s/m]) at the surface's velocity, the slider's mean velocity over the step times
0.5, L2 / (L2 - L1), L3 / (L3 - L1), taken from its previous iteration. Every slider sticks with
the stiffness 3 mu_1 W / uy (mu_1 the inner pair's friction at rest), where teflon-jax's
Bouc-Wen sliders have mu_e W / Y and a rounded corner. Its inner slider's travel is
2 (d_1 + L1 d_3 / L3) (the top surface's), where teflon-jax takes the smaller of the outer
surfaces' d / R: the peers agree up to the inner ring when d_bottom / b = d_top / c.

The normal load is the weight W on an axial spring (stiff), applied statically first; the
transient analysis is Newmark's average acceleration at `time_step`, the record interpolated
linearly (Path series), modified Newton with the initial tangent (a failed step retried as
`_opensees_models._step` does). SI units (m, N, s, kg). The building is the Table 2 frame of
`six_storey_building` (floors as `zeroLength` springs and dashpots reproducing K_s and C_s),
with no spring or dashpot at the isolator.
"""

import time

import numpy as np
from _opensees_models import _step, import_opensees

from teflon_jax.structures import superstructure_matrices
from teflon_jax.tables import load_table2
from teflon_jax.units import STANDARD_GRAVITY


def triple_values(bearing) -> dict:
    """The element's constants of a teflon-jax `TriplePendulum`: L1, L2, L3 [m] (inner,
    bottom, top effective radii), d1, d2, d3 [m] (capacities), and per surface (f_max,
    delta_f, rate_a)."""
    def friction(f):
        return tuple(float(np.asarray(getattr(f, k))) for k in ("f_max", "delta_f", "rate_a"))

    return {"L": tuple(float(np.asarray(x)) for x in (bearing.inner_radius, bearing.bottom_radius,
                                                      bearing.top_radius)),
            "d": tuple(float(np.asarray(x)) for x in (bearing.inner_capacity, bearing.bottom_capacity,
                                                      bearing.top_capacity)),
            "friction": tuple(friction(f) for f in (bearing.inner_friction, bearing.bottom_friction,
                                                    bearing.top_friction))}


def _element(ops, values, weight, uy):
    """The bearing from node 1 (ground) to node 2 (base), its friction models 1-3 and its
    materials 1 (axial: W shortens it by uy / 1000) and 2 (rotations)."""
    for tag, (f_max, delta_f, rate) in enumerate(values["friction"], start=1):
        if delta_f == 0:
            ops.frictionModel("Coulomb", tag, f_max)
        else:
            ops.frictionModel("VelDependent", tag, f_max - delta_f, f_max, rate)
    ops.uniaxialMaterial("Elastic", 1, 1.0e3 * weight / uy)
    ops.uniaxialMaterial("Elastic", 2, 1.0)
    ops.element("TripleFrictionPendulum", 1, 1, 2, 1, 2, 3, 1, 2, 2, 2, *values["L"], *values["d"],
                weight, uy, 1.0, 1.0e-3 * weight, 1.0e-8)


def _gravity(ops, weight, tol):
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(2, 0.0, 0.0, -weight, 0.0, 0.0, 0.0)
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", tol, 50)
    ops.algorithm("Newton")
    ops.integrator("LoadControl", 1.0)
    ops.analysis("Static")
    if ops.analyze(1) != 0:
        raise RuntimeError("OpenSees: the gravity step did not converge.")
    ops.loadConst("-time", 0.0)
    ops.wipeAnalysis()


def _building(ops, two):
    """Floors 3.. above the base node 2 (Table 2, along x, and y when `two`): (masses of base
    and floors, nodes, total weight)."""
    data = load_table2()
    floor_masses, k_s, c_s, _ = superstructure_matrices(data)
    floors = [3 + j for j in range(floor_masses.size)]
    for node, m in zip(floors, floor_masses):
        ops.node(node, 0.0, 0.0, 0.0)
        ops.fix(node, 0, 0 if two else 1, 1, 1, 1, 1)
        ops.mass(node, float(m), float(m) if two else 0.0, 0.0, 0.0, 0.0, 0.0)
    n = floor_masses.size
    links = [(2, floors[i], k_s[i].sum(), c_s[i].sum()) for i in range(n)]
    links += [(floors[i], floors[j], -k_s[i, j], -c_s[i, j]) for i in range(n) for j in range(i + 1, n)]
    for tag, (i_node, j_node, k, c) in enumerate(links, start=10):
        ops.uniaxialMaterial("Elastic", tag, float(k), float(c))
        if two:
            ops.element("zeroLength", tag, i_node, j_node, "-mat", tag, tag, "-dir", 1, 2)
        else:
            ops.element("zeroLength", tag, i_node, j_node, "-mat", tag, "-dir", 1)
    masses = np.concatenate([[data.base_weight / STANDARD_GRAVITY], floor_masses])
    return masses, [2, *floors], float(data.total_weight)


def opensees_triple_structure(kind, acc, dt, values, *, uy, time_step, weight=1.0e6, histories=False, acc_y=None):
    """Peaks of the rigid mass of `weight` [N] ("rigid") or the Table 2 building ("building")
    on one `TripleFrictionPendulum` of `values` (`triple_values`) under the ground acceleration
    `acc` [m/s^2] sampled every `dt` [s], along x.

    **Returns:** (peak |base displacement| [m], peak |base shear| over the weight above the
    isolator [-]: m a_total / W for the rigid mass, the floors' inertia force over their weight
    (the first-storey shear) for the building, wall time of the transient analysis [s]); with
    `histories=True` also a dict of `time`, `base`, `shear`. With `acc_y` (the y component,
    same samples) both directions: resultant peaks, the shear as the resultant force on all
    masses above the ground (base slab included) over their weight W (as
    `teflon_jax.studies.peak_response` reads it)."""
    two = acc_y is not None
    ops = import_opensees()
    ops.wipe()
    ops.logFile("/dev/null", "-noEcho")
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    ops.node(1, 0.0, 0.0, 0.0)
    ops.node(2, 0.0, 0.0, 0.0)
    ops.fix(1, 1, 1, 1, 1, 1, 1)
    ops.fix(2, 0, 0 if two else 1, 0, 1, 1, 1)
    if kind == "rigid":
        masses, nodes, above = np.array([weight / STANDARD_GRAVITY]), [2], slice(0, 1)
    else:
        masses, nodes, weight = _building(ops, two)
        above = slice(0 if two else 1, None)
    ops.mass(2, float(masses[0]), float(masses[0]) if two else 0.0, 0.0, 0.0, 0.0, 0.0)
    _element(ops, values, weight, uy)
    tol = 1.0e-4 * uy
    _gravity(ops, weight, tol)
    ops.timeSeries("Path", 2, "-dt", float(dt), "-values", *np.append(acc, acc[-1]).tolist())
    ops.pattern("UniformExcitation", 2, 1, "-accel", 2)
    if two:
        ops.timeSeries("Path", 3, "-dt", float(dt), "-values", *np.append(acc_y, acc_y[-1]).tolist())
        ops.pattern("UniformExcitation", 3, 2, "-accel", 3)
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", tol, 50)
    algorithm = ("ModifiedNewton", "-initial")
    ops.algorithm(*algorithm)
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    n_steps = int(round((len(acc) - 1) * dt / time_step))
    times = time_step * np.arange(n_steps + 1)
    record_times = dt * np.arange(len(acc))
    grounds = [np.interp(times, record_times, a) for a in ((acc, acc_y) if two else (acc,))]
    base, shear = np.zeros((n_steps + 1, len(grounds))), np.zeros((n_steps + 1, len(grounds)))
    weight_above = float(masses[above].sum()) * STANDARD_GRAVITY
    counts = {"fallback": 0, "failed": 0}
    start = time.perf_counter()
    for i in range(1, n_steps + 1):
        _step(ops, time_step, tol, algorithm, counts)
        for k, ground in enumerate(grounds):
            base[i, k] = ops.nodeDisp(2, k + 1)
            total = np.array([ops.nodeAccel(node, k + 1) for node in nodes]) + ground[i]
            shear[i, k] = float(masses[above] @ total[above]) / weight_above
    wall = time.perf_counter() - start
    ops.wipe()
    if counts["failed"]:
        raise RuntimeError(f"OpenSees: {counts['failed']} steps did not converge.")
    peaks = (float(np.max(np.linalg.norm(base, axis=1))), float(np.max(np.linalg.norm(shear, axis=1))), wall)
    if histories:
        return (*peaks, {"time": times, "base": base, "shear": shear})
    return peaks
