"""Stepped systems: the isolators of `teflon_jax.bearing` under the linear structures of
`teflon_jax.structures`, stepped by `teflon_jax.solver` (imposed-motion bearing tests,
structures on sliders and on series pendulums, two-component structures, the slab and the
building on bearing groups, vertical records), their drivers, and the isolated structures of
the studies; every structure's history is a `StructureResponse` (`simulate_history`), its
peaks the `REDUCERS` over it, folded along a run by one driver (`peak_response`)."""

from ..elements import BALANCES as BALANCES
from ..elements import FRICTION_VELOCITIES as FRICTION_VELOCITIES
from ..elements import TRIPLE_TOLERANCE as TRIPLE_TOLERANCE
from ..structures import LINEAR_RULES as LINEAR_RULES
from ._bearing_test import PATH_STRATEGIES as PATH_STRATEGIES
from ._bearing_test import BearingTestSystem as BearingTestSystem
from ._bearing_test import force_along_path as force_along_path
from ._bearing_test import imposed_path_test as imposed_path_test
from ._bearing_test import path_strategy as path_strategy
from ._bearing_test import respond_along_path as respond_along_path
from ._bearing_test import simulate_bearing_test as simulate_bearing_test
from ._bidirectional import PLANAR_NEWTON_ITERATIONS as PLANAR_NEWTON_ITERATIONS
from ._bidirectional import BidirectionalStructure as BidirectionalStructure
from ._bidirectional_models import BIDIRECTIONAL_TIME_STEP as BIDIRECTIONAL_TIME_STEP
from ._bidirectional_models import bidirectional_building as bidirectional_building
from ._bidirectional_models import (
    bidirectional_initial_state as bidirectional_initial_state,
)
from ._bidirectional_models import bidirectional_rigid_mass as bidirectional_rigid_mass
from ._bidirectional_models import bidirectional_storey_peaks as bidirectional_storey_peaks
from ._bidirectional_models import bidirectional_structure as bidirectional_structure
from ._bidirectional_models import directional_storeys as directional_storeys
from ._drivers import PEAK_REDUCERS as PEAK_REDUCERS
from ._drivers import RESPONSE_NAMES as RESPONSE_NAMES
from ._drivers import STEPS_PER_LOOP_PASS as STEPS_PER_LOOP_PASS
from ._drivers import SURFACE_REDUCERS as SURFACE_REDUCERS
from ._drivers import peak_response as peak_response
from ._drivers import response_layout as response_layout
from ._drivers import simulate_history as simulate_history
from ._drivers import smooth_max as smooth_max
from ._drivers import smooth_max_update as smooth_max_update
from ._drivers import smooth_max_value as smooth_max_value
from ._imposed_path import SampledPath as SampledPath
from ._imposed_path import normal_load_varies as normal_load_varies
from ._imposed_path import sample_velocity as sample_velocity
from ._imposed_path import sampled_path as sampled_path
from ._isolated import MONTE_CARLO_NEWTON_TOLERANCE as MONTE_CARLO_NEWTON_TOLERANCE
from ._isolated import RECOMMENDED_TIME_STEPS as RECOMMENDED_TIME_STEPS
from ._isolated import TRIPLE_MONTE_CARLO_TOLERANCE as TRIPLE_MONTE_CARLO_TOLERANCE
from ._isolated import IsolatedStructure as IsolatedStructure
from ._isolated import check_structure_bearing as check_structure_bearing
from ._isolated import isolated_structure as isolated_structure
from ._isolated import with_vertical_component as with_vertical_component
from ._on_plan import building_centre_height as building_centre_height
from ._on_plan import building_on_plan as building_on_plan
from ._on_plan import slab_on_bearings as slab_on_bearings
from ._on_plan import stack_pendulums as stack_pendulums
from ._response import MONTE_CARLO_PEAKS as MONTE_CARLO_PEAKS
from ._response import REDUCERS as REDUCERS
from ._response import BearingTestResult as BearingTestResult
from ._response import Peaks as Peaks
from ._response import ResponseLayout as ResponseLayout
from ._response import StructureResponse as StructureResponse
from ._response import base_displacement as base_displacement
from ._response import base_shear_ratio as base_shear_ratio
from ._response import carried_weight as carried_weight
from ._response import first_storey_shear_ratio as first_storey_shear_ratio
from ._response import group_load_extremes as group_load_extremes
from ._response import group_load_peaks as group_load_peaks
from ._response import isolator_force as isolator_force
from ._response import level_acceleration as level_acceleration
from ._response import peak_arrays as peak_arrays
from ._response import resultant as resultant
from ._response import slider_travel as slider_travel
from ._response import storey_drift as storey_drift
from ._response import uplift_time as uplift_time
from ._response import uplifted as uplifted
from ._series import structure_on_isolator as structure_on_isolator
from ._series import triple_structure as triple_structure
from ._structure import FRICTION_MODELS as FRICTION_MODELS
from ._structure import StructureOnSliders as StructureOnSliders
from ._structure import initial_state as initial_state
from ._structure_build import STRUCTURE_EFFECTS as STRUCTURE_EFFECTS
from ._structure_build import building_response_quantities as building_response_quantities
from ._structure_build import check_storey_height as check_storey_height
from ._structure_build import rigid_mass as rigid_mass
from ._structure_build import six_storey_building as six_storey_building
from ._structure_build import step_count as step_count
from ._structure_build import storey_rows as storey_rows
from ._structure_build import structure_on_sliders as structure_on_sliders
from ._vertical import LAW_REACH as LAW_REACH
from ._vertical import TablePressure as TablePressure
from ._vertical import flag_pressure_law as flag_pressure_law
from ._vertical import normal_load_factor as normal_load_factor
from ._vertical import pressure_law_valid as pressure_law_valid
from ._vertical import step_load_factors as step_load_factors
from ._vertical import under_ground as under_ground
from ._vertical import with_vertical_motion as with_vertical_motion
