"""One response type for every structure history: a rigid mass, a building or a slab, on flat
sliders, single pendulums or series pendulums, under one or two ground components.

Every history (`simulate_history` for any structure: a diffrax solve on the time grid, or
`run_history` of a stepped engine's `EngineRun`) is a `StructureResponse`; the parts a
structure does not have are `None`.

The response's quantities (base displacement, base shear, storey drift, level acceleration,
isolator force, slider travel, ...) are written here once, each on one sample of a
`StructureResponse` (no time axis) and, the same code, on a history (time along the first
axis: the component and level axes are counted from the last). `REDUCERS` names the
magnitudes whose peaks are kept: `peak_response` folds them along a run step by step, and
`teflon_jax.studies.response_peaks` takes their maxima over a saved history.

**Base shear ratio** (every engine, one and two components): the horizontal force the
bearings carry, the sum over the masses above them of m_j a_j^total (the base slab's included),
over the weight they carry W = g sum_j m_j,

    V(t) / W = sum_j m_j (a_j(t) + a_g(t)) / (g sum_j m_j),

as the paper's figures give it (Mokha, Constantinou & Reinhorn 1990); for a rigid mass or a
slab m (a + a_g) / (m g). The first-storey shear (`first_storey_shear_ratio`) is that sum over
the floors alone over their weight.
"""

import dataclasses
import typing

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..units import STANDARD_GRAVITY


class StructureResponse(eqx.Module):
    """Histories of a structure from rest (SI; time along the first axis, nt saved times).

    **Coordinates.** `displacement`, `velocity` and `total_acceleration` (nt, N) [m, m/s,
    m/s^2] are the structure's coordinates relative to the ground, the total acceleration
    being the relative one plus the ground's (R a_g, R the influence matrix): under one
    component N = n masses (0 the isolator or base slab, 1.. the floors); under two the x
    block then the y block (N = 2n) of a rigid mass or building, or (x, y, rotation) of a slab
    (N = 3, the rotation in [rad]). `ground` (nt, C) [m/s^2]: the C = 1 or 2 ground components.

    **Isolators** (each `None` where the structure has no such part):

    - `friction_force` [N] of flat sliders and single pendulums (their W u / R is in the
      stiffness): (nt,) under one component, mu W Z resisting the sliding; (nt, G, 2) per
      group of bearings under two, the force on the structure;
    - `bearing_force` [N] of series pendulums, the isolator's force beyond the reference spring,
      resisting its displacement: (nt,), (nt, 2) under two components, (nt, G, 2) per group;
    - `z` [-] and `z_peak` [-] (running max |Z|): (nt,) one component; (nt, G, 2) and (nt, G)
      two; `z` (nt, S) of each slider of a series pendulum under one component;
    - `slider` [m]: the S sliders of a series pendulum (in `slider_names` order), (nt, S),
      (nt, S, 2) under two components, (nt, G, S, 2) per group;
    - `bearing_displacement` (nt, G, 2) [m]: each group's displacement (slabs, two components);
    - `normal_load` (nt, G) [N] of each group and `group_uplift_time` (G,) [s] (the steps with
      N_g <= 0 times the step), with groups that share the weight unevenly (overturning);
    - `surface_temperature_rise` (nt, G, S) [K]: each surface's rise s dT (the one that
      enters k_T) on heated bearings, G = S = 1 for flat sliders and single pendulums under one
      component, S = 1 for sliding groups under two, G = 1 for one series pendulum; `tipped`
      (nt,): the slab could not rest on its groups.

    **Vertical record:** `load_factor` (nt,) [-], N / W on the isolators (0 while uplifted),
    and `uplift_time` [s], the steps whose end has N <= 0 times the step.

    **Outcome:** `converged` (nt,): each step's balance converged (stepped engines), or
    `result`, the `diffrax.RESULTS` of a solve on the time grid (`simulate_history`);
    `succeeded` reads either.
    """

    time: jnp.ndarray
    displacement: jnp.ndarray
    velocity: jnp.ndarray
    total_acceleration: jnp.ndarray
    ground: jnp.ndarray
    friction_force: jnp.ndarray | None = None
    bearing_force: jnp.ndarray | None = None
    z: jnp.ndarray | None = None
    z_peak: jnp.ndarray | None = None
    slider: jnp.ndarray | None = None
    bearing_displacement: jnp.ndarray | None = None
    normal_load: jnp.ndarray | None = None
    group_uplift_time: jnp.ndarray | None = None
    surface_temperature_rise: jnp.ndarray | None = None
    tipped: jnp.ndarray | None = None
    load_factor: jnp.ndarray | None = None
    uplift_time: jnp.ndarray | None = None
    converged: jnp.ndarray | None = None
    result: object = None

    @property
    def succeeded(self):
        """Whether the whole run succeeded: the solve's `result` is successful, or every step
        converged."""
        if self.result is not None:
            return self.result == diffrax.RESULTS.successful
        return jnp.all(self.converged, axis=-1)


