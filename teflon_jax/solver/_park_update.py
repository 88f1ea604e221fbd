"""Closed-form update of the biaxial hysteretic variable (Zx, Zy) along a straight increment.

Park, Wen & Ang (1986), as used in Eqs. 8-9 of Constantinou, Mokha & Reinhorn (1990) with
eta = 2:

    Y dZx = A dUx - Zx [gamma (|dUx Zx| + |dUy Zy|) + beta (dUx Zx + dUy Zy)]
    Y dZy = A dUy - Zy [gamma (|dUx Zx| + |dUy Zy|) + beta (dUx Zx + dUy Zy)]

The law is rate independent. Along a straight increment dU = |dU| e (unit direction e, path
length x = |dU| / Y [-]) and while the signs s_i = sign(e_i Z_i) stay fixed it reads

    dZ/dx = A e - Z (w . Z),      w_i = (gamma s_i + beta) e_i,

a vector Riccati equation. It is linearised by Z = y / s with y' = A e s, s' = w . y, so that
s'' = k2 s with k2 = A (w . e), and written with tau = tanh(k x / 2) / k (k2 = k^2 > 0),
tan(k x / 2) / k (k2 = -k^2 < 0) or x / 2 (k2 = 0) as one rational expression:

    Z(x) = [Z0 (1 - k2 tau^2) + 2 A e tau (1 + c tau)] / (1 + k2 tau^2 + 2 c tau),  c = w . Z0.

A component opposing the motion (s_i = -1) can only cross zero upwards (at Z_i = 0,
dZ_i/dx = A e_i), once per increment; its crossing, the smallest positive root of the
numerator (a quadratic in tau), ends the segment and the signs are re-evaluated. Two crossings
at most (after its crossing a component runs with the motion), so three segments cover any
increment exactly; the third has no crossing left to look for. For e = (1, 0) this is the
uniaxial Riccati solution of `bouc_wen_exact_update`.

Cost (the update sits inside every Newton iteration of every step): tau(x) is one entire
function of q = k2 x^2 / 4 on both branches, tau = (x / 2) S(q) / C(q) with
S(q) = sum q^n / (2n + 1)! and C(q) = sum q^n / (2n)! (sinh and cosh of sqrt(q), or sin and
cos of sqrt(-q)), evaluated as polynomials for -pi^2/4 < q <= 1 and with tanh beyond; a
crossing is compared with the end of the increment in tau (tau grows with x), so the inverse
x(tau) (artanh or arctan) is needed only for the length left after a crossing. No float64
tan, arctanh or branch evaluated twice, which on CPU costs more than the rest together.
"""

import math

import jax.numpy as jnp

from ..bearing import vector_arctan

_SERIES_Q = 1.0
"""q = k2 x^2 / 4 above which tau uses tanh instead of the power series (|error| < 1e-17)."""
_POLE_Q = -((math.pi / 2) ** 2)
"""q of the pole of tan: the end of an increment past it lies beyond the crossing."""
_SINH_TERMS = [1.0 / math.factorial(2 * n + 1) for n in range(12)]  # S(q), n = 0..11
_COSH_TERMS = [1.0 / math.factorial(2 * n) for n in range(13)]  # C(q), n = 0..12
_INVERSE_SERIES_V = 0.01
"""|k2 tau^2| below which x(tau) = 2 tau sum v^n / (2n + 1) (8 terms, error < 1e-17)."""


def _horner(coefficients, q):
    out = jnp.full_like(q, coefficients[-1])
    for c in coefficients[-2::-1]:
        out = out * q + c
    return out


