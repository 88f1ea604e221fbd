"""Peaks and histories of a run's response, in SI (each key names its unit): the base's
displacement and shear, the bearings' force, the building's storeys and levels, the slab's
rotation, corners and groups, the sliders of series pendulums and their surfaces' heating.
One reducer per response layout (`_run_response` picks it by the system's type)."""

import numpy as np

from ..units import STANDARD_GRAVITY


def _peak(values):
    return float(np.max(np.abs(values)))


def _resultant(x, y):
    return np.hypot(np.asarray(x), np.asarray(y))


def _storey_ratios(system, response) -> dict:
    """The building's peak drift ratio per storey and total acceleration per level (0 the base
    slab), in x, in y and as resultants (`bidirectional_storey_peaks`)."""
    from ..systems import bidirectional_storey_peaks
    from ..tables import load_table2

    peaks = bidirectional_storey_peaks(response, system, load_table2().storey_height)
    out = {}
    for key, name, scale in (("storey_drift", "storey_drift_ratio", 1.0),
                             ("level_acceleration", "level_acceleration_g", STANDARD_GRAVITY)):
        for index, axis in enumerate("xy"):
            out[f"{name}_{axis}"] = (peaks[key][index] / scale).tolist()
        out[f"{name}_resultant"] = (peaks[f"{key}_resultant"] / scale).tolist()
    return out


def bidirectional_peaks(structure, system, response, plan):
    """(peak dict, histories dict) in SI of the `StructureResponse` of flat sliders or single
    pendulums under two components (the rigid mass, the building or the slab of `plan`)."""
    q = np.asarray(response.displacement)
    m, R = np.asarray(system.mass), np.asarray(system.influence)
    total_acc = np.asarray(response.total_acceleration)
    force = np.einsum("tn,n,nd->td", total_acc, m, R)  # on the structure above the bearings
    weight = float(np.sum(m * R[:, 0])) * STANDARD_GRAVITY
    n = q.shape[1] // 2
    ix, iy = (0, 1) if structure == "slab" else (0, n)
    base_x, base_y = q[:, ix], q[:, iy]
    bearing_force = -np.asarray(response.friction_force).sum(axis=1)
    peak = {
        "base_disp_resultant_m": float(np.max(_resultant(base_x, base_y))),
        "base_disp_x_m": _peak(base_x),
        "base_disp_y_m": _peak(base_y),
        "base_shear_ratio_resultant": float(np.max(_resultant(force[:, 0], force[:, 1]))) / weight,
        "friction_force_ratio_resultant": float(np.max(_resultant(*bearing_force.T))) / weight,
    }
    if structure == "building":
        drift = _resultant(q[:, 1:n] - q[:, 0:n - 1], q[:, n + 1:] - q[:, n:-1])
        floor_acc = _resultant(total_acc[:, 1:n], total_acc[:, n + 1:])
        floors = m[1:n]
        storey = _resultant((floors * total_acc[:, 1:n]).sum(1), (floors * total_acc[:, n + 1:]).sum(1))
        peak["storey_drift_resultant_m"] = [float(v) for v in drift.max(axis=0)]
        peak["floor_acceleration_resultant_g"] = [float(v) for v in floor_acc.max(axis=0) / STANDARD_GRAVITY]
        peak["first_storey_shear_ratio_resultant"] = float(storey.max()) / (float(floors.sum()) * STANDARD_GRAVITY)
        peak.update(_storey_ratios(system, response))
    if structure == "slab":
        peak.update(slab_peaks(plan, q, response))
    histories = {
        "time_s": np.asarray(response.time),
        "ground_x_mps2": np.asarray(response.ground)[:, 0],
        "ground_y_mps2": np.asarray(response.ground)[:, 1],
        "base_disp_x_m": base_x,
        "base_disp_y_m": base_y,
        "bearing_force_x_N": bearing_force[:, 0],
        "bearing_force_y_N": bearing_force[:, 1],
        "base_shear_ratio_x": force[:, 0] / weight,
        "base_shear_ratio_y": force[:, 1] / weight,
    }
    if structure == "slab":
        histories["rotation_rad"] = q[:, 2]
    return peak, histories


