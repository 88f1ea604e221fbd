"""`RiccatiNewmark`: a diffrax solver that is not held back by the stiffness of Z.

The hysteretic variable relaxes on the time scale Y / |v| (0.3 ms for Y = 0.005 in at
15 in/s), so explicit solvers need steps of that size. Bouc-Wen with eta = 2 is rate
independent and, along a monotone displacement increment, a Riccati equation with a closed-form
solution (`bouc_wen_exact_update`). This solver asks the system for one step of its own
structure-aware update:

- imposed-motion tests: Z updated exactly along the imposed increment;
- structures: Newmark's average-acceleration rule (trapezoidal, unconditionally stable,
  second order) for the masses, with the friction force at the end of the step from the exact
  Z update along Newmark's path of the isolator (split at its turning point when the sliding
  velocity reverses inside the step, `split_at_turn`), solved by a bracketed Newton iteration on the isolator
  displacement.

The step size then follows the record and the structure, not Y. The solver plugs into
`diffrax.diffeqsolve` with a constant step size; a step whose nonlinear equation does not
converge is reported as `RESULTS.nonlinear_divergence` (with `throw=False`, per batch member).
"""

import abc
from collections.abc import Callable
from typing import ClassVar

import diffrax
import equinox as eqx
import jax.numpy as jnp
import numpy as np

from ..validation import concrete


class AbstractSteppedSystem(eqx.Module):
    """A vector field `f(t, y, args)` that also provides a structure-aware step.

    Subclasses implement `__call__` (the ODE, usable by any diffrax solver) and `advance`
    (used by `RiccatiNewmark`).
    """

    @abc.abstractmethod
    def __call__(self, t, y, args):
        """dy/dt."""

    @abc.abstractmethod
    def advance(self, t0, t1, y0, args):
        """Advance from t0 to t1; returns (y1, converged) with `converged` a boolean scalar."""


def structure_step_end(t0, t1, time_step):
    """`t1`, checked to lie one structure `time_step` [s] after `t0` (to 1e-6 of the step, or
    the rounding of float32 times): a structure's step matrices are factored for that step, so
    a `RiccatiNewmark` solve on another grid is an error (`eqx.error_if`), not a silent result."""
    t0, t1 = jnp.asarray(t0), jnp.asarray(t1)
    eps = jnp.finfo(jnp.result_type(t1, float)).eps
    slack = jnp.maximum(1e-6 * time_step, 16 * eps * jnp.abs(t1))
    return eqx.error_if(t1, jnp.abs((t1 - t0) - time_step) > slack, "step differs from the structure's time_step")


class RiccatiNewmark(diffrax.AbstractSolver):
    """Fixed-step solver for `AbstractSteppedSystem` vector fields (see module docstring).

    Use with `diffrax.ConstantStepSize()` (or `StepTo` aligned with the record samples).
    Second order for smooth motion; Z itself is exact along monotone increments.
    """

    term_structure: ClassVar = diffrax.ODETerm
    interpolation_cls: ClassVar[Callable[..., diffrax.LocalLinearInterpolation]] = (
        diffrax.LocalLinearInterpolation
    )

    def order(self, terms):
        return 2

    def init(self, terms, t0, t1, y0, args):
        return None

    def step(self, terms, t0, t1, y0, args, solver_state, made_jump):
        del solver_state, made_jump
        system = _unwrap(terms)
        if not isinstance(system, AbstractSteppedSystem):
            raise ValueError(
                "RiccatiNewmark: the ODETerm's vector field must be a teflon-jax system "
                f"(AbstractSteppedSystem), got {type(system).__name__}; use a general diffrax "
                "solver (e.g. diffrax.Tsit5) for other vector fields."
            )
        y1, converged = system.advance(t0, t1, y0, args)
        result = diffrax.RESULTS.where(
            converged, diffrax.RESULTS.successful, diffrax.RESULTS.nonlinear_divergence
        )
        return y1, None, dict(y0=y0, y1=y1), None, result

    def func(self, terms, t0, y0, args):
        return terms.vf(t0, y0, args)


def _unwrap(term):
    # diffeqsolve wraps the user's term (time direction); this solver integrates forward only.
    while isinstance(term, diffrax._term.WrapTerm):
        term = term.term
    return getattr(term, "vector_field", None)


RICCATI_FORM_MESSAGE = (
    "RiccatiNewmark's closed-form Z update needs eta = 2 and gamma > beta (paper: eta = 2, "
    "gamma = 0.9, beta = 0.1); for other Bouc-Wen shapes pass an adaptive diffrax solver, e.g. "
    "solver=diffrax.Tsit5() (with rtol, atol: a PIDController)"
)


def require_riccati_form(h):
    """Check that Bouc-Wen constants admit the closed-form update (eta = 2, gamma > beta).

    Concrete constants: a `ValueError` naming the offending constant, at trace time. Traced
    constants (e.g. under `vmap` over stacked systems): an `eqx.error_if` runtime error. Any
    A > 0 is admitted (the update holds for A != beta + gamma).

    **Returns:** `h`, carrying the runtime check when its constants are traced; use the
    returned value so that the check is part of the computation.
    """
    eta, beta, gamma = concrete(h.eta), concrete(h.beta), concrete(h.gamma)
    if eta is not None and not np.all(eta == 2.0):
        raise ValueError(f"eta: {RICCATI_FORM_MESSAGE}; got eta = {np.asarray(eta).tolist()}.")
    if beta is not None and gamma is not None and not np.all(gamma > beta):
        raise ValueError(
            f"gamma: {RICCATI_FORM_MESSAGE}; got gamma = {np.asarray(gamma).tolist()}, "
            f"beta = {np.asarray(beta).tolist()}."
        )
    if eta is not None and beta is not None and gamma is not None:
        return h
    bad = jnp.any(jnp.asarray(h.eta) != 2.0) | jnp.any(jnp.asarray(h.gamma) <= jnp.asarray(h.beta))
    return eqx.tree_at(
        lambda x: x.yield_disp, h, eqx.error_if(jnp.asarray(h.yield_disp), bad, RICCATI_FORM_MESSAGE)
    )
