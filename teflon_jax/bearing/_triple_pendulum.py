"""The triple friction pendulum isolator: four concave sliding surfaces, modelled as three
sliders in series.

Surfaces 1 (bottom) and 4 (top) are the outer concave plates, 2 and 3 the inner ones, with
effective radii R_i - h_i and effective displacement capacities d_i (R_i - h_i) / R_i. Under a
slowly growing displacement the bearing slides on 2 and 3 (regime I), then 1 and 3 (II), 1
and 4 (III), 2 and 4 once surface 1 meets its restrainer (IV), 2 and 3 once surface 4 meets
its own (V), and stiffens when the inner slider meets its rings. The series model reproduces
that force-displacement relation with three sliders that carry the same force: the inner
surfaces together (radius 2 a, friction mu_2), and the two outer surfaces with their radius
less the inner one (b - a, c - a), each with its friction, its sliding velocity scaled to the
surface's and its capacity shortened in the same ratio (Fenz & Constantinou 2008, Earthquake
Spectra 24(4), 1011-1028; the regimes and their closed forms: Fenz & Constantinou 2008,
Earthquake Engng Struct. Dyn. 37, 163-183). Each slider follows Eq. 1 (at its surface's
velocity) and Bouc-Wen's Z, like the flat bearing of the 1990 paper.
"""

import math
from collections.abc import Mapping
from typing import ClassVar

import jax.numpy as jnp
import numpy as np
from jaxtyping import ArrayLike

from ..catalogue import TRIPLE_FP
from ..validation import require_positive
from ._effects import FrictionalHeating
from ._friction import FrictionParameters
from ._hysteresis import BoucWen
from ._series_pendulum import (
    SeriesPendulum,
    check_surface_heating,
    stack_frictions,
)
from ._surface import check_friction

STOP_STIFFNESS_RATIO = 1000.0
"""Stiffness of a restrainer ring as a multiple of its slider's pendulum stiffness W / R."""


