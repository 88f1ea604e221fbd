"""The `teflon-jax` command line: a leaf that uses every package; nothing imports it."""

from ._main import main as main
