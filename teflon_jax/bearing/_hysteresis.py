"""Hysteretic variable Z of the friction force: Bouc-Wen (uniaxial) and Park et al. (biaxial).

The friction force is F = mu_s W Z with |Z| < 1 while sticking and |Z| -> 1 while sliding.
References: Constantinou, Mokha & Reinhorn (1990), Eqs. 3-4 and 8-9; Bouc (1971); Wen (1976);
Park, Wen & Ang (1986).
"""

import math

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import ArrayLike

from ._elementary import vector_arctan


class BoucWen(eqx.Module):
    """Parameters of the Bouc-Wen equation in the viscoplastic form of Eq. 3.

    Y dZ/dt = A U' - gamma |U'| Z |Z|^(eta-1) - beta U' |Z|^eta

    - `yield_disp` Y [m]: displacement of the elastic (sticking) branch; the paper uses
      0.005 in (1.27e-4 m).
    - `A`, `beta`, `gamma`, `eta` [-]: shape constants; paper values 1, 0.1, 0.9, 2.
      With A / (beta + gamma) = 1 the sliding value of |Z| is 1.
    """

    yield_disp: ArrayLike
    A: ArrayLike = 1.0
    beta: ArrayLike = 0.1
    gamma: ArrayLike = 0.9
    eta: ArrayLike = 2.0


def _abs_power(x, p):
    """|x|^p with finite derivatives in both x and p, also at x = 0 (p > 0)."""
    ax = jnp.abs(x)
    positive = ax > 0
    return jnp.where(positive, jnp.exp(p * jnp.log(jnp.where(positive, ax, 1.0))), 0.0)


def bouc_wen_rate(h: BoucWen, z, velocity):
    """dZ/dt [1/s] of Eq. 3 for sliding `velocity` [m/s], for any A, beta, gamma, eta:
    Y dZ/dt = A U' - gamma |U'| Z |Z|^(eta-1) - beta U' |Z|^eta."""
    z_eta_1 = _abs_power(z, h.eta - 1.0)
    return (
        h.A * velocity
        - h.gamma * jnp.abs(velocity) * z * z_eta_1
        - h.beta * velocity * z_eta_1 * jnp.abs(z)
    ) / h.yield_disp


def _norm(z):
    """Euclidean norm of `z` (..., 2) with a finite (zero) derivative at z = 0 (double-where)."""
    square = jnp.sum(z**2, axis=-1)
    nonzero = square > 0
    return jnp.where(nonzero, jnp.sqrt(jnp.where(nonzero, square, 1.0)), 0.0)


def park_rate(h: BoucWen, z, velocity):
    """d(Zx, Zy)/dt [1/s] of the biaxial model of Park, Wen & Ang (1986), Eqs. 8-9, for any eta.

        Y dZx/dt = A Ux' - Zx |Z|^(eta-2) [gamma (|Ux' Zx| + |Uy' Zy|) + beta (Ux' Zx + Uy' Zy)]
        Y dZy/dt = A Uy' - Zy |Z|^(eta-2) [gamma (|Ux' Zx| + |Uy' Zy|) + beta (Ux' Zx + Uy' Zy)]

    with |Z| = sqrt(Zx^2 + Zy^2); eta = 2 is the paper's form (the factor is 1), and with
    Zy = Uy' = 0 it reduces to Eq. 3 for any eta. `z` and `velocity` have shape (..., 2).
    While sliding with A / (beta + gamma) = 1 the solution is (Zx, Zy) = (cos theta, sin theta),
    theta the direction of the velocity.
    """
    zx, zy = z[..., 0], z[..., 1]
    vx, vy = velocity[..., 0], velocity[..., 1]
    common = h.gamma * (jnp.abs(vx * zx) + jnp.abs(vy * zy)) + h.beta * (vx * zx + vy * zy)
    common = common * _abs_power(_norm(z), h.eta - 2.0)
    dzx = (h.A * vx - common * zx) / h.yield_disp
    dzy = (h.A * vy - common * zy) / h.yield_disp
    return jnp.stack([dzx, dzy], axis=-1)


def _tan_pair(angle):
    """(s, c) with s / c = tan(angle) for `angle` in [0, pi/2), as plain multiply-adds and one
    division, which vectorise over a batch where float64 `jnp.tan` does not: Cody and Waite's
    rational form tan a = a + a^3 P(a^2) / Q(a^2) on [0, pi/4] (the coefficients of Cephes'
    tan.c, Moshier 1989; relative error ~1e-16) and, above pi/4, (1, tan(pi/2 - a))."""
    upper = angle > 0.25 * math.pi
    a = jnp.where(upper, 0.5 * math.pi - angle, angle)
    a2 = a * a
    numerator = a2 * (_TAN_P[0] * a2 + _TAN_P[1]) * a2 + _TAN_P[2] * a2
    denominator = (((a2 + _TAN_Q[0]) * a2 + _TAN_Q[1]) * a2 + _TAN_Q[2]) * a2 + _TAN_Q[3]
    t = a + a * (numerator / denominator)
    return jnp.where(upper, 1.0, t), jnp.where(upper, t, 1.0)