def triple_peaks(structure, system, response, plan=None):
    """(peak dict, histories dict) in SI of series pendulums' `StructureResponse` under one
    component (`simulate_triple_structure`): the base displacement,
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
    if structure == "building":
        from ..tables import load_table2

        height = np.broadcast_to(np.asarray(load_table2().storey_height, float), (m.size - 1,))
        peak["storey_drift_resultant_m"] = np.max(np.abs(np.diff(u, axis=1)), 0).tolist()
        peak["storey_drift_ratio_x"] = (np.max(np.abs(np.diff(u, axis=1)), 0) / height).tolist()
        peak["floor_acceleration_resultant_g"] = (np.max(np.abs(acc[:, 1:]), 0) / STANDARD_GRAVITY).tolist()
        peak["first_storey_shear_ratio_resultant"] = peak["base_shear_ratio_resultant"]
    zeros = np.zeros_like(force)
    histories = {"time_s": np.asarray(response.time),
                 "ground_x_mps2": np.asarray(response.ground)[:, 0], "ground_y_mps2": zeros,
                 "base_disp_x_m": u[:, 0], "base_disp_y_m": zeros, "bearing_force_x_N": force,
                 "bearing_force_y_N": zeros, "base_shear_ratio_x": shear, "base_shear_ratio_y": zeros}
    for index, name in enumerate(system.pendulum.slider_names):
        histories[f"slider_{name}_m"] = np.asarray(response.slider)[:, index]
    return peak, histories


def biaxial_peaks(structure, system, response, plan=None):
    """(peak dict, histories dict) in SI of series pendulums' `StructureResponse` under two
    components (`biaxial_response`): resultant peaks of the base displacement, of the force on
    all masses over W (as the two-component Monte Carlo), of the bearing force over W, per
    slider, and for the building per storey and level."""
    system = system.uniaxial  # a `BiaxialStructureOnTriple`'s structure and isolator
    time, force, sliders = (np.asarray(a) for a in (response.time, response.bearing_force, response.slider))
    m, n = np.asarray(system.mass), np.asarray(system.mass).size
    u = np.asarray(response.displacement).reshape(time.size, 2, n)  # (nt, 2, n)
    acc = np.asarray(response.total_acceleration).reshape(time.size, 2, n)
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
    if structure == "building":
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


def slab_series_peaks(structure, system, response, plan):
    """(peak dict, histories dict) in SI: the slab's peaks of `run --structure slab`, with the
    isolators' whole force (`bearing_force_ratio_resultant`) in place of the friction's."""
    q = np.asarray(response.displacement)
    weight = float(np.sum(system.bearing_load))
    mass = weight / STANDARD_GRAVITY
    total = mass * np.asarray(response.total_acceleration)[:, :2]
    force = np.asarray(response.bearing_force).sum(axis=1)
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


def slider_peaks(plan, system, response) -> dict:
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


def slab_peaks(plan, q, response) -> dict:
    """The slab's peak rotation, corner and group displacements (SI) from coordinates q."""
    from ..structures import slab_corners, slab_point_displacement

    corners = slab_corners(plan["length_x"], plan["length_y"])
    corner = np.asarray(slab_point_displacement(q, corners, plan["centre_of_mass"]))
    bearing = np.asarray(response.bearing_displacement)
    return {
        "rotation_rad": float(np.max(np.abs(q[:, 2]))),
        "corner_disp_resultant_m": [float(v) for v in np.hypot(corner[..., 0], corner[..., 1]).max(axis=0)],
        "group_disp_resultant_m": {g["name"]: float(v) for g, v in
                                   zip(plan["groups"], np.hypot(bearing[..., 0], bearing[..., 1]).max(axis=0))},
    }


