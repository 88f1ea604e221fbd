"""Value checks that run on concrete inputs and step aside for traced ones.

Outside `jit`/`vmap`/`grad` a bad value is a `ValueError` naming the parameter and the rule;
inside them values are not known at trace time and are not checked here.
"""

import jax
import numpy as np


def concrete(value):
    """`value` as a NumPy array, or `None` when it is traced."""
    if value is None:
        return None
    leaves = jax.tree_util.tree_leaves(value)
    if any(isinstance(leaf, jax.core.Tracer) for leaf in leaves):
        return None
    return np.asarray(value)


def require(value, test, name: str, rule: str) -> None:
    """Raise `ValueError(f"{name}: {rule}; got ...")` unless `test(value)` holds everywhere."""
    array = concrete(value)
    if array is None:
        return
    ok = test(array)
    if not bool(np.all(ok)):
        shown = array if array.size == 1 else array[~np.asarray(ok, dtype=bool)]
        raise ValueError(f"{name}: {rule}; got {np.asarray(shown).tolist()}.")


def require_positive(value, name: str, unit: str = "") -> None:
    """`value > 0` (and finite) everywhere, else a `ValueError` naming `name`."""
    require(value, lambda x: np.isfinite(x) & (x > 0), name, f"must be a finite number > 0{unit}")


def given_options(options: dict) -> list[str]:
    """The names in `options` ({name: (value, default)}) whose value was given: not `None`
    where the default is `None`, else different from the default; for refusing, by name, the
    options an engine does not take."""
    return [name for name, (value, default) in options.items()
            if (value is not None if default is None else value != default)]