_TAN_P = (-1.30936939181383777646e4, 1.15351664838587416140e6, -1.79565251976484877988e7)
_TAN_Q = (1.36812963470692954678e4, -1.32089234440210967447e6, 2.50083801823357915839e7,
          -5.38695755929454629881e7)


def bouc_wen_reversal_length(h: BoucWen, z0):
    """|du| / Y [-] after which Z reaches 0 when the motion runs against Z (eta = 2):
    atan(|z0| / w_-) / k_-, with w_- = sqrt(A / (gamma - beta)), k_- = sqrt(A (gamma - beta)).
    Depends on z0 only, so a Newton loop over du computes it once (see `bouc_wen_exact_update`)."""
    c_minus = h.gamma - h.beta
    return vector_arctan(jnp.abs(z0) / jnp.sqrt(h.A / c_minus)) / jnp.sqrt(h.A * c_minus)


def _tan_as_ratio(angle):
    """(tan(angle), 1): a pair (s, c) with s / c = tan(angle), from `jnp.tan`."""
    return jnp.tan(angle), jnp.ones_like(angle)


_TANGENTS = {"library": _tan_as_ratio, "rational": _tan_pair}


def bouc_wen_exact_update(
    h: BoucWen, z0, displacement_increment, reversal_length=None, *, tangent: str = "library"
):
    """Z after a monotone displacement increment, in closed form (eta = 2, gamma > beta).

    Bouc-Wen is rate independent: along a monotone path Z depends only on the displacement.
    With s = sign(du), w = s Z and x = |du| / Y, Eq. 3 becomes a Riccati equation
        dw/dx = A - (gamma + beta) w^2   for w >= 0   (tanh branch, towards sqrt(A/(beta+gamma))),
        dw/dx = A + (gamma - beta) w^2   for w < 0    (tan branch, up to w = 0),
    solved exactly here, crossing w = 0 inside the increment when it happens.
    Requires eta = 2 and gamma > beta (paper: 0.9 > 0.1); the caller checks this.

    **Arguments:** `h` Bouc-Wen constants, `z0` [-] at the start, `displacement_increment` du [m];
    `reversal_length`: `bouc_wen_reversal_length(h, z0)` if already known (computed otherwise);
    `tangent` (static): how tan is evaluated, "library" (`jnp.tan`: cheaper in scalar loops
    under automatic differentiation, e.g. fits) or "rational" (`_tan_pair`, multiply-adds and a
    division: cheaper in wide batches, e.g. Monte Carlo, as float64 `jnp.tan` is not vectorised
    on CPU). Both agree to round-off.

    **Returns:** Z [-] at the end of the increment.
    """
    du = displacement_increment
    sign = jnp.where(du >= 0, 1.0, -1.0)
    w0 = sign * z0
    x = jnp.abs(du) / h.yield_disp
    c_plus = h.gamma + h.beta
    c_minus = h.gamma - h.beta
    w_plus, k_plus = jnp.sqrt(h.A / c_plus), jnp.sqrt(h.A * c_plus)
    w_minus, k_minus = jnp.sqrt(h.A / c_minus), jnp.sqrt(h.A * c_minus)
    x_to_zero = bouc_wen_reversal_length(h, z0) if reversal_length is None else reversal_length

    # Branch w0 < 0: w(x) = w_- tan(k_- x + atan(w0 / w_-)) until w = 0 (x = x_to_zero), by the
    # tangent addition formula; the angle k_- x stays in [0, pi/2).
    negative = w0 < 0
    w0_neg = jnp.where(negative, w0, -1.0)
    if tangent not in _TANGENTS:
        raise ValueError(f"tangent: {tangent!r} is not one of {', '.join(_TANGENTS)}.")
    sin, cos = _TANGENTS[tangent](k_minus * jnp.minimum(x, x_to_zero))  # sin / cos = tan
    w_before_zero = w_minus * (w0_neg * cos + w_minus * sin) / (w_minus * cos - w0_neg * sin)

    # Branch w >= 0, from w0 (w0 >= 0) or from 0 after crossing (w0 < 0):
    # w(x) = w_+ tanh(k_+ x + atanh(w_start / w_+)), written without atanh so that it also
    # holds for w_start > w_+.
    x_plus = jnp.where(negative, jnp.maximum(x - x_to_zero, 0.0), x)
    w_start = jnp.where(negative, 0.0, w0)
    tt = jnp.tanh(k_plus * x_plus)
    w_positive = w_plus * (w_start + w_plus * tt) / (w_plus + w_start * tt)

    return sign * jnp.where(negative & (x <= x_to_zero), w_before_zero, w_positive)
