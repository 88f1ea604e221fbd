"""The engines' numbers, for comparing two versions of the code number for number.

`python benchmarks/engine_numbers.py dump OUT.npz` runs a fixed set of structures under the
same stochastic motions (the rigid mass and the Table 2 building on double and triple friction
pendulums, in one and two horizontal components, with and without a vertical component; on
flat sliders and single pendulums in one and two, with and without a vertical component, and
the slab on flat sliders and on single pendulums) and the imposed-path test of the series pendulums,
and saves every history. Run it under each version (`PYTHONPATH=/path/to/other/checkout`), then
`python benchmarks/engine_numbers.py compare OLD.npz NEW.npz` prints, per case, the largest
difference over the largest value and exits 1 where one exceeds `--tolerance` (1e-9).
"""

import argparse
import inspect
import sys

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

jax.config.update("jax_enable_x64", True)

import teflon_jax.systems as systems  # noqa: E402
from teflon_jax.bearing import BoucWen, DoublePendulum, FrictionParameters, TriplePendulum  # noqa: E402
from teflon_jax.excitation import StochasticGroundMotion, sample, uniform_signal  # noqa: E402
from teflon_jax.studies import bidirectional_isolated_structure  # noqa: E402
from teflon_jax.systems import (  # noqa: E402
    isolated_structure,
    peak_response,
    sampled_path,
    simulate_history,
    slab_on_bearings,
    triple_structure,
    with_vertical_component,
    with_vertical_motion,
)
from teflon_jax.tables import interface_parameters  # noqa: E402

imposed_path_test = getattr(systems, "imposed_path_test", None) or systems.respond_along_path  # a tree before it


def x_record(signal) -> dict:
    """The plan builders' keyword for the x record `signal`: `ground_acceleration`, or
    `ground_x` on a tree before the builders took that name."""
    taken = inspect.signature(slab_on_bearings).parameters
    return {"ground_acceleration" if "ground_acceleration" in taken else "ground_x": signal}


def _with_y(system, ground_y):
    """`system` (series pendulums along x) under the y component too, in this version's API."""
    if hasattr(system, "with_y_component"):
        return system.with_y_component(ground_y)
    from teflon_jax.systems import (
        BiaxialStructureOnTriple,  # versions before `with_y_component`
    )

    return BiaxialStructureOnTriple(system, ground_y)

from teflon_jax.units import PSI, STANDARD_GRAVITY  # noqa: E402

DURATION, RECORD_STEP, TIME_STEP = 12.0, 0.01, 0.005
DOUBLE = DoublePendulum(bottom_radius=1.5, top_radius=2.0, bottom_capacity=0.3, top_capacity=0.3,
                        bottom_friction=FrictionParameters(0.06, 0.03, 25.0),
                        top_friction=FrictionParameters(0.09, 0.04, 15.0), hysteresis=BoucWen(2e-4))
TRIPLE = TriplePendulum(inner_radius=0.3, bottom_radius=2.1, top_radius=2.1, inner_capacity=0.05,
                        bottom_capacity=0.4, top_capacity=0.4, inner_friction=FrictionParameters(0.03, 0.015, 20.0),
                        bottom_friction=FrictionParameters(0.07, 0.03, 20.0),
                        top_friction=FrictionParameters(0.11, 0.05, 20.0), hysteresis=BoucWen(1e-4))


def _series_1d(system, duration):
    """The response of `system` (series pendulums along x): `simulate_triple_structure` where
    this version has it (before the one structure), else the one history driver."""
    return getattr(systems, "simulate_triple_structure", simulate_history)(system, duration)


def _series_2d(system, duration):
    """(state history, bearing-force history) of `system` under two components:
    `biaxial_histories` where this version has it, else the state and force of `simulate_history`."""
    if hasattr(systems, "biaxial_histories"):
        histories = systems.biaxial_histories(system, duration)
        return histories[1], histories[2]
    response = simulate_history(system, duration)
    nt, n = response.time.shape[0], system.mass.shape[-1]
    state = jnp.concatenate([response.displacement.reshape(nt, 2, n),
                             response.velocity.reshape(nt, 2, n)], -1)  # (u, v) in x and in y
    return state, response.bearing_force


