"""Closed-form update of the biaxial hysteretic variable (Zx, Zy) along a straight increment.

Park, Wen & Ang (1986), as used in Eqs. 8-9 of Constantinou, Mokha & Reinhorn (1990) with
eta = 2:

    Y dZx = A dUx - Zx [gamma (|dUx Zx| + |dUy Zy|) + beta (dUx Zx + dUy Zy)]
    Y dZy = A dUy - Zy [gamma (|dUx Zx| + |dUy Zy|) + beta (dUx Zx + dUy Zy)]

The law is rate independent. Along a straight increment dU = |dU| e (unit direction e, path
length x = |dU| / Y [-]) and while the signs s_i = sign(e_i Z_i) stay fixed it reads

    dZ/dx = A e - Z (w . Z),      w_i = (gamma s_i + beta) e_i,

a vector Riccati equation. It is linearised by Z = y / s with y' = A e s, s' = w . y, so that
s'' = k2 s with k2 = A (w . e), and written with tau = tanh(k x / 2) / k (k2 > 0),
tan(k x / 2) / k (k2 < 0) or x / 2 (k2 = 0) as one rational expression:

    Z(x) = [Z0 (1 - k2 tau^2) + 2 A e tau (1 + c tau)] / (1 + k2 tau^2 + 2 c tau),  c = w . Z0.

A component opposing the motion (s_i = -1) can only cross zero upwards (at Z_i = 0,
dZ_i/dx = A e_i), once per increment; its crossing, the root of the numerator (a quadratic
in tau), ends the segment and the signs are re-evaluated. Two crossings at most, so three
segments cover any increment exactly. For e = (1, 0) this is the uniaxial Riccati solution of
`bouc_wen_exact_update`.
"""

import jax
import jax.numpy as jnp

_SEGMENTS = 3
_SMALL = 1e-3  # |k2 x^2 / 4| or |k2 tau^2| below which the Taylor series are used


def _tau_of_length(x, k2):
    """tau(x) = tanh(k x / 2) / k for k2 = k^2 > 0, tan(k x / 2) / k for k2 = -k^2 < 0."""
    q = k2 * x * x / 4
    small = jnp.abs(q) < _SMALL
    series = 0.5 * x * (1 - q / 3 + 2 * q**2 / 15 - 17 * q**3 / 315 + 62 * q**4 / 2835)
    k = jnp.sqrt(jnp.where(small, 1.0, jnp.abs(k2)))
    angle = jnp.where(small, 0.0, k * x / 2)
    hyperbolic = jnp.tanh(angle) / k
    trigonometric = jnp.tan(jnp.minimum(angle, 1.5707963)) / k
    return jnp.where(small, series, jnp.where(k2 > 0, hyperbolic, trigonometric))


def _length_of_tau(tau, k2):
    """Inverse of `_tau_of_length` (inf where tau lies beyond the hyperbolic branch's 1/k)."""
    v2 = k2 * tau * tau
    small = jnp.abs(v2) < _SMALL
    series = 2 * tau * (1 + v2 / 3 + v2**2 / 5 + v2**3 / 7 + v2**4 / 9)
    k = jnp.sqrt(jnp.where(small, 1.0, jnp.abs(k2)))
    v = jnp.where(small, 0.0, k * tau)
    inside = v < 1.0
    hyperbolic = jnp.where(inside, 2 * jnp.arctanh(jnp.where(inside, v, 0.0)) / k, jnp.inf)
    trigonometric = 2 * jnp.arctan(v) / k
    return jnp.where(small, series, jnp.where(k2 > 0, hyperbolic, trigonometric))


