"""One response type for every structure history: a rigid mass, a building or a slab, on flat
sliders, single pendulums or series pendulums, under one or two ground components.

Every history driver (`simulate_structure`, `simulate_bidirectional`,
`simulate_triple_structure`, `simulate_slab_series`, and `simulate_history` for any of their
systems) returns a `StructureResponse`; the parts a structure does not have are `None`. The
peaks kept along a run (`peak_response`, `bidirectional_peak_response`) are a `PeakResponse`;
the reducers over a saved history (base displacement and shear, storeys, groups, sliders,
heating: `teflon_jax.studies.response_peaks`) read its fields, the same for every structure.
"""

import diffrax
import equinox as eqx
import jax.numpy as jnp


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
    - `surface_temperature_rise` (nt, G, S) [K]: each surface's rise on heated series
      pendulums; `tipped` (nt,): the slab could not rest on its groups.

    **Vertical record:** `load_factor` (nt,) [-], N / W on the isolators (0 while uplifted),
    and `uplift_time` [s], the steps whose end has N <= 0 times the step.

    **Outcome:** `converged` (nt,): each step's balance converged (stepped engines), or
    `result`, the `diffrax.RESULTS` of a solve (`simulate_structure`, `simulate_bidirectional`);
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
      [K] the unscaled rise (0 without heating) and `gap_position` [m] (`respond_along_path`);
    - `converged` (nt,): each step's balance of a series pendulum met its tolerance; `result`:
      the `diffrax.RESULTS` of a solve (`simulate_bearing_test`); `succeeded` reads either.

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
