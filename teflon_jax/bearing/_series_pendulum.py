"""Friction pendulums modelled as sliders in series, and the double friction pendulum.

A multi-surface friction pendulum carries one horizontal force through every sliding surface,
and its displacement is the sum of the surfaces' (each slider's) displacements. Slider e has a
radius R_e, a displacement capacity d_e before its restrainer, Eq. 1 friction at its surface's
velocity (the slider's times a factor c_e) and Bouc-Wen's Z; `SeriesPendulum` is what the
structures and the bearing test read of such an isolator, whatever the number of sliders.

The double concave friction pendulum has two concave plates, bottom (surface 1) and top
(surface 2), with an articulated slider between them. With effective radii R_i - h_i and
effective capacities d_i (R_i - h_i) / R_i, it is exactly two sliders in series at the
surfaces' own velocities (Fenz & Constantinou 2006, Earthquake Engng Struct. Dyn. 35,
1403-1424): for mu_1 < mu_2 it slides on surface 1 alone from F/W = mu_1 (slope 1 / R_1), on
both from F/W = mu_2 (slope 1 / (R_1 + R_2)), and on surface 2 alone once surface 1 meets its
restrainer (slope 1 / R_2).

The single friction pendulum is the case S = 1 (`SinglePendulum`): one surface of radius R,
or R = inf for the flat slider, with the flat bearing's whole interface law.
"""

import abc
import math
from collections.abc import Mapping
from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import ArrayLike

from ..catalogue import DOUBLE_FP, SINGLE_FP
from ..validation import require, require_positive
from ._bearing import SlidingBearing, check_heating
from ._effects import FrictionalHeating
from ._friction import FrictionParameters
from ._hysteresis import BoucWen
from ._surface import SurfaceParts, check_friction, check_surface_parts


