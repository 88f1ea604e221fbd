"""Small dense linear algebra of the bidirectional bearing solve, in x and y parts.

Vectors over the G bearing groups are kept as their x and y parts (G,) and matrices as 2 x 2
blocks of (G, G); products over short axes are written out as sums of element products so that
XLA fuses them with the element-wise work around them on a CPU.
"""

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


def matvec(matrix, vector):
    """matrix (m, G) @ vector (G,), as a product of elements for G = 1 (no dot kernel)."""
    return matrix[:, 0] * vector if matrix.shape[1] == 1 else small_dot(matrix, vector)


def block_matvec(blocks, vector):
    """((xx, xy), (yx, yy)) @ (vx, vy), each block (G, G)."""
    return tuple(matvec(blocks[i][0], vector[0]) + matvec(blocks[i][1], vector[1]) for i in range(2))


def affine(flexibility, forces, d, d_linear):
    """d - d_linear + G_b F, in x and y parts."""
    product = block_matvec(flexibility, forces)
    return tuple(d[i] - d_linear[i] + product[i] for i in range(2))


def solve_blocks(blocks, rhs):
    """((xx, xy), (yx, yy))^-1 (rx, ry): in closed form for one bearing group (2 x 2), by LU
    otherwise."""
    if blocks[0][0].shape == (1, 1):
        (a, b), (c, d) = ((blk[:, 0] for blk in row) for row in blocks)
        det = a * d - b * c
        return (d * rhs[0] - b * rhs[1]) / det, (a * rhs[1] - c * rhs[0]) / det
    full = jnp.block(blocks)
    flat = jnp.linalg.solve(full, jnp.concatenate(rhs))
    n = rhs[0].shape[0]
    return flat[:n], flat[n:]


def difference_jacobian(residual, x, r, x0, scale):
    """dr/dx (n, n) by forward differences, steps 1e-7 max(scale, |x - x0|) [m] (relative
    error about 1e-7: Newton's convergence is then quadratic down to far below the tolerance).
    Forward-mode differentiation through the closed-form Park update would be exact, but XLA's
    CPU fusion emitter recomputes its shared subexpressions, making it ~20x dearer than the
    two extra residuals."""
    h = 1e-7 * jnp.maximum(scale, jnp.abs(x - x0))
    columns = [(residual(x.at[j].add(h[j])) - r) / h[j] for j in range(x.shape[0])]
    return jnp.stack(columns, axis=1)