def _first_positive_root(qa, qb, qc):
    """Smallest positive root of qa t^2 + qb t + qc = 0 given qb qc < 0 (inf if none)."""
    disc = qb * qb - 4 * qa * qc
    real = disc >= 0
    sq = jnp.sqrt(jnp.where(real, disc, 0.0))
    q = -0.5 * (qb + jnp.where(qb >= 0, 1.0, -1.0) * sq)
    q_safe = jnp.where(q == 0, 1.0, q)
    r2 = jnp.where(q == 0, jnp.inf, qc / q_safe)
    qa_safe = jnp.where(qa == 0, 1.0, qa)
    r1 = jnp.where(qa == 0, jnp.inf, q / qa_safe)
    r1 = jnp.where(r1 > 0, r1, jnp.inf)
    r2 = jnp.where(r2 > 0, r2, jnp.inf)
    return jnp.where(real, jnp.minimum(r1, r2), jnp.inf)


def _crossing_length(z_i, a_i, c, k2):
    """Path length [-] at which an opposing component z_i (e_i z_i < 0) reaches zero:
    the first positive root of its numerator (2 a_i c - z_i k2) tau^2 + 2 a_i tau + z_i."""
    tau = _first_positive_root(2 * a_i * c - z_i * k2, 2 * a_i, z_i)
    finite = jnp.isfinite(tau)
    x = _length_of_tau(jnp.where(finite, tau, 0.0), k2)
    return jnp.where(finite & (a_i * z_i < 0), x, jnp.inf)


def _segment(h, zx, zy, ex, ey, remaining):
    """One stretch of the increment with fixed signs of e_i Z_i (all arrays elementwise)."""
    sx = jnp.where(ex * zx >= 0, 1.0, -1.0)
    sy = jnp.where(ey * zy >= 0, 1.0, -1.0)
    wx = (h.gamma * sx + h.beta) * ex
    wy = (h.gamma * sy + h.beta) * ey
    c = wx * zx + wy * zy
    ax, ay = h.A * ex, h.A * ey
    k2 = wx * ax + wy * ay
    x_cross_x = _crossing_length(zx, ax, c, k2)
    x_cross_y = _crossing_length(zy, ay, c, k2)
    x_seg = jnp.minimum(remaining, jnp.minimum(x_cross_x, x_cross_y))
    tau = _tau_of_length(x_seg, k2)
    k2t2 = k2 * tau * tau
    denominator = 1 + k2t2 + 2 * c * tau
    grow = 2 * tau * (1 + c * tau)
    zx_new = (zx * (1 - k2t2) + ax * grow) / denominator
    zy_new = (zy * (1 - k2t2) + ay * grow) / denominator
    zx_new = jnp.where(x_cross_x <= x_seg, 0.0, zx_new)
    zy_new = jnp.where(x_cross_y <= x_seg, 0.0, zy_new)
    return zx_new, zy_new, remaining - x_seg


def park_exact_update(h, z0, displacement_increment):
    """(Zx, Zy) after a straight displacement increment, exactly (Park's model, eta = 2).

    **Arguments:** `h`: `BoucWen` constants (Y [m], A, beta, gamma; eta must be 2, which the
    caller checks, e.g. with `require_riccati_form`), scalars or arrays broadcasting with the
    leading axes; `z0` (..., 2) [-] at the start; `displacement_increment` (..., 2) [m], the
    straight increment (dUx, dUy).

    **Returns:** (Zx, Zy) (..., 2) [-] at the end of the increment.
    """
    du = jnp.asarray(displacement_increment)
    z0 = jnp.asarray(z0)
    zx, zy = z0[..., 0], z0[..., 1]
    dx, dy = du[..., 0], du[..., 1]
    norm2 = dx * dx + dy * dy
    moving = norm2 > 0
    norm = jnp.sqrt(jnp.where(moving, norm2, 1.0))
    ex = jnp.where(moving, dx / norm, 1.0)
    ey = jnp.where(moving, dy / norm, 0.0)
    remaining = jnp.where(moving, norm, 0.0) / h.yield_disp
    zx, zy, remaining = jax.lax.fori_loop(
        0, _SEGMENTS, lambda _, c: _segment(h, *c[:2], ex, ey, c[2]), (zx, zy, remaining)
    )
    return jnp.stack([zx, zy], axis=-1)
