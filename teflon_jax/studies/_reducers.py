"""Reducers over a structure's history (`systems.StructureResponse`), written once for every
isolator (flat sliders, single, double and triple pendulums), structure (rigid mass, building,
slab) and one or two ground components: `run`'s peaks and histories and a record suite's peaks
are these, only named for their file.

A `ResponseLayout` (`response_layout(system)`) says where the structure's parts sit in the
response's coordinates: the base and, for a building, the floors in each direction, and each
coordinate's mass and direction. Every reducer is jit/vmap-safe (`jax.numpy`; the layout's
indices are static) and returns histories (time along the first axis) or peaks over them; a
part the response does not hold (`None`) gives `None`.

**Base shear ratio** (every engine, one and two components): the horizontal force the
bearings carry, the sum over the masses above them of m_j a_j^total (the base slab's included),
over the weight they carry W = g sum_j m_j,

    V(t) / W = sum_j m_j (a_j(t) + a_g(t)) / (g sum_j m_j),

as the paper's figures give it (Mokha, Constantinou & Reinhorn 1990); for a rigid mass or a
slab m (a + a_g) / (m g). The first-storey shear (`first_storey_shear_ratio`) is that sum over
the floors alone over their weight.
"""

import typing

import jax.numpy as jnp
import numpy as np

from ..systems import BiaxialStructureOnTriple, StructureOnSliders, StructureOnTriple
from ..units import STANDARD_GRAVITY


class ResponseLayout(typing.NamedTuple):
    """Where a structure's parts sit in its `StructureResponse` coordinates (N of them).

    - `levels` (C, L) static ints: row d the coordinates along ground component d (C = 1 or
      2) of the base (column 0) and, for a building, its floors 1..L-1 (L = 1 otherwise);
    - `mass` (N,) [kg]: each coordinate's translating mass (0 for a slab's rotation);
    - `influence` (N, C) [-]: the direction of each coordinate (1 along its component);
    - `rotation`: the coordinate of a slab's rotation [rad], else `None`;
    - `overturning`: the groups share the weight unevenly (a slab's `supports`), so their
      normal loads are a result (`group_normal_load`).
    """

    levels: tuple
    mass: jnp.ndarray
    influence: jnp.ndarray
    rotation: int | None = None
    overturning: bool = False

    @property
    def components(self) -> int:
        return len(self.levels)

    @property
    def building(self) -> bool:
        return len(self.levels[0]) > 1


def response_layout(system) -> ResponseLayout:
    """The `ResponseLayout` of any structure `systems` builds: a `StructureOnSliders` or
    `StructureOnTriple` (one component: coordinates base, floors), a `BiaxialStructureOnTriple`
    (x block then y block), and a `BidirectionalStructure` or `SlabOnSeries`, which carry their
    own `mass` and `influence` (a rigid mass or building: x block then y block; a slab: x, y,
    rotation). Only shapes are read (static under jit)."""
    if isinstance(system, (StructureOnSliders, StructureOnTriple)):
        n = system.mass.shape[-1]
        return ResponseLayout((tuple(range(n)),), system.mass, jnp.ones((n, 1), system.mass.dtype))
    if isinstance(system, BiaxialStructureOnTriple):
        m = system.mass
        n = m.shape[-1]
        blocks = jnp.repeat(jnp.eye(2, dtype=m.dtype), n, axis=0)
        return ResponseLayout((tuple(range(n)), tuple(range(n, 2 * n))), jnp.concatenate([m, m]), blocks)
    if hasattr(system, "influence"):  # BidirectionalStructure, SlabOnSeries
        count = system.mass.shape[-1]
        if count % 2:  # a slab: (x, y, rotation)
            return ResponseLayout(((0,), (1,)), system.mass, system.influence, rotation=2,
                                  overturning=system.supports is not None)
        n = count // 2
        return ResponseLayout((tuple(range(n)), tuple(range(n, 2 * n))), system.mass, system.influence)
    raise TypeError(f"system: no response layout for a {type(system).__name__}; give a structure built by "
                    "teflon_jax.systems (rigid mass, building or slab on its isolators).")


def resultant(history):
    """|h(t)| (nt, ...) of a history (nt, C, ...) over its C components: |h_x| for C = 1,
    hypot(h_x, h_y) for C = 2."""
    return jnp.abs(history[:, 0]) if history.shape[1] == 1 else jnp.hypot(history[:, 0], history[:, 1])


def peak(history):
    """max_t |h(t)| of a history, time along the first axis."""
    return jnp.max(jnp.abs(history), axis=0)


def base_displacement(layout: ResponseLayout, response):
    """(nt, C) [m]: the base's displacement relative to the ground along each component."""
    return response.displacement[:, np.array([row[0] for row in layout.levels])]


def carried_weight(layout: ResponseLayout):
    """W = g sum_j m_j [N]: the weight of the masses above the bearings."""
    return STANDARD_GRAVITY * jnp.sum(layout.mass * layout.influence[:, 0])


def base_shear_ratio(layout: ResponseLayout, response):
    """(nt, C) [-]: V(t) / W, the force the bearings carry, sum_j m_j a_j^total, over the
    weight they carry (module docstring)."""
    force = response.total_acceleration @ (layout.mass[:, None] * layout.influence)
    return force / carried_weight(layout)