def _field(response, *names):
    """The first of the fields `names` that `response` has: the same history under the names
    of this and of earlier versions of the response types."""
    return next(getattr(response, name) for name in names if hasattr(response, name))



def one_surface_keywords(name: str, radius=None) -> dict:
    """The isolator keywords of `isolated_structure` for flat sliders ("flat", `radius` None)
    or single pendulums of radius `radius` [m] ("single-fp"): the isolator value; under a
    version whose builders take isolator names (no `teflon_jax.bearing.one_surface`), the name
    and the radius, so that both versions build the same structure."""
    try:
        from teflon_jax.bearing import concave_surface, one_surface  # noqa: F401
    except ImportError:
        return {"isolator": name, **({} if radius is None else {"radius": radius})}
    return {"isolator": None if radius is None else concave_surface(radius)}

def _ground(seed, scale=1.0):
    motion = StochasticGroundMotion(peak_ground_acceleration=0.6 * STANDARD_GRAVITY, duration=DURATION,
                                    time_step=RECORD_STEP)
    return scale * np.asarray(sample(motion, jax.random.PRNGKey(seed), 1))[0]


def _series_cases(out):
    vertical = uniform_signal(0.5 * _ground(9), RECORD_STEP)
    for name, pendulum in (("double", DOUBLE), ("triple", TRIPLE)):
        for kind in ("rigid", "building"):
            for with_vertical in (False, True):
                system = triple_structure(kind, pendulum, uniform_signal(_ground(1), RECORD_STEP), time_step=TIME_STEP)
                if with_vertical:
                    system = eqx.tree_at(lambda s: s.vertical_acceleration, system, vertical,
                                         is_leaf=lambda x: x is None)
                key = f"{name}-{kind}-vertical{int(with_vertical)}"
                response = jax.jit(_series_1d, static_argnums=1)(system, DURATION)
                out[f"{key}-1d-displacement"] = np.asarray(response.displacement)
                out[f"{key}-1d-force"] = np.asarray(response.bearing_force)
                both = _with_y(system, uniform_signal(_ground(2, 0.8), RECORD_STEP))
                state, force = jax.jit(_series_2d, static_argnums=1)(both, DURATION)
                out[f"{key}-2d-state"] = np.asarray(state)
                out[f"{key}-2d-force"] = np.asarray(force)
        time = np.arange(0.0, 8.0 + 1e-9, RECORD_STEP)
        path = 0.15 * np.sin(2 * np.pi * time / 4.0)
        test = jax.jit(imposed_path_test)(pendulum, sampled_path(time, path, 1e6))
        out[f"{name}-test-1d-force"] = np.asarray(test.force)


def _flat_cases(out):
    for isolator, radius in (("flat", None), ("single-fp", 1.5)):
        for kind in ("rigid", "building"):
            extra = one_surface_keywords(isolator, radius)
            system = isolated_structure(kind, **extra)(uniform_signal(_ground(1), RECORD_STEP))
            response = jax.jit(simulate_history, static_argnums=1)(system, DURATION)
            out[f"{isolator}-{kind}-1d-displacement"] = np.asarray(response.displacement)
            planar = bidirectional_isolated_structure(kind, **extra)
            pair = (uniform_signal(_ground(1), RECORD_STEP), uniform_signal(_ground(2, 0.8), RECORD_STEP))
            for with_vertical in (False, True):
                if with_vertical:
                    system = with_vertical_component(planar)((pair, uniform_signal(0.5 * _ground(9), RECORD_STEP)))
                else:
                    system = planar(pair)
                response = jax.jit(simulate_history, static_argnums=1)(system, DURATION)
                out[f"{isolator}-{kind}-vertical{int(with_vertical)}-2d-q"] = np.asarray(_field(response, "q", "displacement"))
                out[f"{isolator}-{kind}-vertical{int(with_vertical)}-2d-force"] = np.asarray(response.friction_force)
    _slab_cases(out)


