"""A rigid mass on OpenSees' `singleFPBearing`: the independent peer of the friction pendulum.

The element (SingleFPSimple2d / 3d, A. Schellenberg) is a slider on a spherical surface of
effective radius R in the small-rotation form: its shear force is the restoring force N u / R
plus an elastic-perfectly-plastic friction force of initial stiffness k_init and yield force
mu N, with a circular interaction of the two shear components in 3D. Its friction model is
`Coulomb` (constant mu) or `VelDependent`, mu = muFast - (muFast - muSlow) exp(-transRate |v|),
Eq. 1 of Constantinou, Mokha & Reinhorn (1990) at constant pressure with f_max = muFast,
delta_f = muFast - muSlow and a = transRate [s/m]. The normal load N is the weight, applied in
a static step before the transient analysis (Newmark average acceleration at `time_step`).
SI units (m, N, s, kg). Reference: Zayas, Low & Mahin (1990); OpenSees `singleFPBearing`.
"""

import math
import time

import numpy as np
from _opensees_models import import_opensees

from teflon_jax.units import STANDARD_GRAVITY

ALGORITHM = ("ModifiedNewton", "-initial")
"""The transient analysis' algorithm: modified Newton with the initial (elastic) tangent, which
does not cycle between stick and slip (`_opensees_models`); a failed step is retried with
Newton, then in ten sub-steps."""


def _friction(ops, mu_slow, mu_fast, rate):
    if mu_slow == mu_fast:
        ops.frictionModel("Coulomb", 1, mu_slow)
    else:
        ops.frictionModel("VelDependent", 1, mu_slow, mu_fast, rate)


def _gravity(ops, load):
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(2, *load)
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", 1e-12, 50)
    ops.algorithm("Newton")
    ops.integrator("LoadControl", 1.0)
    ops.analysis("Static")
    if ops.analyze(1) != 0:
        raise RuntimeError("OpenSees: the gravity step did not converge.")
    ops.loadConst("-time", 0.0)
    ops.wipeAnalysis()


def _retried(ops, time_step):
    """A step that failed, retried with Newton, then in ten sub-steps."""
    ops.algorithm("Newton")
    ok = ops.analyze(1, time_step) == 0 or all(ops.analyze(1, time_step / 10) == 0 for _ in range(10))
    ops.algorithm(*ALGORITHM)
    return ok


def rigid_mass_on_pendulum(ax, dt, *, weight, radius, mu_slow, mu_fast=None, rate=0.0, yield_disp,
                           time_step, ay=None):
    """Peaks of a rigid mass W / g on one `singleFPBearing` of effective radius `radius` [m]
    under the ground acceleration `ax` [m/s^2] (2D model) or (`ax`, `ay`) (3D), both sampled
    every `dt` [s]: friction mu_slow..mu_fast [-] with `rate` [s/m] (Coulomb when equal),
    k_init = mu_slow W / `yield_disp` [m].

    **Returns:** (peak resultant displacement [m], peak resultant base shear ratio
    |m a_total| / W [-], wall time of the transient analysis [s])."""
    ops = import_opensees()
    mu_fast = mu_slow if mu_fast is None else mu_fast
    mass, k_init = weight / STANDARD_GRAVITY, mu_slow * weight / yield_disp
    three = ay is not None
    ops.wipe()
    ops.logFile("/dev/null", "-noEcho")
    if three:
        ops.model("basic", "-ndm", 3, "-ndf", 6)
        ops.node(1, 0.0, 0.0, 0.0)
        ops.node(2, 0.0, 0.0, 0.0)
        ops.fix(1, 1, 1, 1, 1, 1, 1)
        ops.fix(2, 0, 0, 0, 1, 1, 1)
        ops.mass(2, mass, mass, 0.0, 0.0, 0.0, 0.0)
    else:
        ops.model("basic", "-ndm", 2, "-ndf", 3)
        ops.node(1, 0.0, 0.0)
        ops.node(2, 0.0, 0.0)
        ops.fix(1, 1, 1, 1)
        ops.fix(2, 0, 0, 1)
        ops.mass(2, mass, 0.0, 0.0)
    _friction(ops, mu_slow, mu_fast, rate)
    ops.uniaxialMaterial("Elastic", 1, 1.0e3 * weight / yield_disp)  # axial: nearly rigid
    ops.uniaxialMaterial("Elastic", 2, 1.0)  # rotations: both nodes fixed
    if three:  # local x (axial) = global Z, local y = global X
        ops.element("singleFPBearing", 1, 1, 2, 1, radius, k_init, "-P", 1, "-T", 2, "-My", 2, "-Mz", 2,
                    "-orient", 0.0, 0.0, 1.0, 1.0, 0.0, 0.0)
        _gravity(ops, (0.0, 0.0, -weight, 0.0, 0.0, 0.0))
    else:  # local x (axial) = global Y, local y (shear) = -global X
        ops.element("singleFPBearing", 1, 1, 2, 1, radius, k_init, "-P", 1, "-Mz", 2,
                    "-orient", 0.0, 1.0, 0.0, -1.0, 0.0, 0.0)
        _gravity(ops, (0.0, -weight, 0.0))
    components = (ax,) if not three else (ax, ay)
    for tag, values in enumerate(components, start=2):
        ops.timeSeries("Path", tag, "-dt", float(dt), "-values", *np.append(values, values[-1]).tolist())
        ops.pattern("UniformExcitation", tag, tag - 1, "-accel", tag)
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", 1e-6 * yield_disp, 50)
    ops.algorithm(*ALGORITHM)
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    n_steps = int(round((len(ax) - 1) * dt / time_step))
    record_times = dt * np.arange(len(ax))
    disp = shear = 0.0
    start = time.perf_counter()
    for i in range(n_steps):
        if ops.analyze(1, time_step) != 0 and not _retried(ops, time_step):
            raise RuntimeError(f"OpenSees: step {i} did not converge.")
        t = (i + 1) * time_step
        u = [ops.nodeDisp(2, d) for d in range(1, len(components) + 1)]
        total = [ops.nodeAccel(2, d + 1) + np.interp(t, record_times, c) for d, c in enumerate(components)]
        disp = max(disp, math.hypot(*u))
        shear = max(shear, mass * math.hypot(*total) / weight)
    wall = time.perf_counter() - start
    ops.wipe()
    return disp, shear, wall
