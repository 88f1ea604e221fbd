"""The catalogue of the isolators teflon-jax runs: each kind listed once, by name, with its
description, sliders, isolator file example and test-record model. Plain Python (no JAX), read
by the bearing package, the file formats and the command line alike."""

from ._isolators import DOUBLE_FP as DOUBLE_FP
from ._isolators import FLAT as FLAT
from ._isolators import IN_SERIES as IN_SERIES
from ._isolators import ISOLATORS as ISOLATORS
from ._isolators import KINDS as KINDS
from ._isolators import ONE_SURFACE as ONE_SURFACE
from ._isolators import SINGLE_FP as SINGLE_FP
from ._isolators import TRIPLE_FP as TRIPLE_FP
from ._isolators import IsolatorKind as IsolatorKind
