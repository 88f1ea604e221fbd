"""The forward-mode Jacobian of a design's responses, one tangent at a time.

`jax.jacfwd` pushes every tangent through the program at once (a `vmap` over the unit
tangents). Over a set of motions that is itself vmapped, each Newton loop of a two-component
run is then batched twice, and its loop runs as long as any member of either batch is off
balance with every member's tangents carried: measured on the rigid mass under two
components (2 motions of 2 s, 2 design variables, 2-core CPU), 35 s against 0.17 s for the
same derivative taken as one `jax.jvp` per variable (`benchmarks/design_derivatives.py`).
`forward_jacobian` takes those tangents one after the other in a `lax.map`: one compiled
`jvp`, the primal recomputed per variable, the same values as `jax.jacfwd` to rounding.
"""

import jax
import jax.numpy as jnp
from jax.flatten_util import ravel_pytree


def forward_jacobian(fn, has_aux: bool = False):
    """`jax.jacfwd(fn, has_aux=has_aux)` for a function of a small pytree `x` of design
    variables, its tangents taken one after the other (`lax.map` of `jax.jvp`; module
    docstring). **Returns:** a function of x giving, as `jax.jacfwd`, for each output leaf of
    shape S a tree like x of leaves S + (leaf shape), and with `has_aux` (jacobian, aux)."""

    def jacobian(x):
        flat, unravel = ravel_pytree(x)
        basis = jnp.eye(flat.size, dtype=flat.dtype)

        def column(tangent):
            return jax.jvp(fn, (x,), (unravel(tangent),), has_aux=has_aux)

        if has_aux:
            _, columns, aux = jax.lax.map(column, basis)
            aux = jax.tree_util.tree_map(lambda a: a[0], aux)
        else:
            _, columns = jax.lax.map(column, basis)
        tree = jax.tree_util.tree_map(lambda c: _per_input(c, x), columns)
        return (tree, aux) if has_aux else tree

    return jacobian


def _per_input(stacked, x):
    """One output leaf's columns (m, *S) as a tree like x of leaves S + (leaf shape)."""
    leaves, treedef = jax.tree_util.tree_flatten(x)
    rows = jnp.moveaxis(stacked, 0, -1)  # (*S, m)
    shape = rows.shape[:-1]
    parts, start = [], 0
    for leaf in leaves:
        size = jnp.size(leaf)
        parts.append(rows[..., start:start + size].reshape(shape + jnp.shape(leaf)))
        start += size
    return jax.tree_util.tree_unflatten(treedef, parts)