class SeriesPendulum(eqx.Module):
    """A friction pendulum isolator as sliders in series (module docstring).

    **Class attributes:** `isolator` (the CLI's and the isolator file's name, its kind's in
    `teflon_jax.catalogue`; the registry `SERIES_PENDULUMS` lists the classes), `slider_names` (one per slider, in the order of the arrays below),
    `description` (plural, for messages). **Field:** `hysteresis`, the `BoucWen` of every
    slider. **Methods** (arrays (S,) over the S sliders): `series_radii` [m],
    `series_capacities` [m], `velocity_factors` [-] (surface velocity over slider velocity),
    `frictions` (stacked `FrictionParameters`), `reference_radius` [m] (the radius of the
    reference spring W / R_ref that the structures' linear step carries); for heated surfaces
    (fields `<slider>_heating`, `<slider>_pressure`) `surface_heatings`, `heated`,
    `heat_factors`, `heat_fluxes`; `scaled_friction` (every surface's friction times a factor).
    **Design space** (`teflon_jax.bearing.design_space`): `design_variables` (class attribute),
    `designed`, `design_ranges`, `check_design_box`, each pendulum's own.
    """

    isolator: ClassVar[str]
    slider_names: ClassVar[tuple[str, ...]]
    description: ClassVar[str]
    design_variables: ClassVar[tuple[str, ...]] = ()
    hysteresis: eqx.AbstractVar[BoucWen]

    @property
    def slider_count(self) -> int:
        """Number S of sliders in series (static)."""
        return len(self.slider_names)

    @abc.abstractmethod
    def series_radii(self):
        """Radii [m] (S,) of the sliders."""

    @abc.abstractmethod
    def series_capacities(self):
        """Travel [m] (S,) of each slider before its restrainer."""

    @abc.abstractmethod
    def velocity_factors(self):
        """Sliding velocity of each surface over its slider's velocity (S,) [-]."""

    @abc.abstractmethod
    def frictions(self) -> FrictionParameters:
        """Eq. 1 constants of the sliders, stacked (S,)."""

    @abc.abstractmethod
    def reference_radius(self):
        """R_ref [m] of the structures' reference spring W / R_ref."""

    def surface_heatings(self) -> tuple:
        """`FrictionalHeating` (or `None`) of each slider's surface, from the fields
        `<slider>_heating` (none: no heating)."""
        return tuple(getattr(self, f"{name}_heating", None) for name in self.slider_names)

    def parts(self) -> tuple:
        """`SurfaceParts` (or `None`) of each slider's surface (static structure)."""
        parts = getattr(self, "surface_parts", None)
        return (None,) * self.slider_count if parts is None else tuple(parts)

    @property
    def has_parts(self) -> bool:
        """Whether any surface has a part beyond Eq. 1 and heating (static)."""
        return any(part is not None for part in self.parts())

    @property
    def reads_pressure(self) -> bool:
        """Whether a surface's law reads its contact pressure (static): heating (the flux mu p v)
        or a part's pressure dependence. Its `<slider>_pressure` is given under the static load,
        and a normal load N scales it by N / that load."""
        return self.heated or any(part is not None and part.pressure_dependence is not None for part in self.parts())

    @property
    def remembers(self) -> bool:
        """Whether any surface's part needs the slider's history, its largest |Z| so far
        (breakaway) or its travel (wear) (static)."""
        return any(part is not None and part.remembers for part in self.parts())

    def contact_pressures(self):
        """Contact pressures [Pa] (S,) of the surfaces under the static load W
        (`<slider>_pressure`; 0 where not given), for heating and pressure dependence."""
        return jnp.stack([jnp.zeros(()) if getattr(self, f"{name}_pressure", None) is None
                          else jnp.asarray(getattr(self, f"{name}_pressure"), float) for name in self.slider_names])

    def surface_bearings(self) -> tuple:
        """Each slider's surface as a flat `SlidingBearing`: its Eq. 1 constants, the
        pendulum's Bouc-Wen constants, its heating and its `SurfaceParts`, the whole
        interface law of the bearing model."""
        frictions = [getattr(self, f"{name}_friction") for name in self.slider_names]
        return tuple((SurfaceParts() if part is None else part).bearing(friction, self.hysteresis, heating)
                     for friction, heating, part in zip(frictions, self.surface_heatings(), self.parts()))

    def scaled_friction(self, factor) -> "SeriesPendulum":
        """This isolator with every surface's friction coefficient `factor` times its own at
        every velocity: f_max and delta_f of each surface's Eq. 1 times `factor` (so f_min =
        f_max - delta_f too; delta_f = 0, Coulomb friction, stays so), rate_a, radii,
        capacities, hysteresis and heating kept. A bounding case's property modification
        factor (`teflon_jax.studies.bounding_design`); a factor > 0 keeps the surfaces' order
        of friction. `factor` may be traced."""
        names = [f"{name}_friction" for name in self.slider_names]
        return self.with_fields(**{n: getattr(self, n).scaled(factor) for n in names})

    def check(self) -> None:
        """`ValueError` naming the constant this isolator's model cannot take (its class's check)."""
        raise NotImplementedError

    def with_fields(self, **fields) -> "SeriesPendulum":
        """This isolator with the named fields replaced (values may be traced), everything else
        (its heating, contact pressures and surface parts) kept."""
        names = list(fields)
        return eqx.tree_at(lambda p: [getattr(p, name) for name in names], self, [fields[n] for n in names])

    def designed(self, design: Mapping) -> "SeriesPendulum":
        """This isolator with the variables of `design` (`design_variables`; values may be
        traced) applied; `ValueError` naming an unknown variable."""
        unknown = sorted(set(design) - set(self.design_variables))
        if unknown:
            raise ValueError(f"design: unknown variable(s) {unknown} for the {self.isolator} isolator; "
                             f"accepted: {', '.join(self.design_variables) or 'none'}.")
        return self._designed(design)

    def _designed(self, design: Mapping) -> "SeriesPendulum":
        return self

    def design_ranges(self) -> dict:
        """Admissible (low, high) of each design variable taken alone."""
        return {}

    def _box_ranges(self, box: Mapping) -> dict:
        """(low, high) of each variable at the corners of `box` (`design_ranges`, unless the
        variables bound each other)."""
        return self.design_ranges()

    def check_design_box(self, box: Mapping) -> None:
        """`ValueError` naming the variable whose bounds (low, high) in `box` leave what this
        isolator takes at a corner of the box (`design_ranges`), or one it does not have."""
        ranges = self._box_ranges(box)
        for name, (lo, hi) in box.items():
            if name not in ranges:
                raise ValueError(f"design: unknown variable {name!r} for the {self.isolator} isolator; "
                                 f"accepted: {', '.join(self.design_variables) or 'none'}.")
            low, high = ranges[name]
            if not (low <= lo and hi <= high):
                raise ValueError(f"{name}: bounds ({lo:.6g}, {hi:.6g}) leave the admissible ({low:.6g}, "
                                 f"{high:.6g}) of this isolator ({self._rule()}); narrow them.")

    def _rule(self) -> str:
        """What the design variables must keep, as the box's error says it."""
        return "positive scales"

    @property
    def heated(self) -> bool:
        """Whether any surface heats up (static)."""
        return any(h is not None for h in self.surface_heatings())

    def heat_factors(self, heat, weights):
        """Factors (S,) [-] on each surface's friction at its heat states `heat` (S, K) of the
        kernel of `weights` (K,): k_T(T0 + dT_e) / k_T(T0) (`FrictionalHeating.factor`), 1
        where a surface has no heating."""
        return jnp.stack([jnp.ones((), heat.dtype) if h is None else h.factor(h.rise(heat[e], weights))
                          for e, h in enumerate(self.surface_heatings())])

    def heat_fluxes(self, coefficients, speeds, load_factor=1.0):
        """Heat fluxes q_e = mu_e p_e v_e [W/m^2] (S,) into each surface's steel at the surface
        speeds v_e [m/s] (S,), coefficients mu_e [-] (S,) and the contact pressures p_e
        (`<slider>_pressure` [Pa] under the static load W) times the load factor N / W; 0
        where a surface has no heating (each surface heated by its own flux, as in Kim &
        Constantinou's TripleFrictionPendulumX element of OpenSees)."""
        return jnp.stack([
            jnp.zeros_like(speeds[e]) if h is None else
            h.flux(coefficients[e], load_factor * getattr(self, f"{name}_pressure") * h.contact_area, speeds[e])
            for e, (name, h) in enumerate(zip(self.slider_names, self.surface_heatings()))])