def _tau_of_length(x, k2):
    """tau(x) [-]: tanh(k x / 2) / k for k2 = k^2 > 0, tan(k x / 2) / k for k2 = -k^2 < 0,
    x / 2 for k2 = 0; inf past the pole of tan (x >= pi / k)."""
    q = 0.25 * k2 * x * x
    big = q > _SERIES_Q
    q_series = jnp.where(big, 0.0, jnp.maximum(q, _POLE_Q))
    cosine = _horner(_COSH_TERMS, q_series)
    before_pole = (q > _POLE_Q) & (cosine > 0)
    series = 0.5 * x * _horner(_SINH_TERMS, q_series) / jnp.where(before_pole, cosine, 1.0)
    half_angle = jnp.sqrt(jnp.where(big, q, 1.0))  # k x / 2
    hyperbolic = 0.5 * x * jnp.tanh(half_angle) / half_angle
    return jnp.where(big, hyperbolic, jnp.where(before_pole, series, jnp.inf))


def _length_of_tau(tau, k2):
    """Inverse of `_tau_of_length` for 0 <= tau < (1/k on the hyperbolic branch):
    x = 2 artanh(k tau) / k (k2 > 0) or 2 arctan(k tau) / k (k2 < 0)."""
    v = k2 * tau * tau
    small = jnp.abs(v) < _INVERSE_SERIES_V
    v_series = jnp.where(small, v, 0.0)
    series = sum(v_series**n / (2 * n + 1) for n in range(8))
    u = jnp.sqrt(jnp.where(small, 1.0, jnp.abs(v)))
    hyperbolic_u = jnp.where(small | (v < 0), 0.5, jnp.minimum(u, 1.0 - 1e-16))
    hyperbolic = 0.5 * jnp.log((1 + hyperbolic_u) / (1 - hyperbolic_u)) / hyperbolic_u
    trigonometric = vector_arctan(u) / u
    return 2 * tau * jnp.where(small, series, jnp.where(v > 0, hyperbolic, trigonometric))


def _crossing_tau(z_i, a_i, c, k2):
    """tau [-] at which a component opposing the motion (a_i z_i < 0) reaches zero: the
    smallest positive root of its numerator (2 a_i c - z_i k2) tau^2 + 2 a_i tau + z_i (inf
    where none). With qb = 2 a_i and qc = z_i of opposite signs, it is qc / q with
    q = -(qb + sign(qb) sqrt(qb^2 - 4 qa qc)) / 2 (the root of smaller magnitude, no
    cancellation)."""
    qa = 2 * a_i * c - z_i * k2
    qb = 2 * a_i
    disc = qb * qb - 4 * qa * z_i
    opposing = (a_i * z_i < 0) & (disc >= 0)
    q = -0.5 * (qb + jnp.where(qb >= 0, 1.0, -1.0) * jnp.sqrt(jnp.where(opposing, disc, 1.0)))
    return jnp.where(opposing, z_i / jnp.where(opposing, q, 1.0), jnp.inf)


def _segment(h, zx, zy, ex, ey, remaining, last):
    """One stretch of the increment with fixed signs of e_i Z_i (all arrays elementwise):
    up to the first crossing of zero by an opposing component, or to the end. **Returns:**
    (Zx, Zy, the length left after it, and the stretch's (gx, gy, c, k2, tau, length, D)
    for its slope, `_segment_slope`)."""
    gx, gy = _sign_factors(h.gamma, h.beta, zx, zy, ex, ey)
    wx, wy = gx * ex, gy * ey
    c = wx * zx + wy * zy
    ax, ay = h.A * ex, h.A * ey
    k2 = wx * ax + wy * ay
    tau = _tau_of_length(remaining, k2)
    length = remaining
    if not last:
        tau_x = _crossing_tau(zx, ax, c, k2)
        tau_y = _crossing_tau(zy, ay, c, k2)
        tau_cross = jnp.minimum(tau_x, tau_y)
        crossing = tau_cross < tau
        tau = jnp.where(crossing, tau_cross, tau)
    k2t2 = k2 * tau * tau
    denominator = 1 + k2t2 + 2 * c * tau
    grow = 2 * tau * (1 + c * tau)
    zx_new = (zx * (1 - k2t2) + ax * grow) / denominator
    zy_new = (zy * (1 - k2t2) + ay * grow) / denominator
    if last:
        return zx_new, zy_new, jnp.zeros_like(remaining), (gx, gy, c, k2, tau, length, denominator)
    zx_new = jnp.where(crossing & (tau_x <= tau_cross), 0.0, zx_new)
    zy_new = jnp.where(crossing & (tau_y <= tau_cross), 0.0, zy_new)
    used = _length_of_tau(jnp.where(crossing, tau_cross, 0.0), k2)
    length = jnp.where(crossing, used, remaining)
    remaining = jnp.where(crossing, jnp.maximum(remaining - used, 0.0), 0.0)
    return zx_new, zy_new, remaining, (gx, gy, c, k2, tau, length, denominator)