class TriplePendulum(SeriesPendulum):
    """A triple friction pendulum bearing (module docstring), with the inner surfaces 2 and 3
    alike (the usual design, which the series model needs).

    **Fields** (effective radii R - h [m]; effective capacities d (R - h) / R [m]):
    `inner_radius` a (surfaces 2 and 3), `bottom_radius` b (1), `top_radius` c (4);
    `inner_capacity`, `bottom_capacity`, `top_capacity`; `inner_friction`,
    `bottom_friction`, `top_friction`: Eq. 1 constants of each surface (`FrictionParameters`;
    delta_f = 0 for Coulomb friction); `hysteresis`: `BoucWen` of every slider;
    `inner_heating` (each of surfaces 2 and 3), `bottom_heating`, `top_heating`:
    `FrictionalHeating` or `None`, with `inner_pressure`, `bottom_pressure`, `top_pressure`
    [Pa], the contact pressure of a heated surface under the static load
    (`SeriesPendulum.heat_fluxes`); `surface_parts`: (inner, bottom, top) `SurfaceParts` or
    `None` each (breakaway, anisotropy, wear, asymmetry, pressure dependence), or `None`.
    """

    isolator: ClassVar[str] = TRIPLE_FP.name
    slider_names: ClassVar[tuple[str, ...]] = ("inner", "bottom", "top")
    description: ClassVar[str] = TRIPLE_FP.description
    design_variables: ClassVar[tuple[str, ...]] = ("outer_radius_scale", "inner_f_max", "outer_f_max",
                                                   "capacity_scale")
    """A smooth change of the isolator (Fenz & Constantinou 2008): `outer_radius_scale` s [-]
    (the outer surfaces' effective radii b, c -> s b, s c: the stiffness of regimes II-IV,
    1 / (a + b), 1 / (b + c), 1 / (a + c), falls as s grows); `inner_f_max` [-] (Eq. 1 of the
    inner surfaces scaled so that their f_max is this value, delta_f in proportion);
    `outer_f_max` [-] (Eq. 1 of the bottom surface scaled to this f_max, the top's by the same
    factor: their ratio, which orders regimes II and III, kept); `capacity_scale` [-] (the
    three effective displacement capacities times it). The series model needs a < s min(b, c)
    and inner f_max <= bottom f_max <= top f_max (`check_triple_pendulum`)."""
    inner_radius: ArrayLike
    bottom_radius: ArrayLike
    top_radius: ArrayLike
    inner_capacity: ArrayLike
    bottom_capacity: ArrayLike
    top_capacity: ArrayLike
    inner_friction: FrictionParameters
    bottom_friction: FrictionParameters
    top_friction: FrictionParameters
    hysteresis: BoucWen
    inner_heating: FrictionalHeating | None = None
    bottom_heating: FrictionalHeating | None = None
    top_heating: FrictionalHeating | None = None
    inner_pressure: ArrayLike | None = None
    bottom_pressure: ArrayLike | None = None
    top_pressure: ArrayLike | None = None
    surface_parts: tuple | None = None

    def series_radii(self):
        """Radii [m] of the three sliders in series: (2 a, b - a, c - a)."""
        a = self.inner_radius
        return jnp.stack([2 * a, self.bottom_radius - a, self.top_radius - a])

    def series_capacities(self):
        """Travel [m] of each slider before its restrainer: the inner pair until the first of
        surfaces 2 and 3 meets its ring, 2 (d_2 + a min(d_1 / b, d_4 / c)) (the inner sliders
        also carry the share a / R of the outer travel in the series model), and each outer
        surface's capacity times (R - a) / R."""
        a, b, c = self.inner_radius, self.bottom_radius, self.top_radius
        inner = 2 * (self.inner_capacity + a * jnp.minimum(self.bottom_capacity / b,
                                                           self.top_capacity / c))
        return jnp.stack([inner, self.bottom_capacity * (1 - a / b),
                          self.top_capacity * (1 - a / c)])

    def velocity_factors(self):
        """Sliding velocity of each surface over its slider's velocity: (1/2, b / (b - a),
        c / (c - a)) (each inner surface takes half of the pair's)."""
        a, b, c = self.inner_radius, self.bottom_radius, self.top_radius
        return jnp.stack([0.5 * jnp.ones_like(a), b / (b - a), c / (c - a)])

    def frictions(self) -> FrictionParameters:
        """Eq. 1 constants of the three sliders, stacked (inner, bottom, top)."""
        return stack_frictions((self.inner_friction, self.bottom_friction, self.top_friction))

    def reference_radius(self):
        """b + c [m]: the effective radius of the outer surfaces sliding together."""
        return self.bottom_radius + self.top_radius

    def check(self) -> None:
        """`check_triple_pendulum`."""
        check_triple_pendulum(self)

    def _designed(self, design: Mapping) -> "TriplePendulum":
        s = design.get("outer_radius_scale", 1.0)
        inner = design.get("inner_f_max", self.inner_friction.f_max) / self.inner_friction.f_max
        outer = design.get("outer_f_max", self.bottom_friction.f_max) / self.bottom_friction.f_max
        k = design.get("capacity_scale", 1.0)
        return self.with_fields(
            bottom_radius=s * self.bottom_radius, top_radius=s * self.top_radius,
            inner_capacity=k * self.inner_capacity, bottom_capacity=k * self.bottom_capacity,
            top_capacity=k * self.top_capacity, inner_friction=self.inner_friction.scaled(inner),
            bottom_friction=self.bottom_friction.scaled(outer), top_friction=self.top_friction.scaled(outer))

    def design_ranges(self) -> dict:
        """The outer radii above the inner one, friction within (0, 1] in the series model's
        order, positive capacities."""
        a, b, c = (float(np.asarray(x)) for x in (self.inner_radius, self.bottom_radius, self.top_radius))
        m2, m1, m4 = (float(np.asarray(f.f_max)) for f in (self.inner_friction, self.bottom_friction,
                                                           self.top_friction))
        return {"outer_radius_scale": (a / min(b, c) * (1 + 1e-9), math.inf), "inner_f_max": (1e-6, m1),
                "outer_f_max": (m2, m1 / m4), "capacity_scale": (1e-6, math.inf)}

    def _rule(self) -> str:
        return "the outer radii above the inner one; inner f_max <= bottom f_max <= top f_max <= 1; positive capacities"

    def _box_ranges(self, box: Mapping) -> dict:
        """The inner f_max below the box's least outer f_max, the outer above its largest inner
        one, the top's f_max (scaled alike) at most 1."""
        ranges = self.design_ranges()
        if "inner_f_max" in box and "outer_f_max" in box:
            ranges["inner_f_max"] = (ranges["inner_f_max"][0], box["outer_f_max"][0])
        if "outer_f_max" in box:
            low, high = ranges["outer_f_max"]
            ranges["outer_f_max"] = (max(box.get("inner_f_max", (0.0, 0.0))[1], low), high)
        return ranges


