"""`run --structure slab --plan FILE`: the slab's plan (bearing groups and loads), read in SI."""

import math
import pathlib

from ..units import parse_quantity
from ._provenance import note_input_file


def read_plan(path_text, structure: str = "slab"):
    """The plan of the slab (`structure` "slab") or of the Table 2 building's base slab
    ("building") in SI: dict with length_x, length_y, weight, centre_of_mass,
    height_of_centre_of_mass (the slab's, 0 when absent; the building's levels' centre of mass,
    `systems.building_centre_height`) and groups (each with name, x, y, load, ptfe,
    pressure, springs, radius, vertical_stiffness, isolator_file (a path relative to the plan's
    folder, for --isolator triple-fp or double-fp); None where the file leaves them out).
    `ValueError` naming the file and key for a height < 0, a radius <= 0, a share of the
    springs or a vertical stiffness that is not a number > 0, or two groups of one name; under
    the building, a height (its levels stand at Table 2's storeys) or a weight not the building's."""
    path = pathlib.Path(path_text)
    if not path.is_file():
        raise ValueError(f"--plan: {path} is not a file.")
    from ..formats import read_json_document

    try:
        plan = read_json_document(path, "slab's plan (docs/tutorials/pendulum.md)")
    except ValueError as error:
        raise ValueError(f"--plan: {error}") from None
    where = f"{path}"

    def q(value, dimension, key):
        return parse_quantity(value, dimension, where=f"{where}: {key}")

    if not isinstance(plan, dict):
        raise ValueError(f"--plan: {path}: expected a JSON object with {', '.join(PLAN_KEYS)}.")
    _refuse_unknown(path, plan, PLAN_KEYS, "")
    for key in ("length_x", "length_y", "weight", "groups"):
        if key not in plan:
            raise ValueError(f"--plan: {path} lacks '{key}'.")
    if not isinstance(plan["groups"], list) or not all(isinstance(g, dict) for g in plan["groups"]):
        raise ValueError(f"--plan: {path}: 'groups' must be a list of objects, one per bearing group.")
    out = {
        "length_x": q(plan["length_x"], "length", "length_x"),
        "length_y": q(plan["length_y"], "length", "length_y"),
        "weight": q(plan["weight"], "force", "weight"),
    }
    com = plan.get("centre_of_mass")
    out["centre_of_mass"] = (
        (out["length_x"] / 2, out["length_y"] / 2) if com is None
        else tuple(q(v, "length", "centre_of_mass") for v in com)
    )
    if structure == "building":
        _building_plan(path, plan, out)
    else:
        out["height_of_centre_of_mass"] = q(plan.get("height_of_centre_of_mass", "0m"), "length",
                                            "height_of_centre_of_mass")
    if not out["height_of_centre_of_mass"] >= 0:
        raise ValueError(f"--plan: {path}: height_of_centre_of_mass must be >= 0 (the centre of mass "
                         "above the sliding surface; 0 for no overturning), got "
                         f"{plan['height_of_centre_of_mass']}.")
    groups = []
    for i, g in enumerate(plan["groups"]):
        name = str(g.get("name", f"group {i + 1}"))
        if any(name == other["name"] for other in groups):
            raise ValueError(f"--plan: {path}: two groups are named {name!r} (groups {_index(groups, name) + 1} "
                             f"and {i + 1}); give each group its own name.")
        _refuse_unknown(path, g, GROUP_KEYS, f"{name}.")
        for key in ("x", "y", "load"):
            if key not in g:
                raise ValueError(f"--plan: {path}: {name} lacks '{key}'.")
        groups.append({
            "name": name,
            "x": q(g["x"], "length", f"{name}.x"),
            "y": q(g["y"], "length", f"{name}.y"),
            "load": q(g["load"], "force", f"{name}.load"),
            "ptfe": g.get("ptfe"),
            "pressure": g.get("pressure"),
            "springs": _ratio(path, g, name, "springs", "the group's share of the springs' stiffness "
                              "(1 for all groups alike; their period is --isolation-period)"),
            "radius": None if g.get("radius") is None else q(g["radius"], "length", f"{name}.radius"),
            "vertical_stiffness": _ratio(path, g, name, "vertical_stiffness", "the group's vertical "
                                         "stiffness relative to the other groups'"),
            "isolator_file": (None if g.get("isolator_file") is None
                              else path.parent / str(g["isolator_file"])),
        })
        _check_group(path, groups[-1], q)
        if groups[-1]["isolator_file"] is not None:  # an input of the run, hashed in its results
            note_input_file(f"--plan {path}: {name}.isolator_file", groups[-1]["isolator_file"])
    out["groups"] = groups
    from ..structures import check_plan

    try:
        check_plan(length_x=out["length_x"], length_y=out["length_y"], weight=out["weight"],
                   centre_of_mass=out["centre_of_mass"], positions=[(g["x"], g["y"]) for g in groups],
                   loads=[g["load"] for g in groups], names=[g["name"] for g in groups])
    except ValueError as error:
        raise ValueError(f"--plan: {path}: {str(error).removeprefix('plan: ')}") from None
    return out


