"""`--isolator triple-fp|double-fp --isolator-file FILE` of `teflon-jax run` and `montecarlo`:
the rigid mass or the Table 2 building on triple or double friction pendulums, under one or two
horizontal components."""

import dataclasses
import pathlib
import sys
import types

import numpy as np

from ..units import STANDARD_GRAVITY, parse_quantity
from ._run_stop import WRITTEN, cut, kept_steps, stop_entries
from ._run_vertical import uplift_line, uplift_summary

SERIES_ISOLATORS = ("triple-fp", "double-fp")
"""The isolators whose surfaces an isolator file gives (`--isolator-file`): the names of the
registry `teflon_jax.bearing.SERIES_PENDULUMS`, written out so that `--help` answers without
loading JAX (`tests/test_cli.py` holds the two equal)."""


def read_isolator_flag(args):
    """The `TriplePendulum` or `DoublePendulum` of `--isolator-file` for `--isolator triple-fp`
    or `double-fp` (None for the other isolators), with the flags checked: `ValueError` naming
    a file without the isolator, the isolator without a file, a file of the other pendulum, and
    the flags of the other isolators given with it."""
    path = getattr(args, "isolator_file", None)
    isolator = args.isolator
    if isolator not in SERIES_ISOLATORS:
        if path is not None:
            raise ValueError(f"--isolator-file: applies to --isolator triple-fp only, or double-fp "
                             f"(the pendulums whose surfaces it gives), not {isolator}; add --isolator "
                             "triple-fp (or double-fp) or leave --isolator-file out.")
        return None
    if path is None:
        raise ValueError(f"--isolator-file: --isolator {isolator} needs the isolator file of its "
                         "surfaces (radius, capacity and friction of each; see docs/formats.md).")
    if args.radius is not None:
        raise ValueError(f"--radius: does not apply to --isolator {isolator} (its radii are in "
                         "--isolator-file); leave --radius out.")
    conflicting = [("--isolation-period", getattr(args, "isolation_period_text", args.isolation_period)),
                   ("--isolation-damping", getattr(args, "isolation_damping_text", args.isolation_damping)),
                   ("--bearing", args.bearing)]
    conflicting += [("--" + name.replace("_", "-"), None if getattr(args, name + "_text", getattr(args, name))
                     == default else name)
                    for name, default in getattr(args, "bearing_option_defaults", {}).items()]
    for flag, value in conflicting:
        if value is not None:
            raise ValueError(f"{flag}: does not apply to --isolator {isolator}, whose friction, "
                             f"period and damping are its surfaces' in --isolator-file; leave {flag} out.")
    return _load(path, isolator)


def _load(path, isolator, command=None):
    """The pendulum of the isolator file `path`; `ValueError` naming the flag, also for a file
    of another isolator than `--isolator`'s (a start file of `command`, fit or diagnose, is
    named as such)."""
    from ..formats import load_isolator

    try:
        pendulum = load_isolator(path)
    except ValueError as error:
        raise ValueError(f"--isolator-file {error}") from None
    if pendulum.isolator != isolator:
        if command is not None:
            raise ValueError(f"--isolator-file: {path} holds a {pendulum.isolator} isolator; {command} "
                             f"--isolator {isolator} starts from a file of that isolator (or give "
                             f"--isolator {pendulum.isolator}).")
        raise ValueError(f"--isolator-file: {path} holds a {pendulum.isolator} isolator, not the "
                         f"{isolator} of --isolator; give --isolator {pendulum.isolator} or another file.")
    return pendulum


def with_vertical_record(system, vertical, dt, samples):
    """`system` with the --record-z component as its vertical acceleration: `vertical(dt,
    samples)` [m/s^2] on the records' grid (`dt` [s]), or `system` itself when that is None."""
    from ..excitation import uniform_signal

    az = None if vertical is None else vertical(dt, samples)
    return system if az is None else dataclasses.replace(system, vertical_acceleration=uniform_signal(az, dt))