def _slab_cases(out):
    params, _ = interface_parameters("UF", 1000 * PSI)
    from teflon_jax.bearing import paper_bearing

    corners = np.array([[2.0, 1.0], [18.0, 1.0], [18.0, 11.0], [2.0, 11.0]])
    for isolator, extra in (("flat", {"isolation_period": 2.5}), ("single-fp", {"radii": 1.5})):
        for height in (0.0, 3.0):
            slab = slab_on_bearings(
                length_x=20.0, length_y=12.0, weight=1e6, centre_of_mass=(9.0, 6.5), positions=corners,
                loads=[2.6e5, 2.4e5, 2.4e5, 2.6e5], bearings=paper_bearing(params), isolator=isolator,
                **x_record(uniform_signal(_ground(1), RECORD_STEP)), ground_y=uniform_signal(_ground(2, 0.8), RECORD_STEP),
                time_step=TIME_STEP, height_of_centre_of_mass=height, **extra)
            slab = with_vertical_motion(slab, uniform_signal(0.5 * _ground(9), RECORD_STEP))
            response = jax.jit(simulate_history, static_argnums=1)(slab, DURATION)
            out[f"slab-{isolator}-h{height:g}-q"] = np.asarray(_field(response, "q", "displacement"))


def _peak_structures():
    """(name, structure) pairs for `peak_response`: the rigid mass and the building on flat
    sliders and on double pendulums, in one and two components, with and without a vertical
    record (0.5 times a third stochastic motion [m/s^2])."""
    ground_x = uniform_signal(_ground(1), RECORD_STEP)
    ground_y = uniform_signal(_ground(2, 0.8), RECORD_STEP)
    vertical = uniform_signal(0.5 * _ground(9), RECORD_STEP)
    extra = one_surface_keywords("flat")
    for kind in ("rigid", "building"):
        one = isolated_structure(kind, **extra)
        two = bidirectional_isolated_structure(kind, **extra)
        yield f"flat-{kind}-vertical0-1d", one(ground_x)
        yield f"flat-{kind}-vertical1-1d", with_vertical_component(one)((ground_x, vertical))
        yield f"flat-{kind}-vertical0-2d", two((ground_x, ground_y))
        yield f"flat-{kind}-vertical1-2d", with_vertical_component(two)(((ground_x, ground_y), vertical))
        series = triple_structure(kind, DOUBLE, ground_x, time_step=TIME_STEP)
        for with_vertical in (False, True):
            system = eqx.tree_at(lambda s: s.vertical_acceleration, series, vertical,
                                 is_leaf=lambda x: x is None) if with_vertical else series
            yield f"double-{kind}-vertical{int(with_vertical)}-1d", system
            yield f"double-{kind}-vertical{int(with_vertical)}-2d", _with_y(system, ground_y)


def _peak_cases(out):
    for name, system in _peak_structures():
        peaks = jax.jit(peak_response, static_argnums=1)(system, DURATION)
        values = dict(peaks)
        for field, value in values.items():
            if value is not None:
                for index, leaf in enumerate(jax.tree_util.tree_leaves(value)):
                    out[f"peaks-{name}-{field}-{index}"] = np.asarray(leaf)