def _building_plan(path, plan: dict, out: dict) -> None:
    """The building's plan: no height of its own, Table 2's weight; its centre of mass's height."""
    from ..systems import building_centre_height
    from ..tables import load_table2

    if "height_of_centre_of_mass" in plan:
        raise ValueError(f"--plan: {path}: height_of_centre_of_mass is the building's, from its levels at "
                         "Table 2's storey heights; leave it out of a plan for --structure building.")
    weight = float(load_table2().total_weight)
    if abs(out["weight"] - weight) > 1e-3 * weight:
        raise ValueError(f"--plan: {path}: weight is {plan['weight']}, and the building on the plan weighs "
                         f"{weight / 1e3:.6g} kN (Table 2: 672 kip); write that weight, which the groups' "
                         "loads add up to.")
    out["weight"] = weight
    out["height_of_centre_of_mass"] = building_centre_height()


PLAN_KEYS = ("length_x", "length_y", "weight", "centre_of_mass", "height_of_centre_of_mass", "groups")
"""The keys of a plan (docs/tutorials/pendulum.md)."""

GROUP_KEYS = ("name", "x", "y", "load", "ptfe", "pressure", "springs", "radius", "vertical_stiffness",
              "isolator_file")
"""The keys of a plan's group; the isolator is the run's `--isolator` (a group may give its own
`isolator_file` of that isolator)."""


def _refuse_unknown(path, entries: dict, known: tuple, prefix: str) -> None:
    """`ValueError` naming the plan file and the first key of `entries` that is not `known`
    (a misspelt key would otherwise be left out without a word)."""
    unknown = [key for key in entries if key not in known]
    if unknown:
        key = unknown[0]
        hint = (" The groups' isolator is --isolator's (a group of series pendulums may give its own "
                "isolator_file).") if "isolator" in key else ""
        raise ValueError(f"--plan: {path}: {prefix}{key} is not a key of a plan{' group' if prefix else ''}; "
                         f"accepted: {', '.join(known)}.{hint}")


def _index(groups, name) -> int:
    return next(j for j, other in enumerate(groups) if other["name"] == name)


def _ratio(path, group: dict, name: str, key: str, meaning: str) -> float | None:
    """The plain number `group[key]` (None when absent); `ValueError` naming the plan file, the
    group and the key, and saying what the number means, for anything else."""
    value = group.get(key)
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, int | float):
        try:
            return float(str(value))
        except ValueError:
            raise ValueError(f"--plan: {path}: {name}.{key} is {meaning}, a plain number such as 1.0; "
                             f"got {value!r}.") from None
    return float(value)


def _check_group(path, group, quantity) -> None:
    """`ValueError` naming the plan file and the group's key for a PTFE type not in Table 1, a
    contact pressure that is not a pressure > 0 (read by `quantity(text, dimension, key)`), a
    radius <= 0, a share of the springs < 0 or a relative vertical stiffness <= 0."""
    from ..tables import PTFE_TYPES

    name = group["name"]
    if group["ptfe"] is not None and str(group["ptfe"]).upper() not in PTFE_TYPES:
        raise ValueError(f"--plan: {path}: {name}.ptfe is {group['ptfe']!r}, not a PTFE type of Table 1; "
                         f"accepted: {', '.join(PTFE_TYPES)}.")
    if group["pressure"] is not None and not quantity(group["pressure"], "pressure", f"{name}.pressure") > 0:
        raise ValueError(f"--plan: {path}: {name}.pressure must be > 0 (the bearings' contact pressure), "
                         f"got {group['pressure']}.")
    if group["radius"] is not None and not group["radius"] > 0:
        raise ValueError(f"--plan: {path}: {name}.radius must be > 0 (the radius of its friction "
                         f"pendulum's surface), got {group['radius']:g} m.")
    springs = group["springs"]
    if springs is not None and not (math.isfinite(springs) and springs >= 0):
        raise ValueError(f"--plan: {path}: {name}.springs must be >= 0 (its share of the springs' "
                         f"stiffness), got {springs:g}.")
    stiffness = group["vertical_stiffness"]
    if stiffness is not None and not (math.isfinite(stiffness) and stiffness > 0):
        raise ValueError(f"--plan: {path}: {name}.vertical_stiffness must be > 0 (relative to the "
                         f"other groups'), got {stiffness:g}.")
