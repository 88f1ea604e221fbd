"""The isolated structure of the studies (rigid mass, building) built from design variables, on
any isolator (flat sliders, the single, double or triple friction pendulum) under one or two
horizontal ground components: `IsolatedStructure`, checked by `isolated_structure`."""

import dataclasses
from collections.abc import Mapping

import equinox as eqx
import jax
import jax.numpy as jnp

from ..bearing import (
    DESIGN_VARIABLES,
    ConcaveSurface,
    FrictionParameters,
    SeriesPendulum,
    SlidingBearing,
    check_design,
    check_series_pendulum,
    designed_pendulum,
    isolator_kind,
    one_surface,
    paper_bearing,
    runs_in_series,
)
from ..catalogue import FLAT, SINGLE_FP
from ..elements import TRIPLE_NEWTON_ITERATIONS, TRIPLE_TOLERANCE
from ..structures import LINEAR_RULES
from ..tables import friction_table
from ..units import PSI
from ..validation import concrete, require_positive
from ._series import triple_structure
from ._structure import NEWTON_ITERATIONS, NEWTON_TOLERANCE, StructureOnSliders
from ._structure_build import check_structure_parts, rigid_mass, six_storey_building
from ._vertical import with_vertical_motion

STRUCTURES = ("rigid", "building")

"""Isolators of the structures: flat sliders (with springs of period T_b, or none), the
single friction pendulum (a concave surface of radius R, `ConcaveSurface`), the triple and the
double friction pendulum (`TriplePendulum`, `DoublePendulum`: `IsolatedStructure.pendulum`, one
or two components)."""

RECOMMENDED_TIME_STEPS = {"rigid": 0.005, "building": 0.005}
"""Structure step [s] per structure, a divisor of the 0.01 s record step (a step that is not
one puts the record's kinks inside steps: 1/150 s left 1.8 % error). With Z updated along the
path to the turning point and back in steps where the sliding velocity reverses
(`split_at_turn`) and the linear structure advanced exactly (`linear_rule="exact"`), the peak
base displacement and base shear of every one of 100 forty-second Clough-Penzien motions lie
within 0.2 % of 0.5 ms steps at 5 ms, for the rigid mass and the building alike
(benchmarks/bench_scale.py, B3 accuracy). With Newmark's rule the building's base shear at
5 ms was 0.8 % off (its storey modes' period error) and it needed 1/300 s. At 10 ms a few
motions differ by 1.5 %: runs in which |Z| comes within 1e-3 of Eq. 17's breakaway threshold
(0.999) switch breakaway off at different times."""

MONTE_CARLO_NEWTON_TOLERANCE = 1e-3
"""`IsolatedStructure.newton_tolerance` of `teflon-jax montecarlo` and the B3 benchmark [-]: the
isolator's equilibrium solved to 1e-3 Y (0.13 um for Y = 0.005 in). Against 1e-5 Y (the
default) the worst peak errors over the 100 benchmark motions at 5 ms do not move (0.18 % /
0.08 % building, 0.10 % / 0.05 % rigid mass, against 0.5 ms steps solved to 1e-5 Y), and a
batch needs 13-15 % less CPU time (fewer steps in which one member holds the whole batch in
Newton's loop for one more iteration). Not for gradients checked against finite differences
of the peaks: those need the root to ~1e-5 Y (the default)."""


DEFAULT_PRESSURE = 1000 * PSI
"""`isolated_structure`'s contact pressure [Pa] where none is given (flat sliders and the single
pendulum: Table 1's row at 1000 psi)."""


DEFAULT_ISOLATION_PERIOD = "2 s on flat sliders"
"""Marks `isolated_structure`'s `isolation_period` as not given: T_b = 2 s on flat sliders,
none on a friction pendulum (its period comes from the radius)."""


# --------------------------------------------------------------------------- structures