def _sign_factors(gamma, beta, zx, zy, ex, ey):
    """(gamma s_x + beta, gamma s_y + beta), s_i = sign(e_i Z_i) (+1 at 0): w_i = g_i e_i."""
    return (gamma * jnp.where(ex * zx >= 0, 1.0, -1.0) + beta,
            gamma * jnp.where(ey * zy >= 0, 1.0, -1.0) + beta)


def _start(h, z0, displacement_increment):
    """(Zx, Zy, ex, ey, the path length |dU| / Y [-], whether dU != 0, |dU| [m] (1 at rest)) of
    an increment: its unit direction e, (1, 0) at rest."""
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
    return zx, zy, ex, ey, remaining, moving, norm


def park_exact_update(h, z0, displacement_increment):
    """(Zx, Zy) after a straight displacement increment, exactly (Park's model, eta = 2).

    **Arguments:** `h`: `BoucWen` constants (Y [m], A, beta, gamma; eta must be 2, which the
    caller checks, e.g. with `require_riccati_form`), scalars or arrays broadcasting with the
    leading axes; `z0` (..., 2) [-] at the start; `displacement_increment` (..., 2) [m], the
    straight increment (dUx, dUy).

    **Returns:** (Zx, Zy) (..., 2) [-] at the end of the increment. Differentiable (forward
    and reverse) in all arguments; at a zero increment the derivative with respect to it is
    taken as zero (the update is only directionally differentiable there).
    """
    zx, zy, ex, ey, remaining, moving, norm = _start(h, z0, displacement_increment)
    for k in range(3):
        zx, zy, remaining, _ = _segment(h, zx, zy, ex, ey, remaining, last=k == 2)
    return jnp.stack([zx, zy], axis=-1)


_SLOPE_SINH = [(n + 1) / math.factorial(2 * n + 3) for n in range(11)]  # S'(q)
_SLOPE_COSH = [(n + 1) / math.factorial(2 * n + 2) for n in range(12)]  # C'(q)


def _tau_slope(length, k2, tau):
    """d tau / d k2 [-] at a fixed length x [-]: ((x / 2)(1 - k2 tau^2) - tau) / (2 k2), from
    tau = tanh(k x / 2) / k on both branches; for |q| <= 1 (q = k2 x^2 / 4, where that
    difference cancels) the derivative of tau = (x / 2) S(q) / C(q) written out in q."""
    q = 0.25 * k2 * length * length
    small = jnp.abs(q) <= _SERIES_Q
    q_series = jnp.where(small, q, 0.0)
    sine, cosine = _horner(_SINH_TERMS, q_series), _horner(_COSH_TERMS, q_series)
    sine_slope, cosine_slope = _horner(_SLOPE_SINH, q_series), _horner(_SLOPE_COSH, q_series)
    series = 0.125 * length**3 * (sine_slope * cosine - sine * cosine_slope) / (cosine * cosine)
    closed = (0.5 * length * (1 - k2 * tau * tau) - tau) / (2 * jnp.where(small, 1.0, k2))
    return jnp.where(small, series, closed)


