"""The rigid mass and the six-storey building of the paper under two ground components.

Both sit on one group of sliding bearings with Park's biaxial Z (Eqs. 8-9); x and y are
uncoupled except through the bearings. Reference: Constantinou, Mokha & Reinhorn (1990),
Figs. 7-11, Table 2 (MODEL.md Sections 4 and 8).
"""

import jax.numpy as jnp
import numpy as np

from ..bearing import SlidingBearing
from ..excitation import Signal
from ..tables import BuildingData
from ._bidirectional import BidirectionalStructure
from ._bidirectional_build import bidirectional_structure
from ._models import rigid_mass, six_storey_building

BIDIRECTIONAL_TIME_STEP = 0.0025
"""Default step [s] of the bidirectional structures: peak resultant base displacement and base
shear within 0.5 % of adaptive Tsit5 (rtol 1e-9) for the rigid mass and the building under the
PEER RSN6 pair and the SCT 1985 pair (tests/test_bidirectional_records.py); at 10 ms the RSN6
building is 1.2 % off."""


def _zero_signal(like: Signal) -> Signal:
    return Signal(times=like.times, values=jnp.zeros_like(like.values), uniform=like.uniform)


def _block(a, b):
    n = a.shape[0]
    out = jnp.zeros((2 * n, 2 * n))
    return out.at[:n, :n].set(a).at[n:, n:].set(b)


def _two_directions(x, y, bearing, ground_x, ground_y, time_step,
                    contact_pressure=None, **law) -> BidirectionalStructure:
    n = x.mass.shape[0]
    influence = np.zeros((2 * n, 2))
    influence[:n, 0] = 1.0
    influence[n:, 1] = 1.0
    bearing_map = np.zeros((1, 2, 2 * n))
    bearing_map[0, 0, 0] = 1.0
    bearing_map[0, 1, n] = 1.0
    return bidirectional_structure(
        mass=jnp.concatenate([x.mass, y.mass]),
        stiffness=_block(x.stiffness, y.stiffness),
        damping=_block(x.damping, y.damping),
        influence=influence,
        bearing_map=bearing_map,
        bearing=bearing,
        bearing_load=x.bearing_load[None],
        ground_x=ground_x,
        ground_y=_zero_signal(ground_x) if ground_y is None else ground_y,
        time_step=time_step,
        contact_pressure=contact_pressure,
        **law,
    )


def bidirectional_rigid_mass(
    *,
    weight,
    bearing: SlidingBearing,
    ground_x: Signal,
    ground_y: Signal | None = None,
    time_step: float,
    isolation_period=None,
    damping_ratio=0.0,
    contact_pressure=None,
    friction_model: str = "hysteretic",
    surface=None,
) -> BidirectionalStructure:
    """A rigid mass W/g on sliding bearings under (a_x, a_y) (TASS-type system with springs):

        m u'' + c u' + k u + mu(|u'|) W Z = -m a_g,   u, Z, a_g in the plane,

    k = m (2 pi / T)^2 in both directions from `isolation_period` T [s] (`None`: flat sliders
    alone), c = 2 zeta m (2 pi / T) from `damping_ratio` zeta [-].

    **Arguments:** `weight` W [N]; `bearing`: `SlidingBearing` (x = parallel to the lay when
    it has `friction_perpendicular`); `ground_x`, `ground_y`: `Signal`s [m/s^2] (y `None` = no
    y motion); `time_step` [s] of `RiccatiNewmark`; `contact_pressure` [Pa] of the bearings
    (for a bearing with heating); `friction_model` "hysteretic", "coulomb" or "none";
    `surface`: a friction pendulum's `ConcaveSurface` (its period is `isolation_period`; its
    restrainer and large-displacement force act in the bearings' solve).

    **Returns:** a `BidirectionalStructure` with q = (u_x, u_y).
    """
    one = rigid_mass(
        weight=weight,
        bearing=None,
        ground_acceleration=ground_x,
        time_step=time_step,
        isolation_period=isolation_period,
        damping_ratio=damping_ratio,
        friction_model="none",
    )
    return _two_directions(one, one, bearing, ground_x, ground_y, time_step, contact_pressure,
                           friction_model=friction_model, surface=surface)


def bidirectional_building(
    *,
    bearing: SlidingBearing,
    ground_x: Signal,
    ground_y: Signal | None = None,
    time_step: float,
    isolation_period,
    isolation_damping=0.05,
    building: BuildingData | None = None,
    building_y: BuildingData | None = None,
    isolation_period_y=None,
    contact_pressure=None,
    friction_model: str = "hysteretic",
    surface=None,
) -> BidirectionalStructure:
    """The six-storey frame of Table 2 in x and y on sliding bearings with springs (Fig. 11).

    Each direction is the 7-degree-of-freedom model of `six_storey_building` (base + six
    floors, 2 % modal damping, springs of period T_b and damping zeta_b in the rigid-body
    mode); y uses the same modal data unless `building_y` (and `isolation_period_y`) are given.
    The bearings carry the total weight W and couple the two bases through Park's Z;
    `contact_pressure` [Pa] of the bearings is needed for a bearing with heating;
    `friction_model` and `surface` as in `bidirectional_rigid_mass`.

    **Returns:** a `BidirectionalStructure` with q = (x: base, floors 1-6; y: base, floors 1-6).
    """
    x = six_storey_building(
        bearing=None,
        ground_acceleration=ground_x,
        time_step=time_step,
        isolation_period=isolation_period,
        isolation_damping=isolation_damping,
        friction_model="none",
        building=building,
    )
    y = x
    if building_y is not None or isolation_period_y is not None:
        y = six_storey_building(
            bearing=None,
            ground_acceleration=ground_x,
            time_step=time_step,
            isolation_period=isolation_period if isolation_period_y is None else isolation_period_y,
            isolation_damping=isolation_damping,
            friction_model="none",
            building=building if building_y is None else building_y,
        )
        if not np.isclose(float(jnp.sum(y.mass)), float(jnp.sum(x.mass))):
            raise ValueError(
                "building_y: its total weight differs from the x model's; one structure has one weight."
            )
    return _two_directions(x, y, bearing, ground_x, ground_y, time_step, contact_pressure,
                           friction_model=friction_model, surface=surface)
