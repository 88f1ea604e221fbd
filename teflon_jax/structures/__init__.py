"""The linear structure above the isolators and its loads: the mass, stiffness and damping of
the paper's rigid mass and Table 2 building (`rigid_mass_matrices`, `building_matrices`,
`superstructure_matrices`), the ground motion as a load signal (`signal_from_motion`), the plan
of a rigid base on bearing groups (arms, bearing map, tributary loads, level heights), the
isolator of each group (`plan_isolator`), and the groups' normal loads under the overturning
moment (`overturning_map`, `SupportPlan`, `supported_loads`). The linear structure's step
rules (`LINEAR_RULES`: Newmark's and the exact step as linear maps, `newmark_step_matrices`,
`exact_step_matrices`) are here too; the systems (`teflon_jax.systems`) put the sliders under
these structures and step them."""

from ._linear import LinearStructure as LinearStructure
from ._linear import building_matrices as building_matrices
from ._linear import rigid_mass_matrices as rigid_mass_matrices
from ._linear import signal_from_motion as signal_from_motion
from ._linear import superstructure_matrices as superstructure_matrices
from ._overturning import SupportPlan as SupportPlan
from ._overturning import group_factor as group_factor
from ._overturning import inertia_force as inertia_force
from ._overturning import initial_normal_load as initial_normal_load
from ._overturning import overturned_loads as overturned_loads
from ._overturning import overturning_force as overturning_force
from ._overturning import overturning_map as overturning_map
from ._overturning import redistributed_loads as redistributed_loads
from ._overturning import resting_loads as resting_loads
from ._overturning import support_plan as support_plan
from ._overturning import supported_loads as supported_loads
from ._plan import LOAD_TOLERANCE as LOAD_TOLERANCE
from ._plan import check_plan as check_plan
from ._plan import level_heights as level_heights
from ._plan import plan_bearing_map as plan_bearing_map
from ._plan import slab_corners as slab_corners
from ._plan import slab_point_displacement as slab_point_displacement
from ._plan import stack_bearings as stack_bearings
from ._plan_isolators import PlanIsolator as PlanIsolator
from ._plan_isolators import plan_isolator as plan_isolator
from ._plan_isolators import refuse_springs as refuse_springs
from ._step_rules import LINEAR_RULES as LINEAR_RULES
from ._step_rules import exact_step_matrices as exact_step_matrices
from ._step_rules import first_order_hold as first_order_hold
from ._step_rules import newmark_step_matrices as newmark_step_matrices
from ._step_rules import small_dot as small_dot