def stack_frictions(parts) -> FrictionParameters:
    """`FrictionParameters` of several surfaces stacked along a first axis."""
    return FrictionParameters(*(jnp.stack([jnp.asarray(getattr(p, name), float) for p in parts])
                                for name in ("f_max", "delta_f", "rate_a")))


class DoublePendulum(SeriesPendulum):
    """A double concave friction pendulum bearing (module docstring): two sliders in series,
    bottom then top, each at its surface's velocity.

    **Fields** (effective radii R - h [m]; effective capacities d (R - h) / R [m]):
    `bottom_radius` R_1, `top_radius` R_2, `bottom_capacity` d_1, `top_capacity` d_2,
    `bottom_friction`, `top_friction`: Eq. 1 constants of each surface (`FrictionParameters`;
    delta_f = 0 for Coulomb friction); `hysteresis`: `BoucWen` of both sliders;
    `bottom_heating`, `top_heating`, `bottom_pressure`, `top_pressure`: as the triple's;
    `surface_parts`: (bottom, top) `SurfaceParts` or `None` each, or `None`.
    """

    isolator: ClassVar[str] = DOUBLE_FP.name
    slider_names: ClassVar[tuple[str, ...]] = ("bottom", "top")
    description: ClassVar[str] = DOUBLE_FP.description
    design_variables: ClassVar[tuple[str, ...]] = ("radius_scale", "surface_f_max", "capacity_scale")
    """`radius_scale` s [-] (R_1, R_2 -> s R_1, s R_2: every slope 1 / R_1, 1 / (R_1 + R_2),
    1 / R_2 of the backbone falls by 1 / s), `surface_f_max` [-] (Eq. 1 of the bottom surface
    scaled to this f_max, the top's by the same factor: their ratio, and so which surface
    slides first, kept), `capacity_scale` [-] (d_1, d_2 times it). Fenz & Constantinou (2006),
    Earthquake Engng Struct. Dyn. 35."""
    bottom_radius: ArrayLike
    top_radius: ArrayLike
    bottom_capacity: ArrayLike
    top_capacity: ArrayLike
    bottom_friction: FrictionParameters
    top_friction: FrictionParameters
    hysteresis: BoucWen
    bottom_heating: FrictionalHeating | None = None
    top_heating: FrictionalHeating | None = None
    bottom_pressure: ArrayLike | None = None
    top_pressure: ArrayLike | None = None
    surface_parts: tuple | None = None

    def series_radii(self):
        """(R_1, R_2) [m]."""
        return jnp.stack([jnp.asarray(self.bottom_radius, float), jnp.asarray(self.top_radius, float)])

    def series_capacities(self):
        """(d_1, d_2) [m]."""
        return jnp.stack([jnp.asarray(self.bottom_capacity, float), jnp.asarray(self.top_capacity, float)])

    def velocity_factors(self):
        """(1, 1): each slider is its surface."""
        return jnp.ones(2)

    def frictions(self) -> FrictionParameters:
        """Eq. 1 constants (bottom, top), stacked."""
        return stack_frictions((self.bottom_friction, self.top_friction))

    def reference_radius(self):
        """R_1 + R_2 [m]: both surfaces sliding together."""
        return self.bottom_radius + self.top_radius

    def check(self) -> None:
        """`check_double_pendulum`."""
        check_double_pendulum(self)

    def _designed(self, design: Mapping) -> "DoublePendulum":
        s, k = design.get("radius_scale", 1.0), design.get("capacity_scale", 1.0)
        factor = design.get("surface_f_max", self.bottom_friction.f_max) / self.bottom_friction.f_max
        return self.with_fields(
            bottom_radius=s * self.bottom_radius, top_radius=s * self.top_radius,
            bottom_capacity=k * self.bottom_capacity, top_capacity=k * self.top_capacity,
            bottom_friction=self.bottom_friction.scaled(factor), top_friction=self.top_friction.scaled(factor))

    def design_ranges(self) -> dict:
        """Positive scales; the bottom f_max such that the top's (scaled alike) stays at most 1."""
        m1, m2 = (float(np.asarray(f.f_max)) for f in (self.bottom_friction, self.top_friction))
        return {"radius_scale": (1e-6, math.inf), "surface_f_max": (1e-6, min(1.0, m1 / m2)),
                "capacity_scale": (1e-6, math.inf)}

    def _rule(self) -> str:
        m1, m2 = (float(np.asarray(f.f_max)) for f in (self.bottom_friction, self.top_friction))
        return (f"positive radii and capacities; the bottom f_max and the top's, {m2 / m1:.4g} times it, "
                "within (0, 1]")