def _segment_slope(h, zx, zy, ex, ey, zx_new, zy_new, parts, dzx, dzy, dex, dey):
    """Tangents of (Zx, Zy) at a stretch's end from those at its start (`dzx`, `dzy`) and of the
    direction (`dex`, `dey`), its length and signs held (each (..., m) for m tangents):
    Z = N / D with N = Z0 (1 - k2 tau^2) + 2 A e tau (1 + c tau), D = 1 + k2 tau^2 + 2 c tau
    differentiated in Z0 and e (c = w . Z0, k2 = A w . e, w_i = g_i e_i, tau through k2)."""
    gx, gy, c, k2, tau, length, denominator = (part[..., None] for part in parts)
    zx, zy, ex, ey, zx_new, zy_new = (a[..., None] for a in (zx, zy, ex, ey, zx_new, zy_new))
    a = jnp.asarray(h.A)[..., None]
    dc = gx * (dex * zx + ex * dzx) + gy * (dey * zy + ey * dzy)
    dk2 = 2 * a * (gx * ex * dex + gy * ey * dey)
    dtau = _tau_slope(length, k2, tau) * dk2
    grow = 1 + c * tau
    d_k2t2 = dk2 * tau * tau + 2 * k2 * tau * dtau
    d_grow = 2 * (dtau * grow + tau * (dc * tau + c * dtau))  # d[2 tau (1 + c tau)]
    d_denominator = d_k2t2 + 2 * (dc * tau + c * dtau)
    dnx = dzx * (1 - k2 * tau * tau) - zx * d_k2t2 + a * (2 * dex * tau * grow + ex * d_grow)
    dny = dzy * (1 - k2 * tau * tau) - zy * d_k2t2 + a * (2 * dey * tau * grow + ey * d_grow)
    return (dnx - zx_new * d_denominator) / denominator, (dny - zy_new * d_denominator) / denominator


def park_exact_update_and_slope(h, z0, displacement_increment):
    """`park_exact_update` and its slope with respect to the increment.

    **Returns:** (Z (..., 2) [-] at the end of the increment, dZ/dU (..., 2, 2) [1/m], rows
    the components of Z, columns those of the increment). Along the increment the slope is the
    end's rate (A e - Z (w . Z)) / Y; across it, the tangent of the path's turning carried
    through each stretch at its fixed length (Park's rate is continuous where a component
    crosses zero, so the crossings' moving carries no slope). At a zero increment, the
    one-sided slope along +x and +y (each column the end rate of a motion that way)."""
    zx, zy, ex, ey, remaining, moving, norm = _start(h, z0, displacement_increment)
    # tangents along the increment's x and y (last axis): Z0 is held; e turns by (I - e e^T) / |dU|
    eye = jnp.eye(2, dtype=zx.dtype)
    turn = jnp.where(moving, 1 / norm, 0.0)[..., None]
    dex = (eye[0] - ex[..., None] * jnp.stack([ex, ey], -1)) * turn
    dey = (eye[1] - ey[..., None] * jnp.stack([ex, ey], -1)) * turn
    dzx = dzy = jnp.zeros(zx.shape + (2,), zx.dtype)
    for k in range(3):
        zx1, zy1, remaining, parts = _segment(h, zx, zy, ex, ey, remaining, last=k == 2)
        dzx, dzy = _segment_slope(h, zx, zy, ex, ey, zx1, zy1, parts, dzx, dzy, dex, dey)
        zx, zy = zx1, zy1
    # the length: the end's rate, along e (a zero increment: along +x and along +y apart)
    ux = jnp.where(moving[..., None], ex[..., None], eye[0])  # the motion's x part per column
    uy = jnp.where(moving[..., None], ey[..., None], eye[1])
    a, gamma, beta, y = (jnp.asarray(v)[..., None] for v in (h.A, h.gamma, h.beta, h.yield_disp))
    zx, zy = zx[..., None], zy[..., None]
    gx, gy = _sign_factors(gamma, beta, zx, zy, ux, uy)
    load = gx * ux * zx + gy * uy * zy
    rate_x, rate_y = (a * ux - zx * load) / y, (a * uy - zy * load) / y
    along = jnp.where(moving[..., None], jnp.stack([ex, ey], -1), 1.0)  # e_j per column, 1 at rest
    slope = jnp.stack([dzx + rate_x * along, dzy + rate_y * along], axis=-2)
    return jnp.stack([zx[..., 0], zy[..., 0]], axis=-1), slope