def check_triple_run(args) -> None:
    """`run`'s flags that a triple or double pendulum under a rigid mass or the building cannot
    take, refused by name (a slab on them, one pair or a suite, goes to `_run_slab_series`)."""
    if args.plan is not None:
        raise ValueError("--plan: only used with --structure slab.")


def run_triple(args, load_components, write_run_outputs, vertical=None) -> int:
    """`teflon-jax run --isolator triple-fp|double-fp`: the x record (and the y record, if
    given) through the structure, peaks in JSON (the keys of the other isolators; y zero for
    one component), histories and plot. `vertical(dt, samples)`: the --record-z component
    [m/s^2] on the records' grid, or None; it sets every slider's normal load."""
    from ..excitation import uniform_signal
    from ..systems import (
        BiaxialStructureOnTriple,
        biaxial_histories,
        simulate_triple_structure,
        triple_structure,
    )

    pendulum = read_isolator_flag(args)
    check_triple_run(args)
    if args.histories is not None and pathlib.Path(args.histories).suffix not in (".nc", ".csv"):
        raise ValueError(f"--histories: {args.histories} must end in .nc or .csv.")
    weight = parse_quantity(args.weight, "force", where="--weight")
    if not weight > 0:
        raise ValueError(f"--weight: must be > 0, got {args.weight}.")
    time_step = parse_quantity(args.time_step, "time", where="--time-step")
    if not time_step > 0:
        raise ValueError(f"--time-step: must be > 0, got {args.time_step}.")
    ax, ay, dt, notes = load_components(args)
    system = triple_structure(args.structure, pendulum, uniform_signal(ax, dt), time_step=time_step,
                              weight=weight)
    system = with_vertical_record(system, vertical, dt, ax.size)
    duration = (ax.size - 1) * dt
    print(f"teflon-jax run: {args.structure} on {pendulum.description}, "
          f"{round(duration / time_step)} steps of {args.time_step} (compiling first)...", file=sys.stderr)
    if args.record_y is None:
        response = simulate_triple_structure(system, duration)
        converged = response.converged
    else:
        response = biaxial_histories(BiaxialStructureOnTriple(system, uniform_signal(ay, dt)), duration)
        converged = response[-1]
    time, converged = np.asarray(response.time if args.record_y is None else response[0]), np.asarray(converged)
    kept, problem = kept_steps(converged), ""
    if kept < time.size:  # the steps before the first unbalanced one
        problem = (f"the sliders' balance did not converge on {int(np.sum(~converged))} steps (first at "
                   f"t = {time[kept]:.4g} s); try a smaller --time-step; {WRITTEN.format(time[kept])}.")
        response, duration = cut(response, time.size, kept), float(time[kept - 1])
    peak, histories = (triple_summary(args, system, response) if args.record_y is None
                       else biaxial_summary(args, system, response))
    uplift = _uplift(system, duration)
    if uplift:
        histories["load_factor"] = _load_factors(system, duration)
    payload = {"structure": args.structure, "record_x": str(args.record_x),
               "record_y": None if args.record_y is None else str(args.record_y),
               "record_z": None if args.record_z is None else str(args.record_z),
               "scale": float(args.scale), "duration_s": duration, "record_time_step_s": dt,
               "solver_time_step_s": time_step, "notes": notes, "isolator": pendulum.isolator,
               "isolator_file": str(args.isolator_file), "radius_m": None, "anisotropic": False,
               "lay_angle_deg": None, "peak": peak, **uplift,
               **stop_entries(time, kept, np.zeros(time.size, bool), ~converged, ["peak", *uplift])}
    return write_run_outputs(args, payload, histories, f"{args.structure} on {pendulum.description}",
                             [uplift_line(uplift)] * bool(uplift), problem)


def _load_factors(system, duration):
    """N / W (nt,) at the solver's times of the structure's vertical record."""
    import jax
    import jax.numpy as jnp

    steps = round(duration / float(system.time_step))
    return np.asarray(jax.vmap(system.load_factor)(jnp.arange(steps + 1) * float(system.time_step)))