class IsolatedStructure(eqx.Module):
    """Builds the rigid mass or the six-storey building on its isolator for one motion and one
    design, under one or two horizontal ground components (`components`).

    Call as `structure(ground_acceleration, design)` with `design` a dict of some of the
    isolator's design variables (`DESIGN_VARIABLES` on flat sliders and the single pendulum,
    `design_space(isolator)` on a series pendulum; arrays, traced or not; missing ones take the
    defaults below) and `ground_acceleration` a `Signal` [m/s^2] (one component) or an (x, y)
    pair of them (two, `bidirectional_isolated_structure`); with `vertical`, the pair
    (horizontal, vertical) of that and the vertical `Signal`. Flat sliders and the single
    pendulum build a `StructureOnSliders` (one component, or two: one group of bearings with
    Park's biaxial Z, the planar step); a triple or double pendulum (`pendulum`) a
    `StructureOnSliders` on its sliders in series (`triple_structure`), in one or two.

    **Fields:**

    - `kind` (static): "rigid" (`rigid_mass`) or "building" (`six_storey_building`, Table 2).
    - `ptfe`, `direction` (static): Table 1 rows, e.g. "UF", "P".
    - `pressure` [Pa]: bearing contact pressure, at which Table 1 gives Eq. 1's constants and b.
    - `isolation_period` T_b [s] of the restoring springs (`None` for a rigid mass on flat
      sliders without springs, and for a friction pendulum).
    - `surface`: the `ConcaveSurface` of a single friction pendulum, or `None` (flat sliders).
      Its small-rotation restoring force W u / R on the weight W carried is the linear spring
      of period T_b = 2 pi sqrt(R / g) (Zayas, Low & Mahin 1990); the rest of its force (the
      large-displacement form, the restrainer) is `StructureOnSliders.surface`'s, one
      direction and hysteretic friction only.
    - `isolation_damping` zeta_b [-] of the rigid-body mode.
    - `breakaway` (static): use Table 1's b (Eq. 17) when True; no breakaway when False.
    - `friction_model` (static): "hysteretic", "coulomb" or "none".
    - `time_step` [s] (static): structure step; `weight` [N] of the rigid mass.
    - `newton_iterations` (static): the most Newton iterations of the bearing's solve per step
      (`StructureOnSliders.newton_iterations`); a run cut short is reported as not converged.
    - `newton_tolerance` (static) [-]: `StructureOnSliders.newton_tolerance`, in units of Y
      (1e-5 by default; the Monte Carlo command uses `MONTE_CARLO_NEWTON_TOLERANCE`).
    - `split_at_turn` (static): `StructureOnSliders.split_at_turn`, True by default here.
    - `linear_rule` (static): `StructureOnSliders.linear_rule`, "exact" by default here (no
      period error in the storey modes). One component only, as `split_at_turn`: under two the
      planar solve's Newmark step (`newton_iterations`, `newton_tolerance` bound and end it).
    - `components` (static): 1 or 2 horizontal ground components.
    - `vertical` (static): whether the structure takes a vertical ground acceleration too, on
      its isolators' normal load (`with_vertical_component`, `with_vertical_motion`); Table 1's
      bearing then takes its constants at the momentary contact pressure (`TablePressure`), a
      given bearing follows it by its pressure dependence, if it has one.
    - `bearing`: a `SlidingBearing` to run instead of Table 1's at `pressure` (e.g. from a
      bearing file); `None` (the default) builds the paper's bearing from `ptfe`, `direction`,
      `pressure` and `breakaway`. The design variables f_max, delta_f, rate_a and
      breakaway_ratio still override its constants; `pressure` does not apply to it.
    - `pendulum`: a `TriplePendulum` or `DoublePendulum` (every surface with its own friction),
      or `None` (flat sliders or the single pendulum). With it `pressure`, `isolation_period`
      are `None` and `isolation_damping` 0 (its period follows from its radii, its damping
      is its friction), and `newton_iterations`, `newton_tolerance` are its sliders' balance's
      (`structure_on_isolator`: the force imbalance over W).
    """

    pressure: jnp.ndarray | None
    isolation_period: jnp.ndarray | None
    isolation_damping: jnp.ndarray
    kind: str = eqx.field(static=True, default="rigid")
    ptfe: str = eqx.field(static=True, default="UF")
    direction: str = eqx.field(static=True, default="P")
    breakaway: bool = eqx.field(static=True, default=True)
    friction_model: str = eqx.field(static=True, default="hysteretic")
    time_step: float = eqx.field(static=True, default=0.0025)
    weight: float = eqx.field(static=True, default=100e3)
    newton_iterations: int = eqx.field(static=True, default=NEWTON_ITERATIONS)
    newton_tolerance: float = eqx.field(static=True, default=NEWTON_TOLERANCE)
    split_at_turn: bool = eqx.field(static=True, default=True)
    linear_rule: str = eqx.field(static=True, default="exact")
    components: int = eqx.field(static=True, default=1)
    vertical: bool = eqx.field(static=True, default=False)
    bearing: SlidingBearing | None = None
    surface: ConcaveSurface | None = None
    pendulum: SeriesPendulum | None = None

    def __check_init__(self):
        """Settings of one component are refused by name on flat sliders under two (their
        planar solve takes Park's Z along each step's increment and the Newmark step)."""
        if self.components == 2 and self.pendulum is None:
            given = [name for name, set_ in (("split_at_turn", not self.split_at_turn),
                                             ("linear_rule", self.linear_rule != "exact")) if set_]
            if given:
                raise ValueError(f"{', '.join(given)}: a setting of one horizontal component; under two the flat "
                                 "sliders' planar solve takes Park's Z along each step's increment and the "
                                 "Newmark step. Leave it at its default (split_at_turn=True, linear_rule='exact').")

    @property
    def isolator(self) -> str:
        """The isolator's name (`teflon_jax.catalogue.ISOLATORS`): flat, single or the pendulum's."""
        if self.pendulum is not None:
            return self.pendulum.isolator
        return FLAT.name if self.surface is None else SINGLE_FP.name

    def table(self):
        """The Table 1 rows (extrapolation switched off by our own range check)."""
        return friction_table(self.ptfe, self.direction, extrapolate=True)

    def isolation(self, design: Mapping | None = None):
        """The bearing, isolation period [s] and damping ratio [-] of this structure with the
        `design` variables (`DESIGN_VARIABLES`) in place of its own; unknown names refused."""
        design = {} if design is None else dict(design)
        unknown = sorted(set(design) - set(DESIGN_VARIABLES))
        if unknown:
            raise ValueError(
                f"design: unknown variable(s) {unknown}; accepted: {', '.join(DESIGN_VARIABLES)}."
            )
        if self.bearing is not None:
            bearing = self._given_bearing(design).at_contact_pressure(
                design.get("pressure", self.pressure))
        else:
            pressure = design.get("pressure", self.pressure)
            params, b = self.table().at(pressure)
            params = FrictionParameters(
                f_max=design.get("f_max", params.f_max),
                delta_f=design.get("delta_f", params.delta_f),
                rate_a=design.get("rate_a", params.rate_a),
            )
            b = design.get("breakaway_ratio", b)
            bearing = paper_bearing(params, breakaway_ratio=b if self.breakaway else None)
        period = self._period(design)
        damping = design.get("isolation_damping", self.isolation_damping)
        return bearing, period, damping

    def _period(self, design):
        """T_b [s]: the springs' (flat sliders) or 2 pi sqrt(R / g) of the surface (pendulum)."""
        wrong = ("radius", "capacity") if self.surface is None else ("isolation_period",)
        for name in wrong:
            if name in design:
                raise ValueError(f"design: {name!r} does not apply to the {self.isolator} isolator.")
        if self.surface is None:
            return design.get("isolation_period", self.isolation_period)
        return self.designed_surface(design).isolation_period()

    def designed_surface(self, design=None):
        """`surface` with the design's radius and capacity in place of its own (`ValueError`
        for a capacity on a surface without restrainer)."""
        design = design or {}
        surface = eqx.tree_at(lambda c: c.radius, self.surface,
                              jnp.asarray(design.get("radius", self.surface.radius), float))
        if "capacity" not in design:
            return surface
        if surface.displacement_capacity is None:
            raise ValueError("design: 'capacity' needs a surface with a restrainer: build it with "
                             "concave_surface(R, displacement_capacity=d, restrainer_stiffness=k_r).")
        return eqx.tree_at(lambda c: c.displacement_capacity, surface, jnp.asarray(design["capacity"], float))

    def contact_pressure(self, design=None):
        """The bearings' contact pressure [Pa] for a bearing with heating (else None; a
        pressure dependence is folded into the bearing by `isolation`)."""
        if self.bearing is None or self.bearing.heating is None:
            return None
        return (design or {}).get("pressure", self.pressure)

    @property
    def pressure_matters(self) -> bool:
        """Whether the contact pressure changes the response: always for Table 1's bearings,
        for a given bearing through its heating or pressure dependence."""
        b = self.bearing
        return b is None or b.heating is not None or b.pressure_dependence is not None

    def _given_bearing(self, design):
        """`bearing` with the design's friction constants in place of its own."""
        if "pressure" in design and not self.pressure_matters:
            raise ValueError("design: 'pressure' picks a Table 1 row; this structure runs a given "
                             "bearing without heating or pressure dependence (set f_max, delta_f, "
                             "rate_a or breakaway_ratio instead).")
        f = self.bearing.friction
        friction = FrictionParameters(
            f_max=design.get("f_max", f.f_max),
            delta_f=design.get("delta_f", f.delta_f),
            rate_a=design.get("rate_a", f.rate_a),
        )
        b = design.get("breakaway_ratio", self.bearing.breakaway_ratio)
        return eqx.tree_at(lambda x: (x.friction, x.breakaway_ratio), self.bearing,
                           (friction, None if b is None else jnp.asarray(b, float)),
                           is_leaf=lambda x: x is None)

    def __call__(self, ground_acceleration, design: Mapping | None = None) -> StructureOnSliders:
        if self.vertical:
            if not (isinstance(ground_acceleration, tuple) and len(ground_acceleration) == 2):
                raise ValueError("ground_acceleration: this structure takes (horizontal, vertical) ground motions "
                                 "(with_vertical_component).")
            horizontal, vertical = ground_acceleration
            return with_vertical_motion(self._horizontal(horizontal, design), vertical,
                                        **self._pressure_law(design))
        return self._horizontal(ground_acceleration, design)

    def _pressure_law(self, design) -> dict:
        """How the friction follows a vertical record's load (`vertical`; `with_vertical_motion`'s arguments)."""
        if self.pendulum is not None or self.friction_model == "none":
            return {}
        if self.bearing is None:
            return {"friction_table": self.table(), "table_pressure": (design or {}).get("pressure", self.pressure)}
        part = self.bearing.pressure_dependence
        return {} if part is None else {"pressure_exponent": part.exponent}

    def _horizontal(self, ground_acceleration, design) -> StructureOnSliders:
        """The structure under the horizontal ground motion (one `Signal` or an (x, y) pair)."""
        if isinstance(ground_acceleration, tuple) != (self.components == 2):
            raise ValueError(f"ground_acceleration: this structure takes {self.components} horizontal component(s) "
                             "(isolated_structure: one Signal; bidirectional_isolated_structure: an (x, y) pair).")
        if self.pendulum is not None:
            return self._on_sliders_in_series(ground_acceleration, design)
        two = self.components == 2
        ground_x, ground_y = ground_acceleration if two else (ground_acceleration, None)
        bearing, period, damping = self.isolation(design)
        surface = None if self.surface is None else self.designed_surface(design)
        common = dict(bearing=bearing, ground_acceleration=ground_x, ground_y=ground_y, components=self.components,
                      time_step=self.time_step, isolation_period=period, friction_model=self.friction_model,
                      contact_pressure=self.contact_pressure(design),
                      **({"surface": surface} if two else {"linear_rule": self.linear_rule}))
        if self.kind == "rigid":
            system = rigid_mass(weight=self.weight, damping_ratio=damping if period is not None else 0.0, **common)
        else:
            system = six_storey_building(isolation_damping=damping, **common)
        if two:  # the planar solve: its `newton_iterations` bound it, its `newton_tolerance` (in Y) ends it
            return dataclasses.replace(system, newton_iterations=self.newton_iterations,
                                       newton_tolerance=self.newton_tolerance)
        if surface is not None:  # W / R: the part of K a vertical record's load scales
            system = dataclasses.replace(system, pendulum_stiffness=system.bearing_load / surface.radius)
        if surface is not None and not self.surface.is_linear:
            system = dataclasses.replace(system, surface=surface)
        settings = (self.newton_iterations, self.split_at_turn, self.newton_tolerance)
        if settings != (system.newton_iterations, system.split_at_turn, system.newton_tolerance):
            system = dataclasses.replace(system, newton_iterations=self.newton_iterations,
                                         split_at_turn=self.split_at_turn, newton_tolerance=self.newton_tolerance)
        return system

    def _on_sliders_in_series(self, ground_acceleration, design) -> StructureOnSliders:
        """The structure on the series pendulum with the design's variables (`designed_pendulum`:
        its design space, a bounding case's `FRICTION_FACTOR`), under one or two components."""
        pendulum = designed_pendulum(self.pendulum, design) if design else self.pendulum
        two = self.components == 2
        return triple_structure(self.kind, pendulum, ground_acceleration[0] if two else ground_acceleration,
                                time_step=self.time_step, weight=self.weight,
                                newton_iterations=self.newton_iterations, newton_tolerance=self.newton_tolerance,
                                ground_y=ground_acceleration[1] if two else None)