class EngineRun(typing.NamedTuple):
    """How a stepped engine runs from rest: its `start` state, the per-step `inputs` (leading
    axis n_steps), `step(state, inputs) -> (state, sample, converged)` with the sample a
    `StructureResponse` without a time axis, and `first`, the sample at rest (t = 0), which a
    history keeps (`run_history`) and the peak driver does not need (`None`)."""

    start: object
    inputs: object
    step: typing.Callable
    first: "StructureResponse | None" = None


def run_history(run: EngineRun) -> "StructureResponse":
    """Every step of `run` kept after its sample at rest, each with whether its step converged
    (True at rest): the same samples the peak driver folds. jit/vmap/grad-safe."""
    def body(state, inputs):
        state, sample, converged = run.step(state, inputs)
        return state, dataclasses.replace(sample, converged=converged)

    _, samples = jax.lax.scan(body, run.start, run.inputs)
    first = dataclasses.replace(run.first, converged=jnp.array(True))
    return jax.tree_util.tree_map(lambda a, b: jnp.concatenate([a[None], b]), first, samples)


_UNBALANCED = ("simulate_history: the isolators' balance (the bearings' forces, or a series pendulum's sliders) "
               "missed its tolerance at a step; "
               "give throw=False to keep the response, whose `converged` says which steps, or a shorter "
               "time_step or more newton_iterations to the structure's builder.")
_TIPPED = ("simulate_history: the slab tipped: at a step the groups still loaded lay on one line and could not "
           "carry its overturning moment; give throw=False to keep the response, whose `tipped` says which "
           "steps, or place groups off that line.")


_PER_RUN = ("uplift_time", "group_uplift_time", "result")
"""The `StructureResponse` fields of the whole run, without a time axis."""


def every_kth(response: StructureResponse, k: int) -> StructureResponse:
    """`response` (every step of a run, t = 0 first) at every `k`-th step: its samples there,
    `converged` whether every step since the previous kept one converged and `tipped` whether
    the slab tipped on any of them (the last kept one also covers the steps after it, so that
    `succeeded` still reads every step)."""
    if k == 1:
        return response

    def since_previous(failed):
        total = jnp.cumsum(failed.astype(int))
        kept = total[::k].at[-1].set(total[-1])
        return jnp.concatenate([kept[:1], jnp.diff(kept)]) > 0

    changes = {name: None if getattr(response, name) is None else getattr(response, name)[::k]
               for name in (f.name for f in dataclasses.fields(response)) if name not in _PER_RUN}
    changes["converged"] = ~since_previous(~response.converged)
    if response.tipped is not None:
        changes["tipped"] = since_previous(response.tipped)
    return dataclasses.replace(response, **changes)


def raise_unbalanced(response: StructureResponse) -> StructureResponse:
    """`response`, raising (at run time, under jit too) where a step did not balance: a slab
    that tipped (`tipped`) or a sliders' balance that missed its tolerance (`converged`)."""
    missed = ~jnp.all(response.converged)
    if response.tipped is None:
        return eqx.error_if(response, missed, _UNBALANCED)
    return eqx.branched_error_if(response, missed, jnp.any(response.tipped).astype(int), (_UNBALANCED, _TIPPED))


def group_uplift_time(normal_load, interval: float):
    """Each group's uplift time (G,) [s]: the saved samples after the first whose normal load
    `normal_load` (nt, G) [N] is <= 0, times the `interval` [s] between them."""
    return jnp.sum(normal_load[1:] <= 0, axis=0) * interval


def group_load_extremes(layout: "ResponseLayout", response):
    """(largest N_g, least N_g, count of N_g <= 0) (G,) over the samples of `response` (time
    along the first axis; one sample: itself, count 0 or 1) of each bearing group whose
    normal load is a result (`ResponseLayout.overturning`), else `None`. Two of them combine
    by `combined_load_extremes`, which is how `peak_response` folds them step by step."""
    if not layout.overturning or response.normal_load is None:
        return None
    load = jnp.atleast_2d(response.normal_load)
    return jnp.max(load, axis=0), jnp.min(load, axis=0), jnp.sum(load <= 0, axis=0)


