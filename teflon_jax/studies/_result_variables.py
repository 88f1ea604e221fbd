"""The variables of a Monte Carlo's results (`MonteCarloResult`, its Dataset and files, the
distributed runs' NetCDF files, the suites' flags and surfaces): name -> units (CF/UDUNITS)
and long name; the table columns and the streamed files' layout of the surfaces' peaks."""

import numpy as np

VARIABLES = {
    "base_disp": ("m", "peak |base displacement| relative to the ground"),
    "base_shear_ratio": ("1", "peak |base shear| / weight above the isolators"),
    "smooth_base_disp": ("m", "smooth maximum (log-mean-cosh) of |base displacement|"),
    "smooth_base_shear_ratio": ("1", "smooth maximum (log-mean-cosh) of |base shear| / weight"),
    "converged": ("1", "every time step's Newton solve converged, within the bearings' pressure law (False: peaks "
                  "not trusted)"),
}
"""Peak variables of a `MonteCarloResult`: name -> (units, long name)."""

STOREY_VARIABLES = {
    "storey_drift": ("storey", "1", "peak |interstorey drift| / storey height (storey j: level j-1 to j)"),
    "floor_acceleration": ("level", "m s-2", "peak |total acceleration| of the level (0: base slab)"),
}
"""A building's storey peaks, when the run kept them: name -> (dimension, units, long name);
dimension "storey" 1.. (storey 1 from the base slab to floor 1), "level" 0.. (0 the base slab
on the isolators, j >= 1 floor j)."""

GROUP_VARIABLES = {
    "group_peak_load": ("N", "largest normal load of the bearing group"),
    "group_min_load": ("N", "least normal load of the bearing group (0: it lifted)"),
    "group_uplift_time": ("s", "time with the bearing group's normal load <= 0"),
}
"""A structure on a plan's peaks per bearing group (dimension "group", labelled by the group
names of `attrs["group_names"]` where given), when its groups share the weight unevenly
(overturning or a vertical component): name -> (units, long name)."""

SURFACE_VARIABLES = {
    "slider_travel": ("slider", "m", "peak travel of the series pendulum's slider on its surface (|s| under one "
                      "component, the length of (s_x, s_y) under two)"),
    "surface_temperature_rise": ("heated_surface", "K", "peak temperature rise s dT of the heated sliding surface "
                                 "(the rise its friction reads)"),
}
"""The peaks of each bearing group's surfaces, where the isolator has them: a series pendulum's
sliders' travel, every heated surface's temperature rise: name -> (dimension, units, long
name), on dimensions ("group", dimension); the dimension's labels are `attrs["<dimension>_names"]`
(the pendulum's slider names; "surface" for a flat slider or single pendulum)."""

BEYOND_PRESSURE_LAW = ("1", "the contact pressure went beyond where Table 1's extended rows give Eq. 1 "
                       "constants (peaks not trusted)")
"""The units and long name of `beyond_pressure_law`."""

TIPPED = ("1", "the run's first unbalanced step was one on which the slab (or the building's base) could not "
          "rest on its bearing groups (peaks not trusted)")
"""The units and long name of `tipped`."""

RUN_FLAGS = {"beyond_pressure_law": BEYOND_PRESSURE_LAW, "tipped": TIPPED}
"""The flags of a run (or a suite pair) beside `converged`, each kept where the structure has it:
`beyond_pressure_law` under Table 1's pressure law, `tipped` on a plan's overturning loads ->
(units, long name)."""

DESIGN_UNITS = {
    "isolation_period": ("s", "isolation period T_b"),
    "pressure": ("Pa", "bearing contact pressure"),
    "isolation_damping": ("1", "isolation damping ratio zeta_b"),
    "f_max": ("1", "Eq. 1 friction coefficient at high velocity f_max"),
    "delta_f": ("1", "Eq. 1 f_max - f_min"),
    "rate_a": ("s m-1", "Eq. 1 rate parameter a"),
    "breakaway_ratio": ("1", "Eq. 17 breakaway ratio b"),
    "radius": ("m", "radius of curvature R of the friction pendulum's surface"),
    "capacity": ("m", "displacement capacity d of the friction pendulum's surface (its restrainer beyond)"),
    "friction_factor": ("1", "property modification factor on every surface's Eq. 1 friction (f_max, delta_f)"),
}

BEARING_DRAW = ("1", "index of the bearing posterior's draw the run took (its constants in place of "
                     "the bearing file's point values)")


def surface_columns(arrays: dict, labels: dict, groups) -> dict:
    """{"<name>_<unit>_[<group>_]<surface>": (...)}: the surface peaks `arrays` {name: (..., G,
    S)} of `SURFACE_VARIABLES` one column per group and surface, labelled by `labels`
    {"<dimension>_names": ...} and the G `groups` (named where there are several)."""
    columns = {}
    for name, (dim, unit, _) in SURFACE_VARIABLES.items():
        if arrays.get(name) is not None:
            values = np.asarray(arrays[name])
            for j, group in enumerate(groups):
                for e, label in enumerate(labels[f"{dim}_names"]):
                    columns["_".join([name, unit, *([group] if len(groups) > 1 else []), label])] = values[..., j, e]
    return columns


def surface_shapes(groups: int, labels: dict) -> tuple[dict, dict]:
    """({name: (G, S)} of the surface peaks a structure of `groups` groups with the surfaces
    `labels` (`surface_attributes`) reports, `labels`): `surface_layout`'s first arguments."""
    shapes = {name: (groups, len(labels[f"{dim}_names"])) for name, (dim, _, _) in SURFACE_VARIABLES.items()
              if f"{dim}_names" in labels}
    return shapes, labels


def group_labels(count: int, group_names=None) -> tuple:
    """The labels of `count` bearing groups: `group_names` where given (`ValueError` naming
    them when there are not `count`), else g0, g1, ..."""
    groups = tuple(f"g{i}" for i in range(count)) if group_names is None else tuple(str(g) for g in group_names)
    if len(groups) != count:
        raise ValueError(f"group_names: {len(groups)} names for the structure's {count} bearing groups.")
    return groups


def surface_layout(shape_of: dict, labels: dict, group_names, lead: tuple) -> tuple[dict, dict, dict]:
    """(dims, coords, variables) of the surfaces in a streamed results file (`create_netcdf`'s
    form; a Monte Carlo's or a suite's), on `lead` + ("group", surface): `shape_of` {name: (...,
    G, S)} of the peaks the structure reports, `labels` (`surface_attributes`), `group_names`
    (`group_labels`: or g0, g1, ...)."""
    dims, coords, variables = {}, {}, {}
    for name, (dim, units, long_name) in SURFACE_VARIABLES.items():
        if name not in shape_of:
            continue
        count, names = shape_of[name][-2], labels[f"{dim}_names"]
        groups = group_labels(count, group_names)
        dims |= {"group": count, dim: len(names)}
        coords["group"] = ("group", np.array(groups, dtype=str), None, "bearing group")
        coords[dim] = (dim, np.array(names, dtype=str), None, None)
        variables[name] = (lead + ("group", dim), units, long_name, "f8")
    return dims, coords, variables