def _uplift(system, duration) -> dict:
    """The JSON entries of the uplift (`uplift_summary`), {} without a vertical record: the
    time of the steps whose end has N <= 0."""
    if system.vertical_acceleration is None:
        return {}
    loads = _load_factors(system, duration)
    counted = types.SimpleNamespace(uplift_time=float(np.sum(loads[1:] <= 0)) * float(system.time_step),
                                    load_factor=loads)
    return uplift_summary(counted)


def triple_summary(args, system, response):
    """(peak dict, histories dict) in SI of a `TripleStructureResponse`: the base displacement,
    the base shear over the weight above the isolators, the bearing force over W and, for the
    building, the storeys' peaks; the y components zero."""
    m = np.asarray(system.mass)
    u, acc = np.asarray(response.displacement), np.asarray(response.total_acceleration)
    above = m if m.size == 1 else m[1:]
    shear = (acc if m.size == 1 else acc[:, 1:]) @ above / (above.sum() * STANDARD_GRAVITY)
    force = np.asarray(response.bearing_force)
    load = float(system.bearing_load)
    peak = {"base_disp_resultant_m": float(np.max(np.abs(u[:, 0]))),
            "base_disp_x_m": float(np.max(np.abs(u[:, 0]))), "base_disp_y_m": 0.0,
            "base_shear_ratio_resultant": float(np.max(np.abs(shear))),
            "bearing_force_ratio_resultant": float(np.max(np.abs(force))) / load,
            "slider_disp_m": {name: float(v) for name, v in
                              zip(system.pendulum.slider_names, np.max(np.abs(np.asarray(response.slider)), 0))}}
    if args.structure == "building":
        from ..tables import load_table2

        height = np.broadcast_to(np.asarray(load_table2().storey_height, float), (m.size - 1,))
        peak["storey_drift_resultant_m"] = np.max(np.abs(np.diff(u, axis=1)), 0).tolist()
        peak["storey_drift_ratio_x"] = (np.max(np.abs(np.diff(u, axis=1)), 0) / height).tolist()
        peak["floor_acceleration_resultant_g"] = (np.max(np.abs(acc[:, 1:]), 0) / STANDARD_GRAVITY).tolist()
        peak["first_storey_shear_ratio_resultant"] = peak["base_shear_ratio_resultant"]
    zeros = np.zeros_like(force)
    histories = {"time_s": np.asarray(response.time),
                 "ground_x_mps2": np.asarray(response.ground_acceleration), "ground_y_mps2": zeros,
                 "base_disp_x_m": u[:, 0], "base_disp_y_m": zeros, "bearing_force_x_N": force,
                 "bearing_force_y_N": zeros, "base_shear_ratio_x": shear, "base_shear_ratio_y": zeros}
    for index, name in enumerate(system.pendulum.slider_names):
        histories[f"slider_{name}_m"] = np.asarray(response.slider)[:, index]
    return peak, histories