def combined_load_extremes(first, second):
    """The `group_load_extremes` of two runs of samples taken together."""
    return jnp.maximum(first[0], second[0]), jnp.minimum(first[1], second[1]), first[2] + second[2]


def group_load_peaks(extremes, uplift_time) -> dict:
    """{"peak_N", "min_N": (G,) [N], "uplift_time_s": (G,) [s]}: each group's largest and least
    normal load from its `group_load_extremes` over a run, and its `uplift_time` [s]."""
    return {"peak_N": extremes[0], "min_N": extremes[1], "uplift_time_s": uplift_time}


class BearingTestResult(eqx.Module):
    """Histories of a bearing, or of an isolator of sliders in series, driven along an imposed
    path (SI; the samples along the first axis, nt of them).

    - `time` (nt,) [s]; `ux`, `uy` [m] and `vx`, `vy` [m/s] (nt,) of the path (`uy`, `vy`
      `None` where the path has no y component or no velocity was given);
    - `fx`, `fy` (nt,) [N]: the force the bearing resists with (positive while sliding in +x;
      `fy` zeros along x only); `normal_load` (nt,) [N];
    - `z` [-]: (nt, 2), Z in x and y of one sliding surface; (nt, S) or (nt, S, 2) of each of
      the S sliders of a series pendulum (in `slider_names` order), with their displacements
      `slider` [m] like it;
    - `coefficient` mu [-] and `z_peak` (running max |Z|) (nt,) of one surface;
    - `temperature_rise` [K], the rise that enters the heating factor (scaled), `heat_index`
      [K] the unscaled rise (0 without heating) and `gap_position` [m] (`imposed_path_test`);
    - `converged` (nt,): each step's balance of a series pendulum met its tolerance; `result`:
      the `diffrax.RESULTS` of a solve (`imposed_path_test`); `succeeded` reads either.

    Each is `None` where the test has no such part.
    """

    time: jnp.ndarray
    fx: jnp.ndarray
    fy: jnp.ndarray
    z: jnp.ndarray
    normal_load: jnp.ndarray | None = None
    ux: jnp.ndarray | None = None
    uy: jnp.ndarray | None = None
    vx: jnp.ndarray | None = None
    vy: jnp.ndarray | None = None
    coefficient: jnp.ndarray | None = None
    z_peak: jnp.ndarray | None = None
    temperature_rise: jnp.ndarray | None = None
    heat_index: jnp.ndarray | None = None
    gap_position: jnp.ndarray | None = None
    slider: jnp.ndarray | None = None
    converged: jnp.ndarray | None = None
    result: object = None

    @property
    def force(self):
        """The force [N] along the path: `fx` (nt,) where the path has no y component (`uy`
        `None`), else (fx, fy) (nt, 2)."""
        return self.fx if self.uy is None else jnp.stack([self.fx, self.fy], axis=-1)

    @property
    def succeeded(self):
        """Whether the test ran through: the solve's `result` is successful, or every step's
        balance converged (True where neither applies)."""
        if self.result is not None:
            return self.result == diffrax.RESULTS.successful
        if self.converged is not None:
            return jnp.all(self.converged, axis=-1)
        return jnp.array(True)


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


def resultant(values, axis: int = -1):
    """|h| over the ground components along `axis` (C = 1 or 2 long; removed): |h_x| for
    C = 1, hypot(h_x, h_y) for C = 2."""
    values = jnp.moveaxis(values, axis, 0)
    return jnp.abs(values[0]) if values.shape[0] == 1 else jnp.hypot(values[0], values[1])


def base_displacement(layout: ResponseLayout, response):
    """(..., C) [m]: the base's displacement relative to the ground along each component."""
    return response.displacement[..., np.array([row[0] for row in layout.levels])]


def carried_weight(layout: ResponseLayout):
    """W = g sum_j m_j [N]: the weight of the masses above the bearings."""
    return STANDARD_GRAVITY * jnp.sum(layout.mass * layout.influence[:, 0])


def base_shear_ratio(layout: ResponseLayout, response):
    """(..., C) [-]: V / W, the force the bearings carry, sum_j m_j a_j^total, over the
    weight they carry (module docstring)."""
    weights = layout.mass[:, None] * layout.influence  # (N, C) [kg]
    force = jnp.sum(response.total_acceleration[..., :, None] * weights, axis=-2)  # no dot kernel per sample
    return force / carried_weight(layout)


