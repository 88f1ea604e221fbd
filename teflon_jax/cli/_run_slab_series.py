"""`teflon-jax run --structure slab --plan FILE --isolator triple-fp|double-fp --isolator-file F`:
the rigid slab on groups of triple or double friction pendulums (a group may name its own
`isolator_file` in the plan), with the overturning of the plan's height; the slab's peaks and
each group's normal load, as for single pendulums; where the isolator files give surfaces
`heating`, each group's surfaces heat under its own normal load and the run reports their
peak temperature rise."""

import pathlib
import sys

import numpy as np

from ..units import STANDARD_GRAVITY, parse_quantity
from ._plan_file import read_plan
from ._run_slab import normal_load_summary, slab_peaks
from ._run_stop import WRITTEN, cut, kept_steps, stop_entries
from ._run_vertical import uplift_line
from ._triple import _load, _load_factors, _uplift, read_isolator_flag, with_vertical_record


def series_plan(args):
    """(plan, pendulums (one per group)) of the flags, checked before any record is read:
    `ValueError` naming the plan's key (a group's radius, springs, ptfe or pressure, which the
    series pendulums do not take; an isolator_file that is missing or of another isolator) or
    the flag (`read_isolator_flag`)."""
    default = read_isolator_flag(args)
    if args.plan is None:
        raise ValueError("--plan: --structure slab needs a plan file (bearing groups and loads).")
    plan = read_plan(args.plan)
    pendulums = []
    for g in plan["groups"]:
        for key, reason in (("radius", "its radii are in the isolator file"),
                            ("springs", "each group restores with its pendulum"),
                            ("ptfe", "its friction is in the isolator file"),
                            ("pressure", "its friction is in the isolator file")):
            if g[key] is not None:
                raise ValueError(f"--plan: {g['name']}.{key} does not apply to --isolator {args.isolator} "
                                 f"({reason}); leave '{key}' out of the group.")
        path = g["isolator_file"]
        if path is None:
            pendulums.append(default)
            continue
        if not pathlib.Path(path).is_file():
            raise ValueError(f"--plan: {args.plan}: {g['name']}.isolator_file {path} is not a file "
                             "(a path relative to the plan's folder).")
        try:
            pendulums.append(_load(path, args.isolator))
        except ValueError as error:
            raise ValueError(f"--plan: {g['name']}.isolator_file: {error}") from None
    plan["isolator_files"] = [str(g["isolator_file"] or args.isolator_file) for g in plan["groups"]]
    return plan, pendulums


def series_slab(args, plan, pendulums, ground_x, ground_y):
    """The `SlabOnSeries` of the plan and its groups' `pendulums` (`series_plan`) under the
    ground `Signal`s [m/s^2], at `--time-step` (checked > 0)."""
    from ..systems import slab_on_bearings

    time_step = parse_quantity(args.time_step, "time", where="--time-step")
    if not time_step > 0:
        raise ValueError(f"--time-step: must be > 0, got {args.time_step}.")
    groups = plan["groups"]
    stiffness = [g["vertical_stiffness"] for g in groups]
    return slab_on_bearings(
        length_x=plan["length_x"], length_y=plan["length_y"], weight=plan["weight"],
        centre_of_mass=plan["centre_of_mass"], positions=[(g["x"], g["y"]) for g in groups],
        loads=[g["load"] for g in groups], ground_x=ground_x, ground_y=ground_y,
        time_step=time_step, names=[g["name"] for g in groups], isolator=args.isolator, pendulums=pendulums,
        height_of_centre_of_mass=plan["height_of_centre_of_mass"],
        vertical_stiffness=None if all(k is None for k in stiffness) else [1.0 if k is None else k
                                                                         for k in stiffness])


def series_slab_suite_build(args, ax0, ay0, dt):
    """(build(ground_x, ground_y) -> the `SlabOnSeries` of one pair, plan) of `run --suite
    --structure slab --isolator triple-fp|double-fp`: the slab built once on the first pair
    (`ax0`, `ay0` [m/s^2], step `dt` [s]), every group's surfaces' f_max and delta_f times
    `args.friction_factor` (a bounding case; 1 otherwise, `scaled_friction`)."""
    import equinox as eqx

    from ..excitation import uniform_signal
    from ._triple import scaled_friction

    plan, pendulums = series_plan(args)
    factor = getattr(args, "friction_factor", 1.0)
    if factor != 1.0:
        pendulums = [scaled_friction(p, factor) for p in pendulums]
    template = series_slab(args, plan, pendulums, uniform_signal(ax0, dt), uniform_signal(ay0, dt))

    def build(ground_x, ground_y):
        return eqx.tree_at(lambda s: (s.ground_x, s.ground_y), template, (ground_x, ground_y))

    return build, plan