TRIPLE_MONTE_CARLO_TOLERANCE = 1e-7
"""`IsolatedStructure.newton_tolerance` of the Monte Carlo command on a series pendulum: the
sliders' force imbalance over W (a displacement error below 1e-7 R_e of each slider)."""


def isolated_structure(
    kind: str = "rigid",
    *,
    ptfe: str = "UF",
    direction: str = "P",
    pressure=DEFAULT_PRESSURE,
    isolation_period=DEFAULT_ISOLATION_PERIOD,
    isolation_damping=None,
    breakaway: bool = True,
    friction_model: str = "hysteretic",
    time_step: float | None = None,
    newton_iterations: int = NEWTON_ITERATIONS,
    newton_tolerance: float = NEWTON_TOLERANCE,
    split_at_turn: bool = True,
    linear_rule: str = "exact",
    isolator=None,
    bearing: SlidingBearing | None = None,
) -> IsolatedStructure:
    """An `IsolatedStructure` with its inputs checked (`ValueError` naming the parameter).

    **Arguments:** see `IsolatedStructure`; `pressure` [Pa] must lie inside the Table 1 rows
    of `ptfe`/`direction` (1000-6500 psi for UF, P), `isolation_period` [s] > 0 (or `None`
    for a rigid mass on flat sliders), `isolation_damping` >= 0 (default 0.05 on flat sliders,
    0 on a friction pendulum, whose damping is its friction), `time_step` > 0 [s]
    (default `RECOMMENDED_TIME_STEPS[kind]`), `newton_iterations` a positive integer (the
    default lets every step converge; 1 cuts the solve short: runs are then reported as not
    converged).

    `isolator`: the isolator value (`bearing.isolator_kind`), whose type picks the engine:
    `None` (the default) Table 1's flat sliders; a `SlidingBearing`: flat sliders of that
    bearing; a `ConcaveSurface` (`concave_surface`, with a restrainer or the large-displacement
    form only with hysteretic friction) or a (`SlidingBearing`, `ConcaveSurface`) pair: the
    single friction pendulum (then `isolation_period` must be `None`: the period is
    2 pi sqrt(R / g)); a `SinglePendulum`: either of these on the flat sliders' engine. A
    `TriplePendulum` or `DoublePendulum`: the structure on its sliders in series
    (`IsolatedStructure.pendulum`; its friction is its surfaces' Eq. 1; `newton_tolerance` is
    then the sliders' force imbalance over W, default `TRIPLE_TOLERANCE`); the flat sliders'
    period, damping and friction model are refused with it.

    `bearing`: flat sliders of that `SlidingBearing`, the same as `isolator=bearing` (no
    other isolator with it: a single pendulum of that bearing is `isolator=(bearing, surface)`).
    """
    if kind not in STRUCTURES:
        raise ValueError(f"structure: unknown {kind!r}; accepted: {', '.join(STRUCTURES)}.")
    isolator = _isolator_value(isolator, bearing)
    if isinstance(newton_iterations, bool) or not isinstance(newton_iterations, int) or newton_iterations < 1:
        raise ValueError(f"newton_iterations: must be a positive integer, got {newton_iterations!r}.")
    if isinstance(newton_tolerance, bool) or not isinstance(newton_tolerance, (int, float)) or not newton_tolerance >= 0:
        raise ValueError(f"newton_tolerance: must be a number >= 0 (in units of Y; on a series pendulum the "
                         f"force imbalance over W), got {newton_tolerance!r}.")
    time_step = RECOMMENDED_TIME_STEPS[kind] if time_step is None else time_step
    if isinstance(time_step, bool) or not isinstance(time_step, (int, float)) or not time_step > 0:
        raise ValueError(f"time_step: must be a positive number of seconds, got {time_step!r}.")
    if runs_in_series(isolator):
        own = "its surfaces carry their own friction and its sliders their own balance; leave it out"
        flat_inputs = {
            "isolation_period": (isolation_period is not DEFAULT_ISOLATION_PERIOD and isolation_period is not None,
                                 "its period follows from its radii"),
            "isolation_damping": (bool(isolation_damping), "its damping is its friction"),
            "friction_model": (friction_model != "hysteretic", "its sliders follow Bouc-Wen's Z"),
            "pressure": (pressure is not DEFAULT_PRESSURE, own), "ptfe": (ptfe != "UF", own),
            "direction": (direction != "P", own), "breakaway": (breakaway is not True, own),
            "split_at_turn": (split_at_turn is not True, own), "linear_rule": (linear_rule != "exact", own)}
        return _on_series_pendulum(kind, isolator, time_step=time_step, newton_iterations=newton_iterations,
                                   newton_tolerance=newton_tolerance,
                                   refused={name: why for name, (given, why) in flat_inputs.items() if given})
    bearing, surface = one_surface(isolator)
    given_period = isolation_period is not DEFAULT_ISOLATION_PERIOD
    if surface is not None and given_period and isolation_period is not None:
        raise ValueError("isolation_period: the single-fp isolator's period is 2 pi sqrt(R / g) of "
                         "its radius; give isolation_period=None.")
    if surface is not None and not surface.is_linear and friction_model != "hysteretic":
        raise ValueError(f"surface: its restrainer or large-displacement force is solved with the "
                         f"hysteretic friction model, not {friction_model!r}.")
    if surface is not None:
        isolation_period = None
    elif not given_period:
        isolation_period = 2.0
    if isolation_damping is None:
        isolation_damping = 0.05 if surface is None else 0.0
    if linear_rule not in LINEAR_RULES:
        raise ValueError(f"linear_rule: unknown {linear_rule!r}; accepted values: {', '.join(LINEAR_RULES)}.")
    structure = IsolatedStructure(
        pressure=jnp.asarray(pressure, dtype=float),
        isolation_period=None if isolation_period is None else jnp.asarray(isolation_period, float),
        isolation_damping=jnp.asarray(isolation_damping, dtype=float), bearing=bearing, surface=surface,
        kind=kind, ptfe=ptfe, direction=direction, breakaway=breakaway, friction_model=friction_model,
        linear_rule=linear_rule, time_step=float(time_step), newton_iterations=int(newton_iterations),
        newton_tolerance=float(newton_tolerance), split_at_turn=bool(split_at_turn))
    if bearing is not None:
        require_positive(pressure, "pressure", " [Pa] (the bearings' contact pressure)")
        check_structure_bearing(bearing, pressure)
        return _checked_isolation(structure, kind, isolation_period, isolation_damping)
    check_design(structure, {"pressure": pressure})
    return _checked_isolation(structure, kind, isolation_period, isolation_damping)