class SinglePendulum(SeriesPendulum):
    """One sliding surface as an isolator of sliders in series (S = 1): the single friction
    pendulum of effective radius R, or with R = inf the flat slider, F = N (u / R + mu Z) (and
    the restrainer beyond the capacity), the surface's whole interface law: Eq. 1, Bouc-Wen
    (Park's model in two components), heating and the `SurfaceParts` (breakaway, anisotropy,
    wear, direction asymmetry, pressure dependence). `single_pendulum` makes one of a flat
    `SlidingBearing`.

    **Fields:** `surface_radius` R [m] (> 0; inf: flat), `surface_friction`
    (`FrictionParameters`), `hysteresis` (`BoucWen`), `surface_capacity` d [m] where the
    restrainer engages (`None`: none), `surface_heating` (`FrictionalHeating` or `None`) with
    `surface_pressure` [Pa], the contact pressure under the static load, `surface_parts`
    ((`SurfaceParts`,) or `None`), as the double's and the triple's.
    """

    isolator: ClassVar[str] = SINGLE_FP.name
    slider_names: ClassVar[tuple[str, ...]] = ("surface",)
    description: ClassVar[str] = "single friction pendulums or flat sliders"
    surface_radius: ArrayLike
    surface_friction: FrictionParameters
    hysteresis: BoucWen
    surface_capacity: ArrayLike | None = None
    surface_heating: FrictionalHeating | None = None
    surface_pressure: ArrayLike | None = None
    surface_parts: tuple | None = None

    def series_radii(self):
        """(R,) [m] (inf for a flat slider)."""
        return jnp.asarray(self.surface_radius, float)[None]

    def series_capacities(self):
        """(d,) [m]; inf without a restrainer."""
        if self.surface_capacity is None:
            return jnp.full((1,), jnp.inf)
        return jnp.asarray(self.surface_capacity, float)[None]

    def velocity_factors(self):
        """(1,): the slider is its surface."""
        return jnp.ones(1)

    def frictions(self) -> FrictionParameters:
        """Eq. 1 constants (1,)."""
        return stack_frictions((self.surface_friction,))

    def reference_radius(self):
        """R [m] (inf for a flat slider: no reference spring)."""
        return jnp.asarray(self.surface_radius, float)

    def check(self) -> None:
        """`check_single_pendulum`."""
        check_single_pendulum(self)


