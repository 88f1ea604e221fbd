"""`run --structure slab --plan FILE`: the slab's plan (bearing groups and loads), read in SI."""

import json
import pathlib

from ..units import parse_quantity


def read_plan(path_text):
    """The slab plan in SI: dict with length_x, length_y, weight, centre_of_mass, groups."""
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
            "springs": float(g.get("springs", 1.0)),
        })
    out["groups"] = groups
    return out
