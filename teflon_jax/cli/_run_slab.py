"""`teflon-jax run --structure slab --plan FILE`: the rigid slab on bearing groups (flat sliders
with springs, or single friction pendulums with `--isolator single-fp`), with the overturning
of its plan's `height_of_centre_of_mass`; its peaks and each group's normal load."""

import numpy as np

from ..units import parse_quantity
from ._plan_file import read_plan
from ._run_bearing import bearing_of_flags

NORMAL_LOAD_NOTE = ("N_g = W_g (1 + a_v / g) + dN_g, dN_g of a rigid slab on vertical supports of "
                    "equal (or the plan's relative) stiffness under the moment h H of the horizontal "
                    "force H at the start of each step; while N_g <= 0 the group carries no shear "
                    "and the others take its share (where at least three groups off one line stay "
                    "down; else the lever rule's loads, a negative N_g the tension a bonded "
                    "support would need)")


def _radii(args, groups):
    """R_g [m] of `--isolator single-fp` (`--radius`, a group's `radius` overriding it), None
    for flat sliders; `ValueError` naming the flag or key that does not fit the isolator."""
    for g in groups:
        if g["isolator_file"] is not None:
            raise ValueError(f"--plan: {g['name']}.isolator_file applies with --isolator triple-fp or "
                             f"double-fp only, not {args.isolator}; leave it out or give that isolator.")
    if args.isolator != "single-fp":
        for g in groups:
            if g["radius"] is not None:
                raise ValueError(f"--plan: {g['name']}.radius applies with --isolator single-fp "
                                 "only (flat sliders have none); add it or leave the radius out.")
        return None
    for g in groups:
        if g["springs"] is not None:
            raise ValueError(f"--plan: {g['name']}.springs conflicts with --isolator single-fp (each "
                             "group restores with its pendulum, W_g / R_g); leave 'springs' out.")
    return [args.radius if g["radius"] is None else g["radius"] for g in groups]


def build_slab(args, ground_x, ground_y, time_step, period, damping):
    """(system, plan) of `--structure slab --plan FILE` (`slab_on_bearings`) under the ground
    `Signal`s; `period` [s] of the springs (flat sliders; ignored for the pendulum) and the
    isolation `damping` ratio."""
    from ..systems import slab_on_bearings

    if args.plan is None:
        raise ValueError("--plan: --structure slab needs a plan file (bearing groups and loads).")
    plan = read_plan(args.plan)
    groups = plan["groups"]
    radii = _radii(args, groups)
    bearings = [bearing_of_flags(args, g["ptfe"] or args.ptfe, g["pressure"] or args.pressure,
                                 f"--plan {g['name']}") for g in groups]
    stiffness = [g["vertical_stiffness"] for g in groups]
    options = (dict(isolator="single-fp", radii=radii) if radii is not None else
               dict(isolation_period=period, spring_shares=[1.0 if g["springs"] is None else g["springs"]
                                                            for g in groups]))
    system = slab_on_bearings(
        length_x=plan["length_x"], length_y=plan["length_y"], weight=plan["weight"],
        centre_of_mass=plan["centre_of_mass"], positions=[(g["x"], g["y"]) for g in groups],
        bearings=bearings, loads=[g["load"] for g in groups], ground_x=ground_x, ground_y=ground_y,
        time_step=time_step, isolation_damping=damping, names=[g["name"] for g in groups],
        contact_pressures=[parse_quantity(g["pressure"] or args.pressure, "pressure",
                                          where=f"--plan {g['name']}") for g in groups],
        height_of_centre_of_mass=plan["height_of_centre_of_mass"],
        vertical_stiffness=None if all(k is None for k in stiffness) else [1.0 if k is None else k
                                                                         for k in stiffness],
        **options)
    plan["radii"] = radii
    return system, plan


def slab_peaks(plan, q, response) -> dict:
    """The slab's peak rotation, corner and group displacements (SI) from coordinates q."""
    from ..systems import slab_corners, slab_point_displacement

    corners = slab_corners(plan["length_x"], plan["length_y"])
    corner = np.asarray(slab_point_displacement(q, corners, plan["centre_of_mass"]))
    bearing = np.asarray(response.bearing_displacement)
    return {
        "rotation_rad": float(np.max(np.abs(q[:, 2]))),
        "corner_disp_resultant_m": [float(v) for v in np.hypot(corner[..., 0], corner[..., 1]).max(axis=0)],
        "group_disp_resultant_m": {g["name"]: float(v) for g, v in
                                   zip(plan["groups"], np.hypot(bearing[..., 0], bearing[..., 1]).max(axis=0))},
    }


def group_normal_loads(system, response):
    """(N_g history (nt, G) [N], uplift time per group (G,) [s]): the state's loads with
    overturning, else W_g times the vertical record's factor (or W_g throughout)."""
    weights = np.asarray(system.bearing_load)
    if response.normal_load is not None:
        return np.asarray(response.normal_load), np.asarray(response.group_uplift_time)
    if response.load_factor is None:
        return np.broadcast_to(weights, (np.size(response.time), weights.size)), np.zeros(weights.size)
    loads = np.asarray(response.load_factor)[:, None] * weights
    return loads, np.full(weights.size, float(response.uplift_time))


def normal_load_summary(plan, system, response, units) -> tuple[dict, list]:
    """(JSON entry "normal_load", printed lines): each group's peak and least normal load [N]
    (negative: the tension a bonded support would need) and its uplift time [s]."""
    loads, uplift = group_normal_loads(system, response)
    name, factor = units.force
    groups, lines = {}, []
    radii = plan.get("radii") or [None] * len(plan["groups"])
    for g, history, time, radius in zip(plan["groups"], loads.T, uplift, radii):
        groups[g["name"]] = {"static_N": g["load"], "peak_N": float(history.max()),
                             "min_N": float(history.min()), "uplift_time_s": float(time),
                             "radius_m": radius}
        lines.append(f"normal load {g['name']}: peak {history.max() / factor:.4g} {name}, least "
                     f"{history.min() / factor:.4g} {name}, uplift {float(time):.4g} s")
    entry = {"height_of_centre_of_mass_m": plan["height_of_centre_of_mass"], "groups": groups,
             "note": NORMAL_LOAD_NOTE}
    return {"normal_load": entry}, lines


def suite_normal_load(plan, groups, pair) -> dict:
    """The "normal_load" entry of `normal_load_summary` (its group keys, without the note) of
    pair index `pair` of a suite's `SuiteResult.groups` ((P, G) peak and least N_g [N], uplift
    time [s]) on the slab `plan` of `build_slab` (or `series_plan`: each group's isolator file)."""
    radii = plan.get("radii") or [None] * len(plan["groups"])
    files = plan.get("isolator_files")
    entry = {g["name"]: {"static_N": g["load"], "peak_N": float(groups["peak_N"][pair, j]),
                         "min_N": float(groups["min_N"][pair, j]),
                         "uplift_time_s": float(groups["uplift_time_s"][pair, j]), "radius_m": radius}
             | ({} if files is None else {"isolator_file": files[j]})
             for j, (g, radius) in enumerate(zip(plan["groups"], radii))}
    return {"normal_load": {"height_of_centre_of_mass_m": plan["height_of_centre_of_mass"], "groups": entry}}
