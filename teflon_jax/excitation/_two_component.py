"""Two horizontal components of a stochastic ground motion, along principal axes.

Penzien & Watabe (1975, "Characteristics of 3-dimensional earthquake ground motions",
Earthquake Engineering and Structural Dynamics 3(4), 365-373) found that recorded
components are, over their strong phase, nearly uncorrelated along a set of principal
axes: a major horizontal axis, a minor horizontal axis at right angles to it (and a
vertical one, not modelled here), the major axis pointing roughly towards the epicentre.
Following them, the two horizontal components are drawn here as two independent
realisations `a_1`, `a_2` of the same `StochasticGroundMotion` (same spectrum, same
envelope), the minor one scaled by `minor_ratio` gamma, and turned by `principal_angle`
theta (from x towards y) into the structure's axes:

    a_x(t) = a_1(t) cos(theta) - gamma a_2(t) sin(theta),
    a_y(t) = a_1(t) sin(theta) + gamma a_2(t) cos(theta).

Their covariance at time t is therefore

    E[a a^T] = sigma^2 e(t)^2 R(theta) diag(1, gamma^2) R(theta)^T,

with `sigma^2 = stationary_variance(model)`, `e(t)` the envelope and `R` the rotation;
each component's spectrum is the model's scaled by `cos^2 + gamma^2 sin^2` (x) or
`sin^2 + gamma^2 cos^2` (y). With gamma = 1 the two components are independent and
alike whatever theta (the common "two independent components" assumption); with
gamma = 0 the motion is one component along theta. Gamma is the user's choice (the ratio
of the minor to the major standard deviation); it is not taken from the reference.

The major component of a two-component sample drawn with `key` is exactly
`sample(model, key, n)`; the minor one is drawn from `fold_in(key, 1)`.
"""

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Float, PRNGKeyArray

from ..validation import concrete
from ._stochastic import StochasticGroundMotion, sample


def _float(x) -> Array:
    return jnp.asarray(x, dtype=jnp.result_type(float))


class TwoComponentGroundMotion(eqx.Module):
    """Two horizontal components along principal axes (module docstring).

    **Fields:**

    - `model`: the `StochasticGroundMotion` of the major component (and, scaled by
      `minor_ratio`, of the minor one).
    - `principal_angle` theta: angle of the major axis from x towards y [rad].
    - `minor_ratio` gamma: standard deviation of the minor component over the major's
      [-], in [0, 1]; 1 gives two independent, equally strong components.
    """

    model: StochasticGroundMotion
    principal_angle: Float[Array, ""] = eqx.field(converter=_float, default=0.0)
    minor_ratio: Float[Array, ""] = eqx.field(converter=_float, default=1.0)

    def __check_init__(self):
        if not isinstance(self.model, StochasticGroundMotion):
            raise ValueError(
                f"TwoComponentGroundMotion: `model` must be a StochasticGroundMotion, got "
                f"{type(self.model).__name__}."
            )
        ratio = concrete(self.minor_ratio)
        if ratio is not None and not bool(((ratio >= 0) & (ratio <= 1)).all()):
            raise ValueError(
                f"TwoComponentGroundMotion: `minor_ratio` must lie in [0, 1] (minor over major "
                f"standard deviation), got {ratio.tolist()}."
            )
        angle = concrete(self.principal_angle)
        if angle is not None and not bool(jnp.all(jnp.isfinite(angle))):
            raise ValueError(
                f"TwoComponentGroundMotion: `principal_angle` must be finite [rad], got {angle.tolist()}."
            )


def principal_covariance(motion: TwoComponentGroundMotion) -> Float[Array, "2 2"]:
    """Covariance of (a_x, a_y) per unit variance of the major component [-]:
    `R(theta) diag(1, gamma^2) R(theta)^T`."""
    c, s = jnp.cos(motion.principal_angle), jnp.sin(motion.principal_angle)
    rotation = jnp.stack([jnp.stack([c, -s]), jnp.stack([s, c])])
    return rotation @ jnp.diag(jnp.stack([jnp.ones_like(c), motion.minor_ratio**2])) @ rotation.T


def sample_two_components(
    motion: TwoComponentGroundMotion,
    key: PRNGKeyArray,
    n: int,
    *,
    stationary: bool = False,
    random_amplitudes: bool = True,
) -> Float[Array, "n 2 nt"]:
    """Draw `n` two-component ground-acceleration records (module docstring).

    **Arguments:** as `sample`: `motion`, a JAX PRNG `key`, the number of records `n`,
    `stationary` (no envelope), `random_amplitudes`.

    **Returns:** accelerations [m/s^2], shape `(n, 2, nt)`: `[:, 0]` along x, `[:, 1]`
    along y, sampled at `sample_times(motion.model)`.
    """
    options = {"stationary": stationary, "random_amplitudes": random_amplitudes}
    major = sample(motion.model, key, n, **options)
    minor = motion.minor_ratio * sample(motion.model, jax.random.fold_in(key, 1), n, **options)
    c, s = jnp.cos(motion.principal_angle), jnp.sin(motion.principal_angle)
    return jnp.stack([c * major - s * minor, s * major + c * minor], axis=1)

