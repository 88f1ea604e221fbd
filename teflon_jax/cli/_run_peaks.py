"""Peaks and histories of a run's response, in SI (each key names its unit): the base's
displacement and shear, the isolators' force, the building's storeys and levels, the slab's
rotation, corners and groups, the sliders of series pendulums and every heated surface's
temperature rise.
One formatter for every isolator, structure and number of components: the numbers are the
reducers of `teflon_jax.studies` (`response_peaks`) over the run's `StructureResponse`; a part
the response does not hold is absent."""

import numpy as np

from ..units import STANDARD_GRAVITY


def _floats(values) -> list:
    return np.asarray(values, dtype=float).tolist()


def _components(values, axis: int = 0) -> tuple:
    """(x, y) of the components along `axis` of a peak (C, ...) or history (nt, C, ...), y
    zeros under one component (C = 1)."""
    values = np.asarray(values)
    x = np.take(values, 0, axis=axis)
    return x, (np.take(values, 1, axis=axis) if values.shape[axis] == 2 else np.zeros_like(x))


def run_peaks(system, response, plan=None):
    """(peak dict, histories dict) in SI of any structure's `StructureResponse` (`plan`: the
    slab's, or None): resultant peaks of the base displacement and base shear (V / W, the
    force the bearings carry over the weight they carry: `studies.base_shear_ratio`), of the
    isolators' force over W (`friction_force_ratio_resultant` of flat sliders and single
    pendulums, `bearing_force_ratio_resultant` of series pendulums), per slider, per storey
    and level of a building, and of a slab's rotation, corners and groups. Under one component
    the y entries are zeros."""
    from ..studies import (
        base_displacement,
        base_shear_ratio,
        isolator_force,
        response_layout,
        response_peaks,
    )
    from ..tables import load_table2

    layout = response_layout(system)
    values = response_peaks(layout, response, load_table2().storey_height if layout.building else None)
    base_x, base_y = _components(values["base_disp"])
    peak = {"base_disp_resultant_m": float(values["base_disp_resultant"]), "base_disp_x_m": float(base_x),
            "base_disp_y_m": float(base_y), "base_shear_ratio_resultant": float(values["base_shear_ratio_resultant"])}
    if "isolator_force_ratio_resultant" in values:
        kind = "friction" if response.friction_force is not None else "bearing"
        peak[f"{kind}_force_ratio_resultant"] = float(values["isolator_force_ratio_resultant"])
    if "slider_travel" in values and np.ndim(values["slider_travel"]) == 1:
        peak["slider_disp_m"] = dict(zip(system.pendulum.slider_names, _floats(values["slider_travel"])))
    if layout.building:
        peak.update(_storey_peaks(values))
    if layout.rotation is not None:  # the slab's (x, y, rotation), alone or under the building
        slab = [layout.levels[0][0], layout.levels[1][0], layout.rotation]
        peak.update(slab_peaks(plan, np.asarray(response.displacement)[:, slab], values))
    return peak, _histories(system, response, layout, base_displacement(layout, response),
                            base_shear_ratio(layout, response), isolator_force(response))


def _storey_peaks(values) -> dict:
    """A building's peaks: per storey (drift [m], drift ratio [-]) and level (total
    acceleration [g], 0 the base slab; `floor_acceleration_resultant_g` the floors 1..)."""
    out = {"storey_drift_resultant_m": _floats(values["storey_drift_resultant"]),
           "floor_acceleration_resultant_g": _floats(np.asarray(values["level_acceleration_resultant"])[1:]
                                                     / STANDARD_GRAVITY),
           "first_storey_shear_ratio_resultant": float(values["first_storey_shear_ratio_resultant"])}
    for key, name, scale in (("storey_drift_ratio", "storey_drift_ratio", 1.0),
                             ("level_acceleration", "level_acceleration_g", STANDARD_GRAVITY)):
        for axis, part in zip("xy", _components(values[key])):
            out[f"{name}_{axis}"] = _floats(part / scale)
        out[f"{name}_resultant"] = _floats(np.asarray(values[f"{key}_resultant"]) / scale)
    return out