def run_series_slab(args, load_components, write_run_outputs, vertical=None) -> int:
    """The run (module docstring); `vertical(dt, samples)`: the --record-z component [m/s^2]
    on the records' grid or None, on every group's normal load."""
    import jax

    from ..excitation import uniform_signal
    from ..systems import simulate_slab_series

    plan, pendulums = series_plan(args)
    if args.histories is not None and pathlib.Path(args.histories).suffix not in (".nc", ".csv"):
        raise ValueError(f"--histories: {args.histories} must end in .nc or .csv.")
    time_step = parse_quantity(args.time_step, "time", where="--time-step")
    if not time_step > 0:
        raise ValueError(f"--time-step: must be > 0, got {args.time_step}.")
    groups = plan["groups"]
    ax, ay, dt, notes = load_components(args)
    system = series_slab(args, plan, pendulums, uniform_signal(ax, dt), uniform_signal(ay, dt))
    system = with_vertical_record(system, vertical, dt, ax.size)
    duration = (ax.size - 1) * dt
    print(f"teflon-jax run: slab on {pendulums[0].description}, {round(duration / time_step)} steps of "
          f"{args.time_step} (compiling first)...", file=sys.stderr)
    response = jax.jit(simulate_slab_series, static_argnums=1)(system, duration)
    problem = unbalanced_message(response, plan["height_of_centre_of_mass"])
    end, response = series_slab_stop(system, response)  # the steps before the first unbalanced one
    kept_duration = duration if problem == "" else float(end[0][end[1] - 1])
    peak, histories = series_slab_summary(plan, system, response)
    from ._common import output_units

    normal, lines = normal_load_summary(plan, system, response, output_units(args.units))
    uplift = _uplift(system, kept_duration)  # the vertical record's own factor, as for one isolator
    if uplift:
        histories["load_factor"] = _load_factors(system, kept_duration)
        lines = [uplift_line(uplift)] + lines
    for g, path in zip(groups, plan["isolator_files"]):
        normal["normal_load"]["groups"][g["name"]]["isolator_file"] = path
    rises = surface_temperature_summary(plan, system, response, histories)
    lines += [f"surface temperature rise {name}: " + ", ".join(f"{e} {v:.4g} K" for e, v in row.items())
              for name, row in (rises or {}).items()]
    payload = {"structure": "slab", "record_x": str(args.record_x),
               "record_y": None if args.record_y is None else str(args.record_y),
               "record_z": None if args.record_z is None else str(args.record_z),
               "scale": float(args.scale), "duration_s": duration, "record_time_step_s": dt,
               "solver_time_step_s": time_step, "notes": notes, "isolator": args.isolator,
               "isolator_file": str(args.isolator_file), "radius_m": None, "anisotropic": False,
               "lay_angle_deg": None, "peak": peak, **uplift, **normal,
               "slider_disp_m": _slider_peaks(plan, system, response), "surface_temperature_rise_K": rises}
    payload |= stop_entries(*end, ["peak", *uplift, *normal, "slider_disp_m", "surface_temperature_rise_K"])
    return write_run_outputs(args, payload, histories, f"slab on {pendulums[0].description}", lines, problem)


def series_slab_stop(system, response):
    """((time (nt,) [s], kept steps, tipped (nt,), unconverged (nt,)) for `stop_entries`, the
    `SlabSeriesResponse` cut to the steps before the first unbalanced one, `kept_steps`, its
    groups' uplift times counting those steps only)."""
    import dataclasses

    time, converged = np.asarray(response.time), np.asarray(response.converged)
    tipped = np.asarray(response.tipped)
    kept = kept_steps(converged)
    if kept == time.size:
        return (time, kept, tipped, ~converged & ~tipped), response
    short = cut(response, time.size, kept)
    uplift = np.sum(np.asarray(short.normal_load)[1:] <= 0, axis=0) * float(system.time_step)
    return (time, kept, tipped, ~converged & ~tipped), dataclasses.replace(short, group_uplift_time=uplift)


