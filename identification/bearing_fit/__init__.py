"""Fitting the 1990 model's constants to bearing test records (measured or digitised)."""

from ._digitised import point_branches as point_branches
from ._fit import as_records as as_records
from ._fit import fit_bearing_test as fit_bearing_test
from ._fit import fit_bearing_tests_batch as fit_bearing_tests_batch
from ._model import PARAMETER_NAMES as PARAMETER_NAMES
from ._pendulum_fit import PendulumFit as PendulumFit
from ._pendulum_fit import fit_pendulum_test as fit_pendulum_test
from ._pendulum_fit import pendulum_friction_record as pendulum_friction_record
from ._pendulum_fit import refit_pendulum_radius as refit_pendulum_radius
from ._plan import BearingFit as BearingFit
from ._plan import RecordResidual as RecordResidual
from ._plan import parse_free as parse_free
from ._record_force import PERPENDICULAR_NAMES as PERPENDICULAR_NAMES
from ._record_force import simulate_record_force as simulate_record_force
from ._report import plot_fit as plot_fit
from ._report import write_fit_json as write_fit_json
from ._to_bearing import PARAMETER_FIELDS as PARAMETER_FIELDS
from ._to_bearing import fitted_bearing as fitted_bearing
from ._to_bearing import part_errors as part_errors
from ._triple_fit import TripleFit as TripleFit
from ._triple_fit import fit_triple_pendulum_test as fit_triple_pendulum_test
from ._triple_fit import triple_parameters as triple_parameters
from ._triple_fit import triple_with_parameters as triple_with_parameters
from ._triple_plan import TRIPLE_PARAMETER_NAMES as TRIPLE_PARAMETER_NAMES
from ._triple_plan import TRIPLE_PARAMETER_UNITS as TRIPLE_PARAMETER_UNITS
from ._triple_plan import triple_fit_plan as triple_fit_plan
