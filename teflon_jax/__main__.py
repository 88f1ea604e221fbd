"""`python -m teflon_jax`: the `teflon-jax` command."""

import sys

from .cli import main

sys.exit(main())
