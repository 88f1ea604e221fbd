"""The implicit derivative of every engine's balance, checked two ways: values, reverse- and
forward-mode derivatives and central differences (steps 1e-5 and 2e-5 relative) of each engine's
response in a friction parameter and a design variable, written to a file, and two such files
(two versions of the code) compared entry by entry.

    PYTHONPATH=TREE python benchmarks/implicit_gradients.py dump OUT.npz [case ...]
    python benchmarks/implicit_gradients.py compare OLD.npz NEW.npz

Newton's tolerance is 0 (flat engine) or 1e-13 (series engines): at the default tolerances a
central difference sees the truncated iterate rather than the root, about 1e-5 away."""
import dataclasses
import sys
import time

import jax

jax.config.update("jax_enable_x64", True)

import equinox as eqx  # noqa: E402
import jax.numpy as jnp  # noqa: E402
import numpy as np  # noqa: E402
from engine_numbers import x_record  # noqa: E402  (the plan builders' x record on either tree)

from teflon_jax.bearing import (  # noqa: E402
    BoucWen,
    FrictionParameters,
    TriplePendulum,
    concave_surface,
    single_pendulum,
)
from teflon_jax.excitation import StochasticGroundMotion, sample, uniform_signal  # noqa: E402
from teflon_jax.studies import bidirectional_isolated_structure  # noqa: E402
from teflon_jax.systems import (  # noqa: E402
    imposed_path_test,
    isolated_structure,
    peak_response,
    sampled_path,
    simulate_history,
    slab_on_bearings,
    structure_on_isolator,
)
from teflon_jax.units import STANDARD_GRAVITY as G  # noqa: E402

TRIPLE = TriplePendulum(inner_radius=0.3, bottom_radius=2.1, top_radius=2.1, inner_capacity=0.05,
                        bottom_capacity=0.3, top_capacity=0.3,
                        inner_friction=FrictionParameters(0.03, 0.015, 20.0),
                        bottom_friction=FrictionParameters(0.08, 0.03, 20.0),
                        top_friction=FrictionParameters(0.12, 0.05, 20.0), hysteresis=BoucWen(1.27e-4))
motion = StochasticGroundMotion(peak_ground_acceleration=0.5 * G, duration=4.0, time_step=0.01,
                                rise_time=0.5, strong_motion_duration=2.5)
ACC = np.asarray(sample(motion, jax.random.key(7), 2))
GX, GY = uniform_signal(ACC[0], 0.01), uniform_signal(0.7 * ACC[1], 0.01)
DUR = 3.0


def smooth_peak(u, w=1e-3):
    return w * jax.nn.logsumexp(jnp.abs(u) / w)


def with_triple(theta):
    p = eqx.tree_at(lambda t: t.top_friction.f_max, TRIPLE, theta[0])
    return eqx.tree_at(lambda t: (t.bottom_radius, t.top_radius), p, (theta[1], theta[1]))


FLAT = isolated_structure("rigid", time_step=0.005, newton_tolerance=0.0)
SINGLE = isolated_structure("rigid", isolator=concave_surface(1.5), time_step=0.005, newton_tolerance=0.0)
ONE = isolated_structure("rigid", isolator=concave_surface(1.5), split_at_turn=False, time_step=0.005,
                         newton_tolerance=0.0)
S1 = isolated_structure("rigid", isolator=TRIPLE, newton_tolerance=1e-13)(GX)
S2 = bidirectional_isolated_structure("rigid", isolator=TRIPLE, newton_tolerance=1e-13)((GX, GY))


def flat(theta):  # flat sliders: f_max, isolation period
    s = FLAT(GX, {"f_max": theta[0], "isolation_period": theta[1]})
    r = peak_response(s, DUR)
    return jnp.stack([r.smooth_base_disp, r.base_shear_ratio])


def single(theta):  # single pendulum on the flat engine: f_max, radius
    s = SINGLE(GX, {"f_max": theta[0], "radius": theta[1]})
    r = peak_response(s, DUR)
    return jnp.stack([r.smooth_base_disp, r.base_shear_ratio])


def triple1(theta):  # series, one component: top f_max, outer radii
    s = eqx.tree_at(lambda s: s.pendulum, S1, with_triple(theta))
    u = simulate_history(s, DUR).displacement[:, 0]
    return jnp.stack([u[-1], smooth_peak(u)])


def onesurface(theta):  # series engine, one slider (bracketed): f_max, radius
    linear = ONE(GX, {"f_max": theta[0], "radius": theta[1]})
    pend = single_pendulum(linear.bearing, radius=theta[1])
    s = structure_on_isolator(linear, pend, friction_velocity="end", newton_tolerance=1e-13)
    u = simulate_history(s, DUR).displacement[:, 0]
    return jnp.stack([u[-1], smooth_peak(u)])


T_PATH = np.arange(0, 2.0001, 0.005)
PATH = 0.2 * np.sin(2 * np.pi * T_PATH / 1.0) * np.sin(np.pi * T_PATH / 2.0)