def check_triple_pendulum(bearing: TriplePendulum) -> None:
    """`ValueError` naming the constant the series model cannot take: radii and capacities
    must be positive, the inner radius below the outer ones, and the friction of the inner
    surfaces at most that of the bottom, which is at most the top's (the order of regimes
    I-V; swap top and bottom if yours is the other way round), each surface's friction what
    Eq. 1 takes (`check_friction`)."""
    for name in ("inner_radius", "bottom_radius", "top_radius", "inner_capacity",
                 "bottom_capacity", "top_capacity"):
        require_positive(getattr(bearing, name), name, " [m]")
    for name in ("inner_friction", "bottom_friction", "top_friction"):
        check_friction(getattr(bearing, name), name)
    a = float(np.asarray(bearing.inner_radius))
    for name in ("bottom_radius", "top_radius"):
        if not float(np.asarray(getattr(bearing, name))) > a:
            raise ValueError(f"{name}: must be larger than inner_radius ({a:g} m), got "
                             f"{float(np.asarray(getattr(bearing, name))):g} m; the inner "
                             "surfaces of a triple pendulum are the tighter ones.")
    mu = {name: float(np.asarray(getattr(bearing, name).f_max))
          for name in ("inner_friction", "bottom_friction", "top_friction")}
    if not mu["inner_friction"] <= mu["bottom_friction"] <= mu["top_friction"]:
        raise ValueError(
            f"friction: the series model needs inner <= bottom <= top (f_max {mu['inner_friction']:g}, "
            f"{mu['bottom_friction']:g}, {mu['top_friction']:g}); swap bottom and top if the "
            "bottom surface is the slipperier outer one.")
    check_surface_heating(bearing)


def triple_pendulum_backbone(bearing: TriplePendulum):
    """The force-displacement relation of regimes I-V under a slowly growing displacement,
    written from the sliding of each surface (Coulomb friction mu_i = f_max_i, rigid below
    it): a list of (start displacement [m], force / W at the start [-], slope d(F/W)/du
    [1/m]) per regime, and the displacement where regime V ends (the inner slider at its
    ring).

        I    (2, 3)  from 0,            F/W = mu_2 + u / (2 a)
        II   (1, 3)  from 2 a (mu_1 - mu_2),                 slope 1 / (a + b)
        III  (1, 4)  when F/W = mu_4,                        slope 1 / (b + c)
        IV   (2, 4)  when F/W = mu_1 + d_1 / b (ring of 1),  slope 1 / (a + c)
        V    (2, 3)  when F/W = mu_4 + d_4 / c (ring of 4),  slope 1 / (2 a)
        end          when F/W = mu_2 + d_2 / a + min(d_1 / b, d_4 / c)

    (for mu_1 + d_1 / b <= mu_4 + d_4 / c, the usual design)."""
    a, b, c = (float(np.asarray(x)) for x in (bearing.inner_radius, bearing.bottom_radius,
                                              bearing.top_radius))
    d1, d2, d4 = (float(np.asarray(x)) for x in (bearing.bottom_capacity, bearing.inner_capacity,
                                                 bearing.top_capacity))
    m2, m1, m4 = (float(np.asarray(p.f_max)) for p in (bearing.inner_friction,
                                                       bearing.bottom_friction,
                                                       bearing.top_friction))
    forces = [m2, m1, m4, m1 + d1 / b, m4 + d4 / c, m2 + d2 / a + min(d1 / b, d4 / c)]
    if not all(f0 <= f1 for f0, f1 in zip(forces[:-1], forces[1:])):
        raise ValueError(
            "capacities: the closed forms of regimes I-V need mu_2 <= mu_1 <= mu_4 <= mu_1 + d_1/b "
            f"<= mu_4 + d_4/c <= the inner ring's force; the transitions are at F/W = "
            f"{', '.join(f'{f:.4g}' for f in forces)} (the series model itself runs other orders).")
    slopes = [1 / (2 * a), 1 / (a + b), 1 / (b + c), 1 / (a + c), 1 / (2 * a)]
    starts = [0.0]
    for force0, force1, slope in zip(forces[:-1], forces[1:], slopes):
        starts.append(starts[-1] + (force1 - force0) / slope)
    regimes = list(zip(starts[:-1], forces[:-1], slopes))
    return regimes, starts[-1]
