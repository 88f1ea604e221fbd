"""Peaks over a structure's saved history (`systems.StructureResponse`), for every isolator
(flat sliders, single, double and triple pendulums), structure (rigid mass, building, slab)
and one or two ground components: `run`'s peaks and a record suite's peaks are these, only
named for their file.

The quantities are the response's `REDUCERS` (`teflon_jax.systems`), written once on one
sample and the same on a history; `response_peaks` takes their maxima over the saved times,
as `systems.peak_response` folds them step by step along a run. A `ResponseLayout`
(`response_layout(system)`) says where the structure's parts sit in the response's
coordinates; a part the response does not hold (`None`) gives no peak.
"""

import jax.numpy as jnp

from ..systems import (
    REDUCERS,
    ResponseLayout,
    base_displacement,
    base_shear_ratio,
    carried_weight,
    first_storey_shear_ratio,
    group_load_extremes,
    group_load_peaks,
    isolator_force,
    level_acceleration,
    response_layout,
    resultant,
    slider_travel,
    storey_drift,
)

__all__ = ["REDUCERS", "ResponseLayout", "base_displacement", "base_shear_ratio", "carried_weight",
           "first_storey_shear_ratio", "group_normal_load", "isolator_force", "level_acceleration", "peak",
           "response_layout", "response_peaks", "resultant", "slider_travel", "storey_drift"]


def peak(history):
    """max_t |h(t)| of a history, time along the first axis."""
    return jnp.max(jnp.abs(history), axis=0)


def group_normal_load(layout: ResponseLayout, response):
    """{"peak_N", "min_N": (G,) [N], "uplift_time_s": (G,) [s]}: each bearing group's largest
    and least N_g and its time at N_g <= 0, where the groups share the weight unevenly
    (`ResponseLayout.overturning`), else `None`; what `systems.peak_response` folds along a
    run (`group_load_peaks`)."""
    extremes = group_load_extremes(layout, response)
    return None if extremes is None else group_load_peaks(extremes, response.group_uplift_time)


def response_peaks(layout: ResponseLayout, response, storey_height=None) -> dict:
    """The peaks (SI) of a saved response: max over time of each of the `REDUCERS` the
    response holds, in their order,

    - `base_disp` (C,) [m] per component, `base_disp_resultant` [m];
    - `base_shear_ratio_resultant` [-], `isolator_force_ratio_resultant` [-];
    - a building: `storey_drift_resultant` (L-1,) [m], `level_acceleration` (C, L) and
      `level_acceleration_resultant` (L,) [m/s^2], `first_storey_shear_ratio_resultant` [-];
      with `storey_height` [m] (scalar or (L-1,)) also `storey_drift_ratio` (C, L-1) and
      `storey_drift_ratio_resultant` (L-1,) [-];
    - `slider_travel` (S,) or (G, S) [m]; `surface_temperature_rise` (G, S) [K]; a slab's
      `rotation` [rad] and `group_disp_resultant` (G,) [m];

    and `group_normal_load` where the groups share the weight unevenly.
    """
    out = {}
    for name, reducer in REDUCERS.items():
        values = reducer(layout, response, storey_height)
        if values is not None:
            out[name] = jnp.max(values, axis=0)
    loads = group_normal_load(layout, response)
    if loads is not None:
        out["group_normal_load"] = loads
    return out