def biaxial_summary(args, system, response):
    """(peak dict, histories dict) in SI of `biaxial_histories`: resultant peaks of the base
    displacement, of the force on all masses over W (as the two-component Monte Carlo), of the
    bearing force over W, per slider, and for the building per storey and level."""
    time, x, force, sliders, acc, _ = (np.asarray(a) for a in response)
    m, n = np.asarray(system.mass), np.asarray(system.mass).size
    u = x[:, :, :n]  # (nt, 2, n)
    total = np.einsum("tkn,n->tk", acc, m)
    load = float(system.bearing_load)
    weight = float(m.sum()) * STANDARD_GRAVITY
    base = np.linalg.norm(u[:, :, 0], axis=1)
    peak = {"base_disp_resultant_m": float(base.max()), "base_disp_x_m": float(np.abs(u[:, 0, 0]).max()),
            "base_disp_y_m": float(np.abs(u[:, 1, 0]).max()),
            "base_shear_ratio_resultant": float(np.linalg.norm(total, axis=1).max()) / weight,
            "bearing_force_ratio_resultant": float(np.linalg.norm(force, axis=1).max()) / load,
            "slider_disp_m": {name: float(v) for name, v in
                              zip(system.pendulum.slider_names, np.linalg.norm(sliders, axis=2).max(axis=0))}}
    if args.structure == "building":
        floors = np.einsum("tkn,n->tk", acc[:, :, 1:], m[1:])
        peak["storey_drift_resultant_m"] = np.linalg.norm(np.diff(u, axis=2), axis=1).max(axis=0).tolist()
        peak["floor_acceleration_resultant_g"] = (np.linalg.norm(acc[:, :, 1:], axis=1).max(axis=0)
                                                  / STANDARD_GRAVITY).tolist()
        peak["first_storey_shear_ratio_resultant"] = float(np.linalg.norm(floors, axis=1).max()) / (
            float(m[1:].sum()) * STANDARD_GRAVITY)
    histories = {"time_s": time, "base_disp_x_m": u[:, 0, 0], "base_disp_y_m": u[:, 1, 0],
                 "bearing_force_x_N": force[:, 0], "bearing_force_y_N": force[:, 1],
                 "base_shear_ratio_x": total[:, 0] / weight, "base_shear_ratio_y": total[:, 1] / weight}
    for index, name in enumerate(system.pendulum.slider_names):
        for axis, label in enumerate("xy"):
            histories[f"slider_{name}_{label}_m"] = sliders[:, index, axis]
    return peak, histories


def triple_montecarlo_structure(args):
    """`montecarlo --isolator triple-fp|double-fp`: the `TripleIsolatedStructure` of the flags,
    once `read_isolator_flag` has checked them (one or two components; `--property-factors`
    and `--newton-tolerance` refused by name)."""
    from ..systems import TRIPLE_MONTE_CARLO_TOLERANCE, isolated_structure

    isolator = args.isolator
    pendulum = _load(args.isolator_file, isolator)
    if args.newton_tolerance is not None:
        raise ValueError("--newton-tolerance: is in units of a flat bearing's yield displacement; "
                         f"the {isolator} isolator's sliders are solved to their own tolerance "
                         "(a force imbalance of 1e-7 W); leave --newton-tolerance out.")
    solver = {} if args.newton_iterations is None else {"newton_iterations": args.newton_iterations}
    pendulum_argument = {"triple-fp": "triple", "double-fp": "double"}[isolator]
    return isolated_structure(args.structure, isolator=isolator, **{pendulum_argument: pendulum},
                              time_step=args.time_step,
                              newton_tolerance=TRIPLE_MONTE_CARLO_TOLERANCE, **solver)


def scaled_friction(pendulum, factor: float):
    """`pendulum` with f_max and delta_f of every surface times `factor` (a bounding case's
    property modification factor on the friction coefficient at every velocity; the order of
    the surfaces' friction that the series model needs is kept): `SeriesPendulum.scaled_friction`."""
    return pendulum.scaled_friction(factor)


def series_suite_build(args):
    """`run --suite` on triple or double pendulums: the function (ground_x, ground_y) -> the
    two-component structure (`BiaxialStructureOnTriple`) of the flags, with the friction of
    every surface times `args.friction_factor` (a bounding case; 1 otherwise)."""
    from ..systems import isolated_structure

    pendulum = read_isolator_flag(args)
    check_triple_run(args)
    time_step = parse_quantity(args.time_step, "time", where="--time-step")
    if not time_step > 0:
        raise ValueError(f"--time-step: must be > 0, got {args.time_step}.")
    factor = getattr(args, "friction_factor", 1.0)
    if factor != 1.0:
        pendulum = scaled_friction(pendulum, factor)
    pendulum_argument = {"triple-fp": "triple", "double-fp": "double"}[args.isolator]
    structure = isolated_structure(args.structure, isolator=args.isolator, **{pendulum_argument: pendulum},
                                   time_step=time_step)

    def build(ground_x, ground_y):
        return structure((ground_x, ground_y))

    return build