def _histories(system, response, layout, base, shear, force) -> dict:
    """The run's histories (SI): time, ground, base displacement, isolator force and base
    shear ratio in x and y, a slab's rotation and each slider's displacement (not per group)."""
    histories = {"time_s": np.asarray(response.time)}
    for name, values in (("ground_{}_mps2", response.ground), ("base_disp_{}_m", base),
                         ("bearing_force_{}_N", force), ("base_shear_ratio_{}", shear)):
        if values is not None:
            for axis, part in zip("xy", _components(values, axis=1)):
                histories[name.format(axis)] = part
    if layout.rotation is not None:
        histories["rotation_rad"] = np.asarray(response.displacement)[:, layout.rotation]
    slider = None if response.slider is None else np.asarray(response.slider)
    if slider is not None and slider.ndim == 1 + layout.components:  # one isolator's sliders, not groups
        for index, name in enumerate(system.pendulum.slider_names):
            if layout.components == 1:
                histories[f"slider_{name}_m"] = slider[:, index]
            else:
                histories[f"slider_{name}_x_m"], histories[f"slider_{name}_y_m"] = slider[:, index].T
    return histories


def slider_peaks(plan, system, response) -> dict:
    """{group: {slider: peak resultant displacement [m]}} of a slab's groups of sliders."""
    from ..studies import peak, slider_travel

    rows = np.asarray(peak(slider_travel(response)))  # (G, S)
    names = system.pendulum.slider_names
    return {g["name"]: dict(zip(names, _floats(row))) for g, row in zip(plan["groups"], rows)}


def surface_temperature_summary(plan, system, response, histories):
    """The peak surface temperature rise [K] of each heated surface, or None without heating:
    {surface: K} of one isolator (flat sliders and single pendulums: "surface"; a series
    pendulum's by its slider names), {group: {surface: K}} of a slab's groups (`plan`, each
    under its own normal load); adds each heated surface's history
    `temperature_rise_[<group>_]<surface>_K` to `histories`."""
    if response.surface_temperature_rise is None:
        return None
    rise = np.asarray(response.surface_temperature_rise)  # (nt, G, S)
    pendulum = system.pendulum
    surfaces = [(0, "surface")] if pendulum is None else [
        (e, name) for e, (name, h) in enumerate(zip(pendulum.slider_names, pendulum.surface_heatings()))
        if h is not None]
    peaks = rise.max(axis=0)  # (G, S)
    groups = [None] if plan is None else [g["name"] for g in plan["groups"]]
    summary = {}
    for j, group in enumerate(groups):
        row = {name: float(peaks[j, e]) for e, name in surfaces}
        for e, name in surfaces:
            histories["_".join(["temperature_rise", *([group] if group else []), name, "K"])] = rise[:, j, e]
        summary.update(row if group is None else {group: row})
    return summary


def temperature_lines(plan, rises) -> list:
    """The printed lines of `surface_temperature_summary`'s peaks."""
    rows = {"": rises} if plan is None else {f" {name}": row for name, row in rises.items()}
    return [f"surface temperature rise{name}: " + ", ".join(f"{e} {v:.4g} K" for e, v in row.items())
            for name, row in rows.items()]


def slab_peaks(plan, q, values) -> dict:
    """The slab's peak rotation, corner and group displacements (SI) from coordinates q and
    the reducers' peaks `values` (`response_peaks`)."""
    from ..structures import slab_corners, slab_point_displacement

    corners = slab_corners(plan["length_x"], plan["length_y"])
    corner = np.asarray(slab_point_displacement(q, corners, plan["centre_of_mass"]))
    return {
        "rotation_rad": float(values["rotation"]),
        "corner_disp_resultant_m": _floats(np.hypot(corner[..., 0], corner[..., 1]).max(axis=0)),
        "group_disp_resultant_m": dict(zip([g["name"] for g in plan["groups"]],
                                           _floats(values["group_disp_resultant"]))),
    }