def unbalanced_message(response, height) -> str:
    """Why the run cannot be trusted ('' when every step balanced): the steps on which the slab
    tipped (`SlabSeriesResponse.tipped`) and those whose sliders' balance did not converge, each
    with its count and first time [s]."""
    time, converged = np.asarray(response.time), np.asarray(response.converged)
    tipped = np.asarray(response.tipped)
    newton = ~converged & ~tipped
    parts = []
    if tipped.any():
        parts.append(f"the slab tips on {int(tipped.sum())} steps (first at t = {time[tipped][0]:.4g} s): "
                     f"the overturning moment of its horizontal force at the centre of mass "
                     f"{height:g} m above the sliding surface exceeds what its weight holds back "
                     "about the leaning groups (they take no tension), which a rigid slab without "
                     "rocking cannot balance; lower height_of_centre_of_mass in the plan, spread "
                     "the groups, or give a weaker record")
    if newton.any():
        parts.append(f"the sliders' balance did not converge on {int(newton.sum())} steps (first at "
                     f"t = {time[newton][0]:.4g} s); try a smaller --time-step")
    if not parts:
        return ""
    return "; ".join(parts) + f"; {WRITTEN.format(time[~converged][0])}."


def series_slab_summary(plan, system, response):
    """(peak dict, histories dict) in SI: the slab's peaks of `run --structure slab`, with the
    isolators' whole force (`bearing_force_ratio_resultant`) in place of the friction's."""
    q = np.asarray(response.q)
    weight = float(np.sum(system.bearing_load))
    mass = weight / STANDARD_GRAVITY
    total = mass * (np.asarray(response.acceleration)[:, :2] + np.asarray(response.ground))
    force = np.asarray(response.group_force).sum(axis=1)
    peak = {"base_disp_resultant_m": float(np.max(np.hypot(q[:, 0], q[:, 1]))),
            "base_disp_x_m": float(np.max(np.abs(q[:, 0]))), "base_disp_y_m": float(np.max(np.abs(q[:, 1]))),
            "base_shear_ratio_resultant": float(np.max(np.hypot(*total.T))) / weight,
            "bearing_force_ratio_resultant": float(np.max(np.hypot(*force.T))) / weight,
            **slab_peaks(plan, q, response)}
    ground = np.asarray(response.ground)
    histories = {"time_s": np.asarray(response.time), "ground_x_mps2": ground[:, 0], "ground_y_mps2": ground[:, 1],
                 "base_disp_x_m": q[:, 0], "base_disp_y_m": q[:, 1], "bearing_force_x_N": force[:, 0],
                 "bearing_force_y_N": force[:, 1], "base_shear_ratio_x": total[:, 0] / weight,
                 "base_shear_ratio_y": total[:, 1] / weight, "rotation_rad": q[:, 2]}
    return peak, histories


def _slider_peaks(plan, system, response) -> dict:
    """{group: {slider: peak resultant displacement [m]}}."""
    sliders = np.linalg.norm(np.asarray(response.slider), axis=-1).max(axis=0)  # (G, S)
    names = system.pendulum.slider_names
    return {g["name"]: {n: float(v) for n, v in zip(names, row)} for g, row in zip(plan["groups"], sliders)}


def surface_temperature_summary(plan, system, response, histories):
    """{group: {heated surface: peak temperature rise [K]}} of a slab whose pendulums have
    heated surfaces (each group's surfaces under that group's own normal load), else None; adds
    each heated surface's history `temperature_rise_<group>_<surface>_K` to `histories`."""
    if response.surface_temperature_rise is None:
        return None
    rise = np.asarray(response.surface_temperature_rise)  # (nt, G, S)
    heated = [(e, name) for e, (name, h) in enumerate(zip(system.pendulum.slider_names,
                                                          system.pendulum.surface_heatings())) if h is not None]
    summary = {}
    for j, g in enumerate(plan["groups"]):
        summary[g["name"]] = {name: float(rise[:, j, e].max()) for e, name in heated}
        for e, name in heated:
            histories[f"temperature_rise_{g['name']}_{name}_K"] = rise[:, j, e]
    return summary
