"""A force-driven oscillator with Bouc-Wen hysteresis, simulated for identification.

    m y'' + c y' + k y + z = u(t)
    z' = alpha y' - beta (gamma |y'| |z|^(nu - 1) z + delta y' |z|^nu)

(y [m], u [N], z [N]; m [kg], c [N s/m], k [N/m], alpha [N/m], beta [1/m] for nu = 1,
gamma, delta, nu [-]): the hysteretic benchmark of nonlinear system identification (Noel &
Schoukens, "Hysteretic benchmark with a dynamic nonlinearity", Workshop on Nonlinear System
Identification Benchmarks, 2016; true values m = 2, c = 10, k = 5e4, alpha = 5e4,
beta = 1e3, gamma = 0.8, delta = -1.1, nu = 1). beta, gamma and delta enter only as the
products beta gamma and beta delta, so those are the parameters here (`beta_gamma`,
`beta_delta` [1/m for nu = 1]).

Integration: classical Runge-Kutta (order 4) with `n_sub` steps per sample interval, the
input between samples from a cubic spline through the sampled u (the input of a sampled record
is known only at the samples); the state starts at rest unless given.
"""

import jax
import jax.numpy as jnp
import numpy as np
from scipy.interpolate import CubicSpline

PARAMETER_NAMES = ("m", "c", "k", "alpha", "beta_gamma", "beta_delta")
"""Identifiable parameters of the benchmark (nu fixed)."""

PARAMETER_UNITS = {"m": "kg", "c": "N s/m", "k": "N/m", "alpha": "N/m",
                   "beta_gamma": "1/m (nu = 1)", "beta_delta": "1/m (nu = 1)", "nu": "-"}

BENCHMARK = {"m": 2.0, "c": 10.0, "k": 5.0e4, "alpha": 5.0e4, "beta_gamma": 1.0e3 * 0.8,
             "beta_delta": 1.0e3 * -1.1, "nu": 1.0}
"""True values of Noel & Schoukens (2016), SI (beta = 1e3, gamma = 0.8, delta = -1.1)."""


def fine_input(time, u, n_sub: int):
    """Input at the RK4 stage times: (n - 1, 2 n_sub + 1) array (half-step spacing)."""
    time = np.asarray(time, dtype=float)
    spline = CubicSpline(time, np.asarray(u, dtype=float))
    frac = np.linspace(0.0, 1.0, 2 * n_sub + 1)
    t = time[:-1, None] + np.diff(time)[:, None] * frac[None, :]
    return spline(t)


def _rhs(p, state, u):
    y, v, z = state
    nu = p["nu"]
    absz = jnp.abs(z)
    zn1 = jnp.where(nu == 1.0, jnp.ones_like(z), jnp.power(absz + 1e-300, nu - 1.0))
    dz = p["alpha"] * v - p["beta_gamma"] * jnp.abs(v) * zn1 * z - p["beta_delta"] * v * zn1 * absz
    a = (u - p["c"] * v - p["k"] * y - z) / p["m"]
    return jnp.stack([v, a, dz])


def simulate_hysteretic(params, time, u_fine, *, state0=None):
    """Displacement y [m] at the samples (jit/grad-safe).

    **Arguments:** `params` with `PARAMETER_NAMES` (and optional `nu`, default 1), `time`
    [s] (n,), `u_fine` from `fine_input` (the number of substeps is read from its shape),
    `state0` = (y, y', z) at time[0] (default rest).

    **Returns:** y (n,).
    """
    p = dict(params)
    p.setdefault("nu", 1.0)
    time = jnp.asarray(time)
    u_fine = jnp.asarray(u_fine)
    n_sub = (u_fine.shape[1] - 1) // 2
    dt = jnp.diff(time)
    s0 = jnp.zeros(3) if state0 is None else jnp.asarray(state0, dtype=float)

    def interval(state, inputs):
        h_all, uu = inputs
        h = h_all / n_sub

        def sub(j, s):
            u0, u1, u2 = uu[2 * j], uu[2 * j + 1], uu[2 * j + 2]
            k1 = _rhs(p, s, u0)
            k2 = _rhs(p, s + 0.5 * h * k1, u1)
            k3 = _rhs(p, s + 0.5 * h * k2, u1)
            k4 = _rhs(p, s + h * k3, u2)
            return s + h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)

        state = jax.lax.fori_loop(0, n_sub, sub, state)
        return state, state[0]

    _, y = jax.lax.scan(interval, s0, (dt, u_fine))
    return jnp.concatenate([s0[:1], y])
