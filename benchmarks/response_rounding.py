"""Whether the set of arrays a jitted history returns changes its rounding: the same
`simulate_history` (the rigid mass on the triple pendulum of `engine_numbers.py`, its
record and step) compiled once returning its whole response and once returning only the
displacement and the bearing force. Prints the largest difference of each over its largest value.

`python benchmarks/response_rounding.py` (run it under any checkout with `PYTHONPATH`).
"""

import importlib.util
import pathlib

import jax
import numpy as np

jax.config.update("jax_enable_x64", True)

from teflon_jax.excitation import uniform_signal  # noqa: E402
from teflon_jax.systems import (  # noqa: E402
    simulate_history,
    triple_structure,
)

spec = importlib.util.spec_from_file_location("en", pathlib.Path(__file__).with_name("engine_numbers.py"))
en = importlib.util.module_from_spec(spec)
spec.loader.exec_module(en)
system = triple_structure("rigid", en.TRIPLE, uniform_signal(en._ground(1), en.RECORD_STEP), time_step=en.TIME_STEP)
full = jax.jit(simulate_history, static_argnums=1)(system, en.DURATION)
two = jax.jit(lambda s: (lambda r: (r.displacement, r.bearing_force))(simulate_history(s, en.DURATION)))(system)
for name, a, b in (("displacement", full.displacement, two[0]), ("bearing_force", full.bearing_force, two[1])):
    print(name, float(np.max(np.abs(np.asarray(a) - np.asarray(b))) / np.max(np.abs(np.asarray(a)))))
