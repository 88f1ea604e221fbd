"""Hysteretic variable Z of the friction force: Bouc-Wen (uniaxial) and Park et al. (biaxial).

The friction force is F = mu_s W Z with |Z| < 1 while sticking and |Z| -> 1 while sliding.
References: Constantinou, Mokha & Reinhorn (1990), Eqs. 3-4 and 8-9; Bouc (1971); Wen (1976);
Park, Wen & Ang (1986).
"""

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import ArrayLike


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
    """dZ/dt [1/s] of Eq. 3 for sliding `velocity` [m/s]."""
    z_eta_1 = _abs_power(z, h.eta - 1.0)
    return (
        h.A * velocity
        - h.gamma * jnp.abs(velocity) * z * z_eta_1
        - h.beta * velocity * z_eta_1 * jnp.abs(z)
    ) / h.yield_disp


def park_rate(h: BoucWen, z, velocity):
    """d(Zx, Zy)/dt [1/s] of the biaxial model of Park, Wen & Ang (1986), Eqs. 8-9 (eta = 2).

    `z` and `velocity` have shape (..., 2). While sliding with A / (beta + gamma) = 1 the
    solution is (Zx, Zy) = (cos theta, sin theta), theta the direction of the velocity.
    """
    zx, zy = z[..., 0], z[..., 1]
    vx, vy = velocity[..., 0], velocity[..., 1]
    common = h.gamma * (jnp.abs(vx * zx) + jnp.abs(vy * zy)) + h.beta * (vx * zx + vy * zy)
    dzx = (h.A * vx - common * zx) / h.yield_disp
    dzy = (h.A * vy - common * zy) / h.yield_disp
    return jnp.stack([dzx, dzy], axis=-1)


def bouc_wen_exact_update(h: BoucWen, z0, displacement_increment):
    """Z after a monotone displacement increment, in closed form (eta = 2, gamma > beta).

    Bouc-Wen is rate independent: along a monotone path Z depends only on the displacement.
    With s = sign(du), w = s Z and x = |du| / Y, Eq. 3 becomes a Riccati equation
        dw/dx = A - (gamma + beta) w^2   for w >= 0   (tanh branch, towards sqrt(A/(beta+gamma))),
        dw/dx = A + (gamma - beta) w^2   for w < 0    (tan branch, up to w = 0),
    solved exactly here, crossing w = 0 inside the increment when it happens.
    Requires eta = 2 and gamma > beta (paper: 0.9 > 0.1); the caller checks this.

    **Arguments:** `h` Bouc-Wen constants, `z0` [-] at the start, `displacement_increment` du [m].

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

    # Branch w0 < 0: w(x) = w_minus * tan(k_minus x + atan(w0 / w_minus)) until w = 0.
    negative = w0 < 0
    w0_neg = jnp.where(negative, w0, -1.0)
    x_to_zero = -jnp.arctan(w0_neg / w_minus) / k_minus
    x_neg = jnp.minimum(x, x_to_zero)
    t = jnp.tan(k_minus * x_neg)
    w_after_neg = w_minus * (w0_neg + w_minus * t) / (w_minus - w0_neg * t)
    x_left = jnp.maximum(x - x_to_zero, 0.0)
    w_crossed = w_plus * jnp.tanh(k_plus * x_left)
    w_from_negative = jnp.where(x <= x_to_zero, w_after_neg, w_crossed)

    # Branch w0 >= 0: w(x) = w_plus * tanh(k_plus x + atanh(w0 / w_plus)), written without atanh
    # so that it also holds for w0 > w_plus.
    w0_pos = jnp.where(negative, 0.0, w0)
    tt = jnp.tanh(k_plus * x)
    w_from_positive = w_plus * (w0_pos + w_plus * tt) / (w_plus + w0_pos * tt)

    return sign * jnp.where(negative, w_from_negative, w_from_positive)