def first_storey_shear_ratio(layout: ResponseLayout, response):
    """(nt, C) [-] of a building: sum_{j>=1} m_j a_j^total over g sum_{j>=1} m_j (the floors);
    `None` for a rigid mass or a slab."""
    if not layout.building:
        return None
    floors = np.array([row[1:] for row in layout.levels])  # (C, L - 1)
    masses = layout.mass[floors]
    force = jnp.sum(response.total_acceleration[:, floors] * masses, axis=-1)
    return force / (STANDARD_GRAVITY * jnp.sum(masses[0]))


def storey_drift(layout: ResponseLayout, response):
    """(nt, C, L - 1) [m] of a building: q_j - q_(j-1) per storey (storey 1 from the base slab
    to floor 1) along each component; `None` for a rigid mass or a slab."""
    if not layout.building:
        return None
    return jnp.diff(response.displacement[:, np.array(layout.levels)], axis=-1)


def level_acceleration(layout: ResponseLayout, response):
    """(nt, C, L) [m/s^2] of a building: each level's total acceleration a_j + a_g (level 0 the
    base slab) along each component; `None` for a rigid mass or a slab."""
    if not layout.building:
        return None
    return response.total_acceleration[:, np.array(layout.levels)]


def isolator_force(response):
    """(nt, C) [N]: the isolators' whole force resisting the base's motion, summed over
    bearing groups (flat sliders and single pendulums: the friction force; series pendulums:
    the force beyond the reference spring); `None` without either."""
    if response.friction_force is not None:
        force = response.friction_force  # (nt,) resisting, or (nt, G, 2) on the structure
        return force[:, None] if force.ndim == 1 else -jnp.sum(force, axis=1)
    force = response.bearing_force
    if force is None:
        return None
    return force[:, None] if force.ndim == 1 else (jnp.sum(force, axis=1) if force.ndim == 3 else force)


def slider_travel(response):
    """(nt, S) or (nt, G, S) [m]: each slider's displacement magnitude (|s| under one
    component, the length of (s_x, s_y) under two; per group of a slab); `None` without
    sliders."""
    slider = response.slider
    if slider is None:
        return None
    return jnp.abs(slider) if slider.ndim == 2 else jnp.linalg.norm(slider, axis=-1)


def group_normal_load(layout: ResponseLayout, response):
    """{"peak_N", "min_N": (G,) [N], "uplift_time_s": (G,) [s]}: each bearing group's largest
    and least N_g and its time at N_g <= 0, where the groups share the weight unevenly
    (`ResponseLayout.overturning`), else `None`."""
    if not layout.overturning or response.normal_load is None:
        return None
    return {"peak_N": jnp.max(response.normal_load, axis=0), "min_N": jnp.min(response.normal_load, axis=0),
            "uplift_time_s": response.group_uplift_time}


def response_peaks(layout: ResponseLayout, response, storey_height=None) -> dict:
    """The peaks (SI) of a response, each where the response holds its part:

    - `base_disp` (C,) [m] per component, `base_disp_resultant` [m];
    - `base_shear_ratio_resultant` [-] (`base_shear_ratio`), `isolator_force_ratio_resultant`
      [-] (`isolator_force` over the carried weight);
    - a building: `storey_drift_resultant` (L-1,) [m], `level_acceleration` (C, L) and
      `level_acceleration_resultant` (L,) [m/s^2], `first_storey_shear_ratio_resultant` [-];
      with `storey_height` [m] (scalar or (L-1,)) also `storey_drift_ratio` (C, L-1) and
      `storey_drift_ratio_resultant` (L-1,) [-];
    - `slider_travel` (S,) or (G, S) [m]; `surface_temperature_rise` (G, S) [K]; a slab's
      `rotation` [rad] and `group_disp_resultant` (G,) [m]; `group_normal_load`.
    """
    base = base_displacement(layout, response)
    out = {"base_disp": peak(base), "base_disp_resultant": jnp.max(resultant(base)),
           "base_shear_ratio_resultant": jnp.max(resultant(base_shear_ratio(layout, response)))}
    force = isolator_force(response)
    if force is not None:
        out["isolator_force_ratio_resultant"] = jnp.max(resultant(force)) / carried_weight(layout)
    if layout.building:
        drift, acc = storey_drift(layout, response), level_acceleration(layout, response)
        out["storey_drift_resultant"] = jnp.max(resultant(drift), axis=0)
        out["level_acceleration"] = peak(acc)
        out["level_acceleration_resultant"] = jnp.max(resultant(acc), axis=0)
        out["first_storey_shear_ratio_resultant"] = jnp.max(resultant(first_storey_shear_ratio(layout, response)))
        if storey_height is not None:
            height = jnp.broadcast_to(jnp.asarray(storey_height, drift.dtype), drift.shape[-1:])
            out["storey_drift_ratio"] = peak(drift / height)
            out["storey_drift_ratio_resultant"] = jnp.max(resultant(drift / height), axis=0)
    if response.slider is not None:
        out["slider_travel"] = peak(slider_travel(response))
    if response.surface_temperature_rise is not None:
        out["surface_temperature_rise"] = jnp.max(response.surface_temperature_rise, axis=0)
    if layout.rotation is not None:
        out["rotation"] = peak(response.displacement[:, layout.rotation])
    if response.bearing_displacement is not None:
        out["group_disp_resultant"] = jnp.max(jnp.linalg.norm(response.bearing_displacement, axis=-1), axis=0)
    loads = group_normal_load(layout, response)
    if loads is not None:
        out["group_normal_load"] = loads
    return out