def single_pendulum(bearing: SlidingBearing, *, radius=math.inf, capacity=None, contact_pressure=None) -> SinglePendulum:
    """The `SinglePendulum` of the flat bearing `bearing` (its Eq. 1, Bouc-Wen constants,
    heating and every other part as the surface's) on a surface of `radius` R [m] (inf, the
    default: a flat slider) with a restrainer at `capacity` [m] (`None`: none);
    `contact_pressure` [Pa] under the static load, needed for heating and pressure dependence.
    `ValueError` naming `n_interfaces` or `backlash`, which a structure's surface does not
    take (a stack of interfaces, a test rig's gap)."""
    if bearing.n_interfaces != 1:
        raise ValueError(f"n_interfaces: a single pendulum's surface is one interface, got {bearing.n_interfaces}.")
    if bearing.backlash is not None:
        raise ValueError("backlash: a gap of the test rig, not a part of a structure's surface.")
    parts = SurfaceParts(breakaway_ratio=bearing.breakaway_ratio,
                         friction_perpendicular=bearing.friction_perpendicular, lay_angle=bearing.lay_angle,
                         pressure_dependence=bearing.pressure_dependence, wear=bearing.wear,
                         asymmetry=bearing.asymmetry)
    plain = all(getattr(parts, name) is None for name in ("breakaway_ratio", "friction_perpendicular",
                                                          "pressure_dependence", "wear", "asymmetry"))
    return SinglePendulum(surface_radius=jnp.asarray(radius, float), surface_friction=bearing.friction,
                          hysteresis=bearing.hysteresis,
                          surface_capacity=None if capacity is None else jnp.asarray(capacity, float),
                          surface_heating=bearing.heating,
                          surface_pressure=None if contact_pressure is None else jnp.asarray(contact_pressure, float),
                          surface_parts=None if plain else (parts,))


def check_single_pendulum(bearing: SinglePendulum) -> None:
    """`ValueError` naming the constant the model cannot take: `surface_radius` > 0 (inf: a
    flat slider), `surface_capacity` > 0 or `None`, the yield displacement > 0, the surface's
    friction what Eq. 1 takes (`check_friction`), its heating and parts
    (`check_surface_heating`)."""
    if not isinstance(bearing, SinglePendulum):
        raise ValueError(f"single: expected a SinglePendulum, got {type(bearing).__name__}.")
    require(bearing.surface_radius, lambda x: x > 0, "surface_radius", "must be > 0 [m] (inf: a flat slider)")
    if bearing.surface_capacity is not None:
        require_positive(bearing.surface_capacity, "surface_capacity", " [m] (None: no restrainer)")
    check_friction(bearing.surface_friction, "surface_friction")
    require_positive(bearing.hysteresis.yield_disp, "yield_disp", " [m]")
    check_surface_heating(bearing)


def check_double_pendulum(bearing: DoublePendulum) -> None:
    """`ValueError` naming the constant the model cannot take: radii, capacities and the
    yield displacement must be positive, and each surface's friction what Eq. 1 takes
    (`check_friction`). Either surface may be the slipperier one."""
    if not isinstance(bearing, DoublePendulum):
        raise ValueError(f"double: expected a DoublePendulum, got {type(bearing).__name__}.")
    for name in ("bottom_radius", "top_radius", "bottom_capacity", "top_capacity"):
        require_positive(getattr(bearing, name), name, " [m]")
    for name in ("bottom_friction", "top_friction"):
        check_friction(getattr(bearing, name), name)
    require_positive(bearing.hysteresis.yield_disp, "yield_disp", " [m]")
    check_surface_heating(bearing)


def check_surface_heating(bearing: SeriesPendulum) -> None:
    """`ValueError` naming `<slider>_heating.<constant>` or `<slider>_pressure` where a heated
    surface's constants are out of range or its contact pressure is missing, or naming
    `surface_parts` or `surface_parts.<slider>.<part>` where the surfaces' parts are not one
    `SurfaceParts` (or `None`) per slider or are out of range (`check_surface_parts`)."""
    _check_parts(bearing)
    for name, heating in zip(bearing.slider_names, bearing.surface_heatings()):
        if heating is None:
            continue
        check_heating(heating, f"{name}_heating")
        pressure = getattr(bearing, f"{name}_pressure", None)
        if pressure is None:
            raise ValueError(f"{name}_pressure: a surface with {name}_heating needs its contact pressure "
                             "[Pa] under the static load (the heat flux is mu p v).")
        require_positive(pressure, f"{name}_pressure", " [Pa] (contact pressure on the surface)")


def _check_parts(bearing: SeriesPendulum) -> None:
    """The surfaces' parts beyond Eq. 1 and heating (`check_surface_heating`)."""
    parts = getattr(bearing, "surface_parts", None)
    if parts is None:
        return
    if not isinstance(parts, tuple | list) or len(parts) != bearing.slider_count:
        raise ValueError(f"surface_parts: one SurfaceParts (or None) per slider ({', '.join(bearing.slider_names)}), "
                         f"got {parts!r}.")
    for name, part in zip(bearing.slider_names, parts):
        if part is None:
            continue
        if not isinstance(part, SurfaceParts):
            raise ValueError(f"surface_parts.{name}: expected a SurfaceParts or None, got {type(part).__name__}.")
        check_surface_parts(part, f"surface_parts.{name}", getattr(bearing, f"{name}_pressure", None))