def path1(theta):  # imposed path, one component: top f_max, amplitude
    r = imposed_path_test(eqx.tree_at(lambda t: t.top_friction.f_max, TRIPLE, theta[0]),
                           sampled_path(T_PATH, theta[1] * PATH, 1e6))
    return jnp.stack([r.fx[-1], r.fx[len(T_PATH) // 3]])


def _one_component(s):
    """The part of a two-component series structure that holds its pendulum: the structure
    itself, or its one-component structure where it is a field (`uniaxial`)."""
    return s.uniaxial if "uniaxial" in {f.name for f in dataclasses.fields(s)} else s


def biaxial(theta):  # series, two components
    s = eqx.tree_at(lambda s: _one_component(s).pendulum, S2, with_triple(theta))
    r = simulate_history(s, DUR)
    n = r.displacement.shape[-1] // 2  # the x block, then the y block
    x = jnp.stack([r.displacement[:, :n], r.displacement[:, n:]], 1)
    return jnp.stack([x[-1, 0, 0], x[-1, 1, 0], smooth_peak(jnp.hypot(x[:, 0, 0], x[:, 1, 0]))])


def path2(theta):  # imposed planar path
    orbit = np.stack([PATH, 0.6 * np.roll(PATH, 40)], -1)
    r = imposed_path_test(eqx.tree_at(lambda t: t.top_friction.f_max, TRIPLE, theta[0]),
                           sampled_path(T_PATH, theta[1] * orbit, 1e6, park_elements=16))
    return jnp.stack([r.fx[-1], r.fy[-1], r.fx[len(T_PATH) // 3]])


CORNERS = np.array([[2.0, 1.0], [18.0, 1.0], [18.0, 11.0], [2.0, 11.0]])


def slab(theta):  # slab on series pendulums: top f_max, outer radii
    s = slab_on_bearings(length_x=20.0, length_y=12.0, weight=1e6, centre_of_mass=np.array([10.0, 6.0]),
                         positions=CORNERS, loads=[0.25e6] * 4, **x_record(GX), ground_y=GY, time_step=0.005,
                         isolator=TRIPLE.isolator, pendulums=with_triple(theta), height_of_centre_of_mass=3.0)
    q = simulate_history(dataclasses.replace(s, newton_tolerance=1e-13), 2.0).displacement
    return jnp.stack([q[-1, 0], q[-1, 1], q[-1, 2]])


CASES = {"flat": (flat, [0.10, 2.0]), "single": (single, [0.10, 1.5]), "triple1": (triple1, [0.12, 2.1]),
         "onesurface": (onesurface, [0.10, 1.5]), "path1": (path1, [0.12, 1.0]),
         "biaxial": (biaxial, [0.12, 2.1]), "path2": (path2, [0.12, 1.0]), "slab": (slab, [0.12, 2.1])}

def dump(out, names):
    results = {}
    for name in names:
        f, theta = CASES[name]
        theta = jnp.asarray(theta)
        t0 = time.time()
        fj = jax.jit(f)
        value = np.asarray(fj(theta))
        rev = np.asarray(jax.jit(jax.jacrev(f))(theta))
        fwd = np.asarray(jax.jit(jax.jacfwd(f))(theta))
        fd = {}
        for rel in (1e-5, 2e-5):
            cols = []
            for i in range(2):
                h = rel * float(theta[i])
                e = jnp.zeros(2).at[i].set(h)
                cols.append((np.asarray(fj(theta + e)) - np.asarray(fj(theta - e))) / (2 * h))
            fd[rel] = np.stack(cols, -1)
        results.update({f"{name}/value": value, f"{name}/rev": rev, f"{name}/fwd": fwd,
                        f"{name}/fd": fd[1e-5], f"{name}/fd2": fd[2e-5]})
        err = np.abs(fd[1e-5] - fd[2e-5])
        print(f"{name}: {time.time() - t0:.0f} s  fwd-rev {np.max(np.abs(fwd - rev) / np.abs(rev)):.2e}  "
              f"|rev-fd|/|fd| {np.max(np.abs(rev - fd[1e-5]) / np.abs(fd[1e-5])):.2e}  "
              f"fd-err/|fd| {np.max(err / np.abs(fd[1e-5])):.2e}", flush=True)
    np.savez(out, **results)


def compare(old, new):
    a, b = np.load(old), np.load(new)
    for key in a:
        if key in b:
            scale = np.max(np.abs(a[key]))
            print(f"{key:20s} max|old-new|/max|old| = {np.max(np.abs(a[key] - b[key])) / scale:.2e}")
        else:
            print(f"{key:20s} only in {old}")


if __name__ == "__main__":
    if len(sys.argv) < 3 or sys.argv[1] not in ("dump", "compare"):
        sys.exit(__doc__)
    if sys.argv[1] == "dump":
        dump(sys.argv[2], sys.argv[3:] or list(CASES))
    else:
        compare(sys.argv[2], sys.argv[3])