def first_storey_shear_ratio(layout: ResponseLayout, response):
    """(..., C) [-] of a building: sum_{j>=1} m_j a_j^total over g sum_{j>=1} m_j (the
    floors); `None` for a rigid mass or a slab."""
    if not layout.building:
        return None
    floors = np.array([row[1:] for row in layout.levels])  # (C, L - 1)
    masses = layout.mass[floors]
    force = jnp.sum(response.total_acceleration[..., floors] * masses, axis=-1)
    return force / (STANDARD_GRAVITY * jnp.sum(masses[0]))


def storey_drift(layout: ResponseLayout, response):
    """(..., C, L - 1) [m] of a building: q_j - q_(j-1) per storey (storey 1 from the base
    slab to floor 1) along each component; `None` for a rigid mass or a slab."""
    if not layout.building:
        return None
    return jnp.diff(response.displacement[..., np.array(layout.levels)], axis=-1)


def level_acceleration(layout: ResponseLayout, response):
    """(..., C, L) [m/s^2] of a building: each level's total acceleration a_j + a_g (level 0
    the base slab) along each component; `None` for a rigid mass or a slab."""
    if not layout.building:
        return None
    return response.total_acceleration[..., np.array(layout.levels)]


def isolator_force(response):
    """(..., C) [N]: the isolators' whole force resisting the base's motion, summed over
    bearing groups (flat sliders and single pendulums: the friction force; series pendulums:
    the force beyond the reference spring); `None` without either."""
    lead = jnp.ndim(response.time)  # 1 on a history, 0 on one sample
    if response.friction_force is not None:
        force = response.friction_force  # (...,) resisting, or (..., G, 2) on the structure
        return force[..., None] if force.ndim == lead else -jnp.sum(force, axis=-2)
    force = response.bearing_force
    if force is None:
        return None
    if force.ndim == lead:
        return force[..., None]
    return jnp.sum(force, axis=-2) if force.ndim == lead + 2 else force


def slider_travel(response):
    """(..., S) or (..., G, S) [m]: each slider's displacement magnitude (|s| under one
    component, the length of (s_x, s_y) under two; per group of a slab); `None` without
    sliders."""
    slider = response.slider
    if slider is None:
        return None
    lead = jnp.ndim(response.time)
    return jnp.abs(slider) if slider.ndim == lead + 1 else jnp.linalg.norm(slider, axis=-1)


def uplifted(load_factor):
    """Whether the isolators are uplifted, N <= 0, at the sample(s) of a vertical record's load
    factor N / W [-] (`StructureResponse.load_factor`): they then carry no shear."""
    return load_factor <= 0


def uplift_time(load_factor, time_step):
    """Time [s] of the steps 1..n whose end has N <= 0, from the load factors (n + 1,) at the
    saved times 0..n of a run stepped by `time_step` [s] (`uplifted`)."""
    return jnp.sum(uplifted(load_factor[1:])) * time_step


def _drift_ratio(layout, response, storey_height):
    drift = storey_drift(layout, response)
    if drift is None or storey_height is None:
        return None
    return drift / jnp.broadcast_to(jnp.asarray(storey_height, drift.dtype), drift.shape[-1:])


def _abs(values):
    return None if values is None else jnp.abs(values)


def _resultant(values, axis=-1):
    return None if values is None else resultant(values, axis)


def _isolator_force_ratio(layout, response):
    force = isolator_force(response)
    return None if force is None else resultant(force) / carried_weight(layout)


def _group_disp(response):
    displacement = response.bearing_displacement
    return None if displacement is None else jnp.linalg.norm(displacement, axis=-1)


def _rotation(layout, response):
    return None if layout.rotation is None else jnp.abs(response.displacement[..., layout.rotation])