def _isolator_value(isolator, bearing):
    """The isolator value of `isolated_structure`'s `isolator` and `bearing` (`ValueError`
    naming `isolator` for a value of another type, `bearing` for one that is not a
    `SlidingBearing` or is given beside an isolator value)."""
    isolator_kind(isolator)
    if bearing is None:
        return isolator
    if not isinstance(bearing, SlidingBearing):
        raise ValueError(f"bearing: expected a SlidingBearing, got a {type(bearing).__name__} (give an "
                         "isolator value as isolator=).")
    if isolator is not None:
        raise ValueError(f"bearing: the isolator value ({type(isolator).__name__}) carries the whole isolator; "
                         "leave bearing out (a single pendulum of that bearing: isolator=(bearing, surface)).")
    return bearing


def _on_series_pendulum(kind, pendulum, *, time_step, newton_iterations, newton_tolerance,
                        refused) -> IsolatedStructure:
    """`isolated_structure` on a series pendulum, checked: `ValueError` naming the constant the
    series model cannot take (`check_series_pendulum`; traced constants, under a gradient,
    are the caller's to check) and each flat sliders' input given with it (`refused`: name ->
    why it does not apply). `newton_tolerance` at the flat sliders' default means the sliders'
    `TRIPLE_TOLERANCE`."""
    if all(concrete(leaf) is not None for leaf in jax.tree_util.tree_leaves(pendulum)):
        check_series_pendulum(pendulum)
    for name, why in refused.items():
        raise ValueError(f"{name}: does not apply to the {pendulum.isolator} isolator ({why}).")
    return IsolatedStructure(
        pressure=None, isolation_period=None, isolation_damping=jnp.asarray(0.0), pendulum=pendulum, kind=kind,
        time_step=float(time_step),
        newton_iterations=int(newton_iterations if newton_iterations != NEWTON_ITERATIONS else TRIPLE_NEWTON_ITERATIONS),
        newton_tolerance=TRIPLE_TOLERANCE if newton_tolerance == NEWTON_TOLERANCE else float(newton_tolerance))


