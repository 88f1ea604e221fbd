"""Isolator elements: what an isolator of `teflon_jax.bearing` does over one step of a structure
or of an imposed path, as an element's state determination does in a finite-element code.

- `_sliders.py`: the sliders' forces at the end of a step (Eq. 1 with Table 1's parts, Bouc-Wen
  or Park's Z updated along the increment, the restrainer), their heating and their history
  (largest |Z|, surface travel).
- `_one_slider.py`: the one slider of a flat-slider or single-pendulum structure, solved for
  the isolator's displacement.
- `_balance.py`: the balance of a pendulum's sliders in series over a step, in one or two
  horizontal components, given the compliance the structure (or an actuator) leaves them.

The structures of `teflon_jax.systems` step through these; the iterations themselves are
`teflon_jax.solver`'s.
"""

from ._balance import BALANCES as BALANCES
from ._balance import SECANT_FLOOR as SECANT_FLOOR
from ._balance import TRIPLE_NEWTON_ITERATIONS as TRIPLE_NEWTON_ITERATIONS
from ._balance import TRIPLE_TOLERANCE as TRIPLE_TOLERANCE
from ._balance import balance as balance
from ._balance import isolator_parameters as isolator_parameters
from ._balance import loaded_blocks as loaded_blocks
from ._balance import pendulum_blocks as pendulum_blocks
from ._balance import predicted_increments as predicted_increments
from ._balance import secant_floors as secant_floors
from ._balance import slider_step as slider_step
from ._balance import uplift_increments as uplift_increments
from ._one_slider import bearing_force as bearing_force
from ._one_slider import force_and_slopes as force_and_slopes
from ._one_slider import isolator_residual as isolator_residual
from ._one_slider import isolator_root as isolator_root
from ._one_slider import predicted_root as predicted_root
from ._one_slider import residual_and_slope as residual_and_slope
from ._sliders import FRICTION_VELOCITIES as FRICTION_VELOCITIES
from ._sliders import balance_forces as balance_forces
from ._sliders import end_velocity as end_velocity
from ._sliders import heated_step as heated_step
from ._sliders import initial_history as initial_history
from ._sliders import next_history as next_history
from ._sliders import series_heat_kernel as series_heat_kernel
from ._sliders import slider_forces as slider_forces
from ._sliders import slider_lengths as slider_lengths
from ._sliders import step_history as step_history
from ._sliders import surface_temperature_rises as surface_temperature_rises