REDUCERS = {
    "base_disp": lambda layout, r, h: jnp.abs(base_displacement(layout, r)),
    "base_disp_resultant": lambda layout, r, h: resultant(base_displacement(layout, r)),
    "base_shear_ratio_resultant": lambda layout, r, h: resultant(base_shear_ratio(layout, r)),
    "isolator_force_ratio_resultant": lambda layout, r, h: _isolator_force_ratio(layout, r),
    "storey_drift_resultant": lambda layout, r, h: _resultant(storey_drift(layout, r), -2),
    "level_acceleration": lambda layout, r, h: _abs(level_acceleration(layout, r)),
    "level_acceleration_resultant": lambda layout, r, h: _resultant(level_acceleration(layout, r), -2),
    "first_storey_shear_ratio_resultant": lambda layout, r, h: _resultant(first_storey_shear_ratio(layout, r)),
    "storey_drift_ratio": lambda layout, r, h: _abs(_drift_ratio(layout, r, h)),
    "storey_drift_ratio_resultant": lambda layout, r, h: _resultant(_drift_ratio(layout, r, h), -2),
    "slider_travel": lambda layout, r, h: slider_travel(r),
    "surface_temperature_rise": lambda layout, r, h: r.surface_temperature_rise,
    "rotation": lambda layout, r, h: _rotation(layout, r),
    "group_disp_resultant": lambda layout, r, h: _group_disp(r),
}
"""The peak quantities of a response: name -> `(layout, response, storey_height) ->` the
non-negative magnitude whose maximum over time is the peak (on one sample or on a history,
`None` where the response has no such part): the base displacement per component [m] and as
a resultant, the base shear ratio V / W [-], the isolator force over W [-], a building's
storey drift [m] and drift ratio [-] (with `storey_height` [m], scalar or per storey), level
acceleration [m/s^2] per component and as resultants and first-storey shear ratio [-], each
slider's travel [m], each surface's temperature rise [K], a slab's rotation [rad] and each
group's displacement [m]."""


MONTE_CARLO_PEAKS = {"base_disp": "base_disp_resultant", "base_shear_ratio": "base_shear_ratio_resultant",
                     "smooth_base_disp": "smooth_base_disp_resultant",
                     "smooth_base_shear_ratio": "smooth_base_shear_ratio_resultant", "converged": "converged",
                     "storey_drift": "storey_drift_ratio", "floor_acceleration": "level_acceleration",
                     "uplift_time": "uplift_time", "group_normal_load": "group_normal_load",
                     "within_pressure_law": "within_pressure_law", "tipped": "tipped",
                     "slider_travel": "slider_travel", "surface_temperature_rise": "surface_temperature_rise"}
"""The Monte Carlo's names of `peak_response`'s peaks (`MonteCarloResult` fields) -> their
reducer names."""


@jax.tree_util.register_pytree_node_class
class Peaks(dict):
    """The peaks of one run of `peak_response` (or batched), keyed by reducer name, with
    `components` (1 or 2) the ground components of its structure. The Monte Carlo's names
    (`MONTE_CARLO_PEAKS`) read as attributes: `base_disp` [m] and `base_shear_ratio` [-]
    (resultants), their smooth maxima `smooth_base_disp`, `smooth_base_shear_ratio`,
    `converged`, a building's `storey_drift` [-] (drift ratio) and `floor_acceleration`
    [m/s^2] per storey and level ((S,), (S + 1,) under one component; (2, S), (2, S + 1) under
    two), `uplift_time` [s], where groups share the weight unevenly `group_normal_load`
    ({"peak_N", "min_N", "uplift_time_s"}: (G,) each) and `tipped` (bool, whether the run's
    first unbalanced step tipped the slab), with Table 1's pressure law in a study
    `within_pressure_law` (bool), and where kept each slider's travel `slider_travel` [m]
    ((S,), or (G, S) per group) and each surface's temperature rise
    `surface_temperature_rise` [K] ((G, S)); `None` where not kept."""

    def __init__(self, values=(), components: int = 1):
        super().__init__(values)
        self.components = components

    def __getattr__(self, name):
        if name not in MONTE_CARLO_PEAKS:
            raise AttributeError(name)
        value = self.get(MONTE_CARLO_PEAKS[name])
        if value is not None and self.components == 1 and name in ("storey_drift", "floor_acceleration"):
            value = jnp.squeeze(value, axis=-2)
        return value

    def tree_flatten(self):
        keys = tuple(self.keys())
        return tuple(self[k] for k in keys), (keys, self.components)

    @classmethod
    def tree_unflatten(cls, aux, children):
        keys, components = aux
        return cls(zip(keys, children), components)


def peak_arrays(peaks: Peaks, components=None) -> dict:
    """{Monte Carlo name: array} (`MONTE_CARLO_PEAKS`) of the peaks kept in `peaks`."""
    return {name: getattr(peaks, name) for name, key in MONTE_CARLO_PEAKS.items() if key in peaks}