def _checked_isolation(structure, kind, isolation_period, isolation_damping):
    if isolation_period is None and kind == "building" and structure.surface is None:
        raise ValueError("isolation_period: the building needs T_b [s] > 0 (Fig. 11: 0.2-4 s).")
    if isolation_period is not None:
        check_design(structure, {"isolation_period": isolation_period})
    check_design(structure, {"isolation_damping": isolation_damping})
    return structure


def check_structure_bearing(bearing: SlidingBearing, pressure=1.0) -> None:
    """`check_bearing`, and a `ValueError` naming the optional parts of `bearing` the
    structures do not run (`STRUCTURE_EFFECTS`, and pressure dependence when the bearing
    cannot take it at a contact pressure: `SlidingBearing.at_contact_pressure`)."""
    from ..bearing import check_bearing

    check_bearing(bearing)
    check_structure_parts(eqx.tree_at(lambda b: b.pressure_dependence, bearing, None,
                                      is_leaf=lambda x: x is None))
    bearing.at_contact_pressure(pressure)  # a pressure dependence needs the contact area


def with_vertical_component(structure: IsolatedStructure) -> IsolatedStructure:
    """`structure` (an `IsolatedStructure` of any isolator, one or two horizontal components)
    taking (horizontal, vertical) ground motions, the vertical acceleration [m/s^2, up +] on its
    isolators' normal load (`IsolatedStructure.vertical`, `with_vertical_motion`); `ValueError`
    naming `structure` for anything else, or one that takes a vertical component already."""
    if not isinstance(structure, IsolatedStructure):
        raise ValueError(f"structure: expected an IsolatedStructure (isolated_structure(...)), "
                         f"got {type(structure).__name__}.")
    if structure.vertical:
        raise ValueError("structure: it takes a vertical component already (with_vertical_component "
                         "was applied to it once).")
    return dataclasses.replace(structure, vertical=True)