def _study_cases(out):
    """Monte Carlo peaks through the study structure on the double and triple pendulums
    (rigid mass and building; one and two components, the three bounding cases, a vertical
    component), four 8 s motions each; in versions whose single study structure takes one or
    two components by its own type, the two-component one is that of `isolated_structure`."""
    from teflon_jax.excitation import TwoComponentGroundMotion, VerticalGroundMotion
    from teflon_jax.studies import bounding_design, monte_carlo

    model = StochasticGroundMotion(peak_ground_acceleration=3.0, duration=8.0, time_step=0.01, rise_time=1.0,
                                   strong_motion_duration=3.0)
    two_by_type = hasattr(systems, "TripleIsolatedStructure")
    for name, pendulum in (("double", DOUBLE), ("triple", TRIPLE)):
        for kind in ("rigid", "building"):
            for components in (1, 2):
                build = isolated_structure if components == 1 or two_by_type else bidirectional_isolated_structure
                structure = build(kind, isolator=pendulum, time_step=TIME_STEP)
                motions = model if components == 1 else TwoComponentGroundMotion(model)
                for design in (None, bounding_design(structure, lower=0.85, upper=1.3)):
                    result = monte_carlo(structure, motions, 4, design=design, key=jax.random.key(3), chunk_size=4)
                    label = f"study-{name}-{kind}-{components}c-{'nominal' if design is None else 'bounding'}"
                    for field in ("base_disp", "base_shear_ratio", "smooth_base_disp", "converged"):
                        out[f"{label}-{field}"] = np.asarray(getattr(result, field))
            structure = with_vertical_component(isolated_structure(kind, isolator=pendulum, time_step=TIME_STEP))
            result = monte_carlo(structure, VerticalGroundMotion(model, vertical_ratio=0.67), 4, key=jax.random.key(3),
                                 chunk_size=4)
            for field in ("base_disp", "uplift_time"):
                out[f"study-{name}-{kind}-vertical-{field}"] = np.asarray(getattr(result, field))


GROUP_DURATION = 8.0  # [s] of the slabs on bearing groups


def _slab_history(slab, duration):
    """The slab's history under this version's driver (`simulate_history`; a slab on series
    pendulums through `simulate_slab_series` where the version has it)."""
    import teflon_jax.systems as systems

    series = getattr(systems, "SlabOnSeries", None)
    driver = systems.simulate_slab_series if series is not None and isinstance(slab, series) else systems.simulate_history
    return jax.jit(driver, static_argnums=1)(slab, duration)


def _save_history(out, key, response):
    """Every array of `response` (a `StructureResponse`) under `key`-field."""
    for name, value in vars(response).items():
        if value is not None and not isinstance(value, (str, bool, int, float)):
            leaves = jax.tree_util.tree_leaves(value)
            if leaves and all(hasattr(leaf, "shape") for leaf in leaves):
                for index, leaf in enumerate(leaves):
                    out[f"{key}-{name}" + (f"-{index}" if len(leaves) > 1 else "")] = np.asarray(leaf)


def _group_isolators():
    """(name, `slab_on_bearings` isolator keywords) of every isolator of the groups: flat
    sliders with springs, single pendulums, double and triple pendulums, a heated double."""
    from teflon_jax.bearing import FrictionalHeating, paper_bearing

    params, _ = interface_parameters("UF", 1000 * PSI)
    heating = FrictionalHeating(contact_area=0.05)
    heated = eqx.tree_at(lambda p: (p.bottom_heating, p.bottom_pressure, p.top_heating, p.top_pressure), DOUBLE,
                         (heating, 20e6, heating, 20e6), is_leaf=lambda x: x is None)
    return (("flat", {"bearings": paper_bearing(params), "isolator": "flat", "isolation_period": 2.5}),
            ("single-fp", {"bearings": paper_bearing(params), "isolator": "single-fp", "radii": 1.5}),
            ("double-fp", {"isolator": "double-fp", "pendulums": DOUBLE}),
            ("triple-fp", {"isolator": "triple-fp", "pendulums": TRIPLE}),
            ("double-fp-heated", {"isolator": "double-fp", "pendulums": heated}))


