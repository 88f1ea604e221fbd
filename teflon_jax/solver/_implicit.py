"""The implicit derivative of an equilibrium solve, written once for every engine.

A step's balance is a root x(p) of a residual r(x, p) = 0 in the step's parameters p (the
bearing's and the structure's, the linear step's displacement and compliance, the start
state). Whatever iteration found the root (a bracketed scalar Newton, a damped Newton with a
line search, a secant stage), the implicit function theorem gives its tangent

    dx = -J^-1 (dr/dp dp),   J = dr/dx at the root,

one linear solve whatever the number of iterations, and outputs beyond x that are a function
y(x, p) of the root (a bearing force, Z) have dy = y_x dx + y_p dp. Forward and reverse mode
both work (the tangent is linear in dp and transposes). Krantz & Parks (2002), The Implicit
Function Theorem, Thm. 3.3.1; the same rule as optimistix's `ImplicitAdjoint`, here with the
engine's own forward iteration (its iterates unchanged) and its own structured solve of J.
"""

import functools

import jax
import jax.numpy as jnp
import numpy as np


def implicit_root(solve, residual, linear_solve, p, guess, *args, outputs=None):
    """The root of `residual` found by `solve`, differentiated implicitly in `p`.

    **Arguments:**
    - `solve(p, guess, *args)` -> (x, aux): the forward iteration (the engine's strategy), run
      as it is; `aux` its further outputs (a flag of convergence, a force at the root).
    - `residual(x, p)` -> r: the balance whose root x is (r has the shape of x).
    - `linear_solve(x, p, b, dp)` -> J^-1 b at the root, J = dr/dx: the engine's structured
      inverse (Sherman-Morrison, Woodbury blocks, a floored slope); where the iteration also
      holds a constraint that r does not carry (an imposed path's sum of increments equal to
      D), its inverse takes that constraint's tangent from `dp` as well.
    - `p`: the differentiable parameters (a pytree); `guess` and `args` (a bracket, a
      tolerance) carry no tangent.
    - `outputs(x, p)` -> `aux` again, as a function of the root and p, the same structure
      (its tangent is taken along (dx, dp); a flag or a count in it gets none); `None`: `aux`
      carries no tangent.

    **Returns:** (x, aux), x and aux bit for bit those of `solve`; tangent dx = -J^-1 (r_p dp)
    (module docstring)."""
    return _root(solve, residual, linear_solve, outputs, p, guess, *args)


@functools.partial(jax.custom_jvp, nondiff_argnums=(0, 1, 2, 3))
def _root(solve, residual, linear_solve, outputs, p, guess, *args):
    return solve(p, guess, *args)


@_root.defjvp
def _root_jvp(solve, residual, linear_solve, outputs, primals, tangents):
    p, dp = primals[0], tangents[0]
    x, aux = solve(*primals)
    r_p = jax.jvp(lambda q: residual(x, q), (p,), (dp,))[1]
    dx = -linear_solve(x, p, r_p, dp)
    if outputs is None:
        d_aux = jax.tree_util.tree_map(_zero_tangent, aux)
    else:
        d_aux = jax.jvp(outputs, (x, p), (dx, dp))[1]
    return (x, aux), (dx, d_aux)


def _zero_tangent(value):
    """The zero tangent of an output that carries none (float0 for a flag or a count)."""
    if jnp.issubdtype(jnp.result_type(value), jnp.inexact):
        return jnp.zeros_like(value)
    return np.zeros(np.shape(value), jax.dtypes.float0)
