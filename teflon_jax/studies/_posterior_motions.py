"""Monte Carlo over bearing uncertainty and ground motion together.

A posterior of a bearing's constants (S draws, e.g. of a Bayesian fit: `BearingPosterior`,
or `IsolatorPosterior` of a series pendulum's surfaces) enters `monte_carlo` as one
`SlidingBearing` (or `SeriesPendulum`) whose leaves carry a leading axis of the S draws
(`.bearings(point)`), with the index of the draw each run takes. The
compiled chunk function receives the stacked bearings as an argument and the draw indices as
a batched input; inside the vmap a run's bearing is the draw's slice of every leaf, put in
place of the structure's own (`with_bearing`). The friction constants are thus traced values:
one compiled program serves every draw, and another posterior of the same parts.

Two designs:

- one draw per motion (`motion_draws`): motion m runs draw k(m) = p[m mod S], p a seeded
  permutation of the S draws, so the draws are taken without replacement while N <= S and
  cycled through again beyond;
- nested, K bearings x M motions (`nested_draws`): K distinct draws (seeded, without
  replacement), each run on the same M motions (common random numbers: the bearings are
  compared on one set of motions), for the split of each peak's variance into a motion part
  and a bearing part (`variance_split`).
"""

import equinox as eqx
import jax
import numpy as np

from ..bearing import SeriesPendulum, check_bearing, check_series_pendulum
from ..systems import IsolatedStructure
from ..validation import concrete


