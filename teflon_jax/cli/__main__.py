"""`python -m teflon_jax.cli`."""

import sys

from ._main import main

sys.exit(main())