def _group_cases(out):
    """`slab_on_bearings` on every isolator's groups, at heights 0 and 3 m (overturning and
    uplift), without and with a vertical record, and the series groups driven into their
    restrainers (a biased 0.2 g + 0.35 g sine, heights 0 and 0.25 m), and every isolator's
    groups lifting under a vertical record beyond g; every history."""
    corners = np.array([[2.0, 1.0], [18.0, 1.0], [18.0, 11.0], [2.0, 11.0]])
    plan = {"length_x": 20.0, "length_y": 12.0, "weight": 1e6, "centre_of_mass": (9.0, 6.5), "positions": corners,
            "loads": [2.6e5, 2.4e5, 2.4e5, 2.6e5], "time_step": TIME_STEP}
    pair = {**x_record(uniform_signal(1.5 * _ground(1), RECORD_STEP)),
            "ground_y": uniform_signal(1.2 * _ground(2), RECORD_STEP)}
    vertical = uniform_signal(0.8 * _ground(9), RECORD_STEP)
    for name, isolator in _group_isolators():
        for height in (0.0, 3.0):
            for with_vertical in (False, True):
                slab = slab_on_bearings(**plan, **pair, **isolator, height_of_centre_of_mass=height)
                if with_vertical:
                    slab = with_vertical_motion(slab, vertical)
                key = f"groups-{name}-h{height:g}-vertical{int(with_vertical)}"
                _save_history(out, key, _slab_history(slab, GROUP_DURATION))
    time = np.arange(0.0, 4.0 + 1e-9, RECORD_STEP)
    drive = {**x_record(uniform_signal((0.2 + 0.35 * np.sin(2 * np.pi * 0.7 * time)) * STANDARD_GRAVITY,
                                       RECORD_STEP)),
             "ground_y": uniform_signal(0 * time, RECORD_STEP)}
    for name, isolator in _group_isolators()[2:4]:
        for height in (0.0, 0.25):
            slab = slab_on_bearings(**plan, **drive, **isolator, height_of_centre_of_mass=height)
            _save_history(out, f"groups-{name}-restrainers-h{height:g}", _slab_history(slab, 3.0))
    lifting = uniform_signal(2.2 * _ground(9), RECORD_STEP)  # a_v beyond g: groups lift
    for name, isolator in _group_isolators():
        slab = with_vertical_motion(slab_on_bearings(**plan, **pair, **isolator, height_of_centre_of_mass=3.0), lifting)
        _save_history(out, f"groups-{name}-uplift", _slab_history(slab, GROUP_DURATION))


def dump(path, cases="all"):
    out = {}
    if cases in ("all", "series"):
        _series_cases(out)
    if cases in ("all", "flat"):
        _flat_cases(out)
    if cases == "peaks":
        _peak_cases(out)
    if cases == "groups":
        _group_cases(out)
    if cases == "study":
        _study_cases(out)
    np.savez(path, **out)
    print(f"{len(out)} histories -> {path}")


def compare(old_path, new_path, tolerance):
    old, new = np.load(old_path), np.load(new_path)
    worst = 0.0
    for key in sorted(set(old.files) | set(new.files)):
        if key not in old.files or key not in new.files:
            print(f"{key:40s} only in {'new' if key in new.files else 'old'}")
            continue
        before, after = old[key].astype(float), new[key].astype(float)
        scale = max(np.max(np.abs(before)), 1e-300)
        relative = float(np.max(np.abs(before - after)) / scale)
        worst = max(worst, relative)
        print(f"{key:40s} {relative:.2e}")
    print(f"largest relative difference {worst:.2e} (tolerance {tolerance:g})")
    return 0 if worst <= tolerance else 1


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    dumping = sub.add_parser("dump")
    dumping.add_argument("out")
    dumping.add_argument("--cases", choices=("all", "series", "flat", "peaks", "groups", "study"), default="all",
                         help="all, the series pendulums, the flat sliders, single pendulums and slabs; "
                              "or (not in all) the peaks of `peak_response`, the slabs on every isolator's groups, "
                              "or the Monte Carlo peaks through the study structure on series pendulums")
    both = sub.add_parser("compare")
    both.add_argument("old")
    both.add_argument("new")
    both.add_argument("--tolerance", type=float, default=1e-9)
    args = parser.parse_args(argv)
    if args.command == "dump":
        dump(args.out, args.cases)
        return 0
    return compare(args.old, args.new, args.tolerance)


if __name__ == "__main__":
    sys.exit(main())
