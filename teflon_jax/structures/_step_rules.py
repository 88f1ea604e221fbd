"""One step of a structure on sliders as a linear map: Newmark's, or exact for inputs that vary
linearly over the step.

Both give the state at the end of a step as (u1, v1) = R w + f F, with
w = (u0, v0, a_g0, F_r0, a_g1) the start state, the ground acceleration at both ends and the
bearing force at the start, and F the bearing force at the end (solved for by
the isolator's balance in `teflon_jax.systems`), M a + C v + K u = -M r a_g - B F. Products over
short axes are written out as sums of element products (`small_dot`), which XLA fuses with
the element-wise work around them on a CPU.
"""

import jax
import jax.numpy as jnp

SMALL_PRODUCT = 4
"""Contraction length up to which `small_dot` writes a matrix product as sums of products."""


def small_dot(a, b, limit=SMALL_PRODUCT):
    """a @ b for a (m, k) or (k,) and b (k, n) or (k,): as a written-out sum over k of element
    products when k <= `limit`, which XLA fuses with the element-wise work around it
    (a CPU dot kernel per tiny product costs more than the product: ~20 % of the rigid-mass
    step), a dot otherwise."""
    k = a.shape[-1]
    if k > limit:
        return a @ b
    if a.ndim == 1:
        return sum(a[i] * b[i] for i in range(k))
    if b.ndim == 1:
        return sum(a[:, i] * b[i] for i in range(k))
    return sum(a[:, i, None] * b[None, i, :] for i in range(k))


LINEAR_RULES = ("newmark", "exact")
"""`StructureOnSliders.linear_rule`: how the linear structure is advanced over a step.

- "newmark": Newmark's average acceleration (trapezoidal rule); its period error
  (omega dt)^2 / 12 reaches 0.8 % for the building's upper storey modes at 5 ms steps.
- "exact": the exact response to ground acceleration and bearing force varying linearly
  over the step (first-order hold), from one matrix exponential: no period error in any mode,
  so that the step is set by the bearing alone (the building at 5 ms; see RECOMMENDED_TIME_STEPS).
"""


EXPONENTIAL_SQUARINGS = 64
"""Most squarings of the exact step's matrix exponential (`first_order_hold`): the norm of
A dt halved up to 64 times (the default 16 stops near omega^2 dt = 10^5 and gives NaN beyond).
Each halving costs some accuracy: a rigid-frame limit of Table 2's building is best taken at
10^3 times its frequencies at 5 ms steps (tests/test_building_on_plan_series.py)."""


def first_order_hold(a, b, time_step):
    """(free, start, end) of the exact step of x' = A x + B q(s) with the inputs q varying
    linearly from q0 to q1 over `time_step` dt [s]: x1 = free x0 + start q0 + end q1, where
    free = e^(A dt), end = (1/dt) int_0^dt e^(A (dt - s)) s ds B and start + end =
    int_0^dt e^(A s) ds B, all blocks of the exponential of the augmented matrix
    [[A, B, 0], [0, 0, I], [0, 0, 0]] dt (Van Loan, 1978). `a` (N, N), `b` (N, k). A stiff
    structure (omega^2 dt far above 1) needs more halvings of A dt than `expm`'s default 16, which
    return NaN: up to `EXPONENTIAL_SQUARINGS` are allowed."""
    size, inputs = a.shape[0], b.shape[1]
    total = size + 2 * inputs
    augmented = jnp.zeros((total, total), a.dtype)
    augmented = augmented.at[:size, :size].set(a).at[:size, size:size + inputs].set(b)
    augmented = augmented.at[size:size + inputs, size + inputs:].set(jnp.eye(inputs, dtype=a.dtype))
    e = jax.scipy.linalg.expm(augmented * time_step, max_squarings=EXPONENTIAL_SQUARINGS)
    end = e[:size, size + inputs:] / time_step
    return e[:size, :size], e[:size, size:size + inputs] - end, end


def exact_step_matrices(mass, stiffness, damping, time_step):
    """(R, f) of the exact step for inputs linear over the step (first-order hold).

    With x = (u, v), x' = A x + B q(s), A = [[0, I], [-M^-1 K, -M^-1 C]], q = (a_g, F) and
    B = [[0, 0], [-1, -e0 / m0]], q varying linearly from q0 to q1 over dt:
    x1 = e^(A dt) x0 + (G0 - G1) q0 + G1 q1 with G0 = int_0^dt e^(A s) ds B and
    G1 = (1/dt) int_0^dt e^(A (dt - s)) s ds B; e^(A dt), G0 and dt G1 are blocks of the
    exponential of the augmented matrix [[A, B, 0], [0, 0, I], [0, 0, 0]] dt (Van Loan, 1978).

    **Arguments:** `mass` (n,) [kg], `stiffness`, `damping` (n, n) [N/m, N s/m], `time_step` [s].

    **Returns:** R (2n, 2n + 3) acting on (u0, v0, a_g0, F_r0, a_g1) and f (2n,) on F [N].
    """
    m = mass
    n = m.shape[-1]
    eye, zeros = jnp.eye(n, dtype=m.dtype), jnp.zeros((n, n), m.dtype)
    a = jnp.block([[zeros, eye], [-stiffness / m[:, None], -damping / m[:, None]]])
    b = jnp.concatenate([jnp.zeros((n, 2), m.dtype),
                         jnp.stack([-jnp.ones(n, m.dtype), -eye[:, 0] / m[0]], 1)], 0)
    free, start, end = first_order_hold(a, b, time_step)
    return jnp.concatenate([free, start, end[:, :1]], 1), end[:, 1]


def newmark_step_matrices(mass, stiffness, damping, newmark_inverse, time_step):
    """(R, f) of Newmark's average-acceleration step, with the start acceleration
    a0 = -1 a_g0 - M^-1 (C v0 + K u0) - e0 F_r0 / m0 folded in:
    u1 = K_eff^-1 (M (4/dt^2 u0 + 4/dt v0 + a0) + C (2/dt u0 + v0) - M 1 a_g1 - e0 F),
    v1 = 2/dt (u1 - u0) - v0 (Newmark written out in `test_step_matrix_is_the_step`)."""
    dt, m, inverse = time_step, mass, newmark_inverse
    n = m.shape[-1]
    diagonal = jnp.diag(m)
    eye, zeros = jnp.eye(n, dtype=m.dtype), jnp.zeros((n, n), m.dtype)
    e0 = eye[:, 0]
    a_of = jnp.concatenate([-stiffness / m[:, None], -damping / m[:, None], -jnp.ones((n, 1), m.dtype),
                            -(e0 / m[0])[:, None]], 1)
    start = jnp.concatenate([4 / dt**2 * diagonal + 2 / dt * damping, 4 / dt * diagonal + damping,
                             jnp.zeros((n, 2), m.dtype)], 1) + diagonal @ a_of
    u_rows = inverse @ jnp.concatenate([start, -(m)[:, None]], 1)
    identity_u = jnp.concatenate([eye, zeros, jnp.zeros((n, 3), m.dtype)], 1)
    identity_v = jnp.concatenate([zeros, eye, jnp.zeros((n, 3), m.dtype)], 1)
    v_rows = 2 / dt * (u_rows - identity_u) - identity_v
    fu = -inverse[:, 0]
    return jnp.concatenate([u_rows, v_rows], 0), jnp.concatenate([fu, 2 / dt * fu])
