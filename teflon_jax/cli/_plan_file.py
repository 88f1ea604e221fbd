"""`run --structure slab --plan FILE`: the slab's plan (bearing groups and loads), read in SI."""

import json
import math
import pathlib

from ..units import parse_quantity


def read_plan(path_text):
    """The slab plan in SI: dict with length_x, length_y, weight, centre_of_mass,
    height_of_centre_of_mass (0 when absent) and groups (each with name, x, y, load, ptfe,
    pressure, springs, radius, vertical_stiffness, isolator_file (a path relative to the plan's
    folder, for --isolator triple-fp or double-fp); None where the file leaves them out).
    `ValueError` naming the file and key for a height < 0, a radius <= 0 or a vertical
    stiffness <= 0."""
    path = pathlib.Path(path_text)
    if not path.is_file():
        raise ValueError(f"--plan: {path} is not a file.")
    try:
        plan = json.loads(path.read_text())
    except json.JSONDecodeError as error:
        raise ValueError(f"--plan: {path}, line {error.lineno}: not valid JSON ({error.msg}).") from None
    where = f"{path}"

    def q(value, dimension, key):
        return parse_quantity(value, dimension, where=f"{where}: {key}")

    for key in ("length_x", "length_y", "weight", "groups"):
        if key not in plan:
            raise ValueError(f"--plan: {path} lacks '{key}'.")
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
    out["height_of_centre_of_mass"] = q(plan.get("height_of_centre_of_mass", "0m"), "length",
                                        "height_of_centre_of_mass")
    if not out["height_of_centre_of_mass"] >= 0:
        raise ValueError(f"--plan: {path}: height_of_centre_of_mass must be >= 0 (the centre of mass "
                         "above the sliding surface; 0 for no overturning), got "
                         f"{plan['height_of_centre_of_mass']}.")
    groups = []
    for i, g in enumerate(plan["groups"]):
        name = str(g.get("name", f"group {i + 1}"))
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
            "springs": None if g.get("springs") is None else float(g["springs"]),
            "radius": None if g.get("radius") is None else q(g["radius"], "length", f"{name}.radius"),
            "vertical_stiffness": (None if g.get("vertical_stiffness") is None
                                   else float(g["vertical_stiffness"])),
            "isolator_file": (None if g.get("isolator_file") is None
                              else path.parent / str(g["isolator_file"])),
        })
        _check_group(path, groups[-1])
    out["groups"] = groups
    return out


def _check_group(path, group) -> None:
    """`ValueError` naming the plan file and the group's key for a radius <= 0 or a relative
    vertical stiffness <= 0."""
    name = group["name"]
    if group["radius"] is not None and not group["radius"] > 0:
        raise ValueError(f"--plan: {path}: {name}.radius must be > 0 (the radius of its friction "
                         f"pendulum's surface), got {group['radius']:g} m.")
    stiffness = group["vertical_stiffness"]
    if stiffness is not None and not (math.isfinite(stiffness) and stiffness > 0):
        raise ValueError(f"--plan: {path}: {name}.vertical_stiffness must be > 0 (relative to the "
                         f"other groups'), got {stiffness:g}.")
