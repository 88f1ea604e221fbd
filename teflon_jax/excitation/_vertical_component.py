"""A horizontal stochastic ground motion with its vertical component.

The vertical component is drawn as an independent realisation of the horizontal
`StochasticGroundMotion` with two changes:

- its nominal peak is `vertical_ratio` times the horizontal one. Newmark, Blume & Kapur
  (1973, "Seismic design spectra for nuclear power plants", J. Power Div. ASCE 99(2),
  287-303) took the vertical design spectrum as 2/3 of the horizontal one (the "2/3 rule",
  `NEWMARK_VERTICAL_RATIO`); Bozorgnia & Campbell (2004, "The vertical-to-horizontal
  response spectral ratio and tentative procedures for developing simplified V/H and
  vertical design spectra", J. Earthquake Eng. 8(2), 175-207) found V/H ratios of peak
  ground acceleration from about 0.5 far from the source to above 1 close to it;
- its Kanai-Tajimi frequency (and the Clough-Penzien high-pass frequency with it) is
  `frequency_ratio` times the horizontal one: vertical motions carry their energy at
  shorter periods, where Bozorgnia & Campbell's V/H spectral ratios peak (0.05-0.1 s, against
  horizontal spectra peaking at 0.2-0.5 s). The default 2 (15.6 -> 31.2 rad/s, a
  predominant period of 0.2 s) is a modelling choice within that range, not a value from
  the references.

The horizontal and vertical components are taken as uncorrelated, as Penzien & Watabe (1975,
Earthquake Eng. Struct. Dyn. 3(4), 365-373) found for principal axes. The horizontal
component of a sample drawn with `key` is exactly `sample(model, key, n)` (or, for two
horizontal components, `sample_two_components(model, key, n)`, whose minor component comes
from `fold_in(key, 1)`); the vertical one is drawn from `fold_in(key, 2)`, so adding it or a
second horizontal component leaves the others as they were.
"""

import math

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Float, PRNGKeyArray

from ..validation import concrete
from ._stochastic import StochasticGroundMotion, sample
from ._two_component import TwoComponentGroundMotion, sample_two_components

NEWMARK_VERTICAL_RATIO = 2.0 / 3.0
"""Vertical over horizontal peak ground acceleration of Newmark, Blume & Kapur (1973) [-]."""

VERTICAL_FREQUENCY_RATIO = 2.0
"""Default vertical over horizontal Kanai-Tajimi frequency [-] (module docstring)."""


def _float(x) -> Array:
    return jnp.asarray(x, dtype=jnp.result_type(float))


class VerticalGroundMotion(eqx.Module):
    """A horizontal motion `model` with a vertical component (module docstring).

    **Fields:** `model`: the horizontal `StochasticGroundMotion`, or a
    `TwoComponentGroundMotion` (two horizontal components; the vertical one then follows its
    major component's model); `vertical_ratio` [-] (>= 0): the vertical component's nominal
    peak over the horizontal one's (0: a vertical record of zeros, N = W throughout); `frequency_ratio` [-] (> 0): its site (and high-pass)
    frequency over the horizontal one's.
    """

    model: StochasticGroundMotion | TwoComponentGroundMotion
    vertical_ratio: Float[Array, ""] = eqx.field(converter=_float, default=NEWMARK_VERTICAL_RATIO)
    frequency_ratio: Float[Array, ""] = eqx.field(converter=_float, default=VERTICAL_FREQUENCY_RATIO)

    def __check_init__(self):
        if not isinstance(self.model, (StochasticGroundMotion, TwoComponentGroundMotion)):
            raise ValueError(f"VerticalGroundMotion: `model` must be a StochasticGroundMotion or a "
                             f"TwoComponentGroundMotion, got {type(self.model).__name__}.")
        for name, lowest in (("vertical_ratio", 0.0), ("frequency_ratio", None)):
            value = concrete(getattr(self, name))
            above = value > 0 if lowest is None else value >= lowest
            if value is not None and not bool((above & jnp.isfinite(value)).all()):
                raise ValueError(f"VerticalGroundMotion: `{name}` must be {'> 0' if lowest is None else '>= 0'} "
                                 f"and finite, got {value.tolist()}.")
        base = self.horizontal_model
        frequency = concrete(base.site_frequency * self.frequency_ratio)
        if frequency is not None and bool(jnp.any(2 * frequency > math.pi / base.time_step)):
            raise ValueError(f"VerticalGroundMotion: the vertical site frequency {frequency.tolist()} rad/s "
                             f"needs a time_step below pi / (2 omega) (the record's is "
                             f"{base.time_step} s); lower `frequency_ratio` or the step.")

    @property
    def horizontal_components(self) -> int:
        """1, or 2 for a `TwoComponentGroundMotion` `model`."""
        return 2 if isinstance(self.model, TwoComponentGroundMotion) else 1

    @property
    def horizontal_model(self) -> StochasticGroundMotion:
        """The `StochasticGroundMotion` of the (major) horizontal component."""
        return self.model.model if isinstance(self.model, TwoComponentGroundMotion) else self.model

    @property
    def vertical_model(self) -> StochasticGroundMotion:
        """The `StochasticGroundMotion` of the vertical component."""
        m = self.horizontal_model
        return eqx.tree_at(
            lambda x: (x.peak_ground_acceleration, x.site_frequency, x.high_pass_frequency), m,
            (m.peak_ground_acceleration * self.vertical_ratio, m.site_frequency * self.frequency_ratio,
             m.high_pass_frequency * self.frequency_ratio))


def sample_with_vertical(motion: VerticalGroundMotion, key: PRNGKeyArray, n: int) -> Float[Array, "n c nt"]:
    """Draw `n` records [m/s^2] of shape (n, 2, nt): `[:, 0]` horizontal (`sample(model, key,
    n)`), `[:, 1]` vertical, up positive (from `fold_in(key, 2)`); with two horizontal
    components (n, 3, nt): `[:, :2]` x and y (`sample_two_components(model, key, n)`), `[:, 2]`
    vertical."""
    vertical = sample(motion.vertical_model, jax.random.fold_in(key, 2), n)
    if isinstance(motion.model, TwoComponentGroundMotion):
        return jnp.concatenate([sample_two_components(motion.model, key, n), vertical[:, None]], axis=1)
    horizontal = sample(motion.model, key, n)
    return jnp.stack([horizontal, vertical], axis=1)
