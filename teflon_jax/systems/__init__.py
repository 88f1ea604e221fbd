"""Systems as diffrax vector fields: imposed-motion bearing tests, structures on sliders (rigid
mass, the Table 2 building), and the isolated structures of the studies with their peak responses."""

from ._bearing_test import BearingTestResult as BearingTestResult
from ._bearing_test import BearingTestSystem as BearingTestSystem
from ._bearing_test import force_along_path as force_along_path
from ._bearing_test import simulate_bearing_test as simulate_bearing_test
from ._bidirectional import BidirectionalResponse as BidirectionalResponse
from ._bidirectional import BidirectionalStructure as BidirectionalStructure
from ._bidirectional import bidirectional_initial_state as bidirectional_initial_state
from ._bidirectional import bidirectional_structure as bidirectional_structure
from ._bidirectional import simulate_bidirectional as simulate_bidirectional
from ._bidirectional_models import bidirectional_building as bidirectional_building
from ._bidirectional_models import bidirectional_rigid_mass as bidirectional_rigid_mass
from ._isolated import RECOMMENDED_TIME_STEPS as RECOMMENDED_TIME_STEPS
from ._isolated import IsolatedStructure as IsolatedStructure
from ._isolated import check_design as check_design
from ._isolated import design_ranges as design_ranges
from ._isolated import isolated_structure as isolated_structure
from ._models import BuildingResponse as BuildingResponse
from ._models import building_response_quantities as building_response_quantities
from ._models import rigid_mass as rigid_mass
from ._models import signal_from_motion as signal_from_motion
from ._models import six_storey_building as six_storey_building
from ._models import superstructure_matrices as superstructure_matrices
from ._peaks import RESPONSE_NAMES as RESPONSE_NAMES
from ._peaks import peak_response as peak_response
from ._peaks import smooth_max as smooth_max
from ._structure import FRICTION_MODELS as FRICTION_MODELS
from ._structure import StructureOnSliders as StructureOnSliders
from ._structure import StructureResponse as StructureResponse
from ._structure import initial_state as initial_state
from ._structure import simulate_structure as simulate_structure
from ._structure import structure_on_sliders as structure_on_sliders