def _count(value, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise ValueError(f"{name}: must be a positive integer, got {value!r}.")
    return int(value)


def _permutation(n_draws: int, seed) -> np.ndarray:
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed: must be an integer >= 0, got {seed!r}.")
    return np.random.default_rng(int(seed)).permutation(n_draws)


def motion_draws(n_motions: int, n_draws: int, *, seed: int = 0) -> np.ndarray:
    """The posterior draw of each of `n_motions` motions: k(m) = p[m mod S] for a permutation
    p of the S = `n_draws` draws seeded by `seed` (NumPy's PCG64), so no draw repeats while
    N <= S and every draw is used as evenly as N allows beyond.

    **Returns:** (N,) int array of draw indices in [0, S)."""
    n_motions, n_draws = _count(n_motions, "n_motions"), _count(n_draws, "n_draws")
    return _permutation(n_draws, seed)[np.arange(n_motions) % n_draws]


def nested_draws(n_bearings: int, n_draws: int, *, seed: int = 0) -> np.ndarray:
    """K = `n_bearings` distinct draws of the S = `n_draws` of a posterior, for the nested
    design K bearings x M motions: the first K of the permutation `motion_draws` takes for
    the same `seed`. `ValueError` when K > S.

    **Returns:** (K,) int array of draw indices in [0, S)."""
    n_bearings, n_draws = _count(n_bearings, "n_bearings"), _count(n_draws, "n_draws")
    if n_bearings > n_draws:
        raise ValueError(f"n_bearings: {n_bearings} bearings asked for but the posterior has "
                         f"{n_draws} draws; ask for at most {n_draws}.")
    return _permutation(n_draws, seed)[:n_bearings]


def structure_bearing(structure):
    """The bearing whose constants a posterior's draws vary in a structure of the studies (an
    `IsolatedStructure` built with `bearing=...`, or on a triple or double pendulum, in one or
    two components, with or without a vertical component): its `SlidingBearing`, or its
    `SeriesPendulum`; `None` where it runs Table 1's bearing."""
    if isinstance(structure, IsolatedStructure):
        return structure.bearing if structure.pendulum is None else structure.pendulum
    return None


def with_bearing(structure, bearing):
    """`structure` running `bearing` (of the same parts as its own `structure_bearing`, traced
    or not) in place of its own."""
    if isinstance(structure, IsolatedStructure) and structure.pendulum is not None:
        return eqx.tree_at(lambda s: s.pendulum, structure, bearing)
    return eqx.tree_at(lambda s: s.bearing, structure, bearing)


def draw_bearing(bearings, index):
    """The bearing of draw `index` (an integer, traced or not) of stacked `bearings`: every
    leaf's slice `leaf[index]`."""
    return jax.tree_util.tree_map(lambda leaf: leaf[index], bearings)


def check_bearings(structure, bearings) -> int:
    """S, the number of draws of the stacked `bearings` (every leaf with a leading axis of S
    over the shape of the structure's own bearing's leaf), checked against `structure`:
    `ValueError` naming what differs (a structure without a bearing of its own, other parts,
    other shapes, values that are not finite or outside the bearing's ranges: `check_bearing`)."""
    point = structure_bearing(structure)
    if point is None:
        raise ValueError("bearings: the structure runs no bearing of its own (Table 1's); build it with "
                         "isolated_structure(..., bearing=point) (or isolator=pendulum, a triple or double "
                         "pendulum) from the bearing the posterior's draws vary.")
    if jax.tree_util.tree_structure(bearings) != jax.tree_util.tree_structure(point):
        raise ValueError("bearings: their parts differ from the structure's bearing's; stack draws of "
                         "the same bearing (BearingPosterior.bearings(point) of the structure's bearing).")
    sizes = set()
    for leaf, own in zip(jax.tree_util.tree_leaves(bearings), jax.tree_util.tree_leaves(point)):
        shape, own_shape = np.shape(leaf), np.shape(own)
        if len(shape) != len(own_shape) + 1 or shape[1:] != own_shape:
            raise ValueError(f"bearings: a leaf of shape {shape} stacks the structure's bearing's "
                             f"{own_shape}; every leaf needs a leading axis of the draws.")
        sizes.add(shape[0])
        values = concrete(leaf)  # None when traced
        if values is not None and not np.all(np.isfinite(values.astype(float))):
            raise ValueError("bearings: a constant of a draw is not finite (NaN or inf).")
    if len(sizes) != 1 or 0 in sizes:
        raise ValueError(f"bearings: the leaves stack different numbers of draws {sorted(sizes)}.")
    size = sizes.pop()
    try:  # the bearing's ranges, draw by draw (a flat bearing's checks take arrays)
        if isinstance(point, SeriesPendulum):
            if concrete(jax.tree_util.tree_leaves(bearings)[0]) is not None:
                for k in range(size):
                    check_series_pendulum(jax.tree_util.tree_map(lambda leaf, k=k: leaf[k], bearings))
        else:
            check_bearing(bearings)
    except ValueError as error:
        raise ValueError(f"bearings: a draw is outside the bearing's ranges: {error}") from None
    return size


def run_draws(bearing_draw, n_draws: int, n_motions: int, nested: bool) -> np.ndarray:
    """The draw index of each run of a Monte Carlo with stacked bearings, checked: one per
    motion, `bearing_draw` (N,); nested, each of the K draws of `bearing_draw` (K,) on all N
    motions, run r = k N + m taking draw `bearing_draw[k]` and motion m."""
    if bearing_draw is None:
        raise ValueError("bearing_draw: give the draw of each motion (motion_draws) or, with "
                         "nested=True, the draws to run on every motion (nested_draws).")
    draws = np.asarray(bearing_draw)
    if draws.ndim != 1 or draws.size == 0 or not np.issubdtype(draws.dtype, np.integer):
        raise ValueError(f"bearing_draw: expected a non-empty 1-D array of integers, got {draws!r}.")
    if draws.min() < 0 or draws.max() >= n_draws:
        raise ValueError(f"bearing_draw: indices must lie in [0, {n_draws}) (the draws of the "
                         f"bearings), got {draws.min()}..{draws.max()}.")
    if nested:
        return np.repeat(draws, n_motions)
    if draws.size != n_motions:
        raise ValueError(f"bearing_draw: {draws.size} draws for {n_motions} motions; give one per "
                         "motion (or nested=True).")
    return draws


def nest_runs(tree, n_bearings: int):
    """Arrays over runs r = k M + m (leading axis K M) reshaped to (K, M, ...)."""
    return jax.tree_util.tree_map(lambda x: np.reshape(np.asarray(x), (n_bearings, -1) + np.shape(x)[1:]), tree)
