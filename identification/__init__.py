"""Identification of PTFE bearing models from test records: fitting and model discovery.

Fits the constants of Constantinou, Mokha & Reinhorn (1990) -- f_max, delta_f, rate_a of Eq. 1
(parallel and, from biaxial records, perpendicular to the lay), yield_disp of Eq. 3 and
breakaway_ratio of Eq. 17 -- to measured or digitised bearing tests
with optimistix least squares, with standard errors and identifiability warnings, and (model
discovery) looks for the effects the 1990 model misses.
"""

from teflon_jax.formats import read_friction_damper_json as read_friction_damper_json

from . import bayes as bayes
from . import bearing_fit as bearing_fit
from . import discovery as discovery
from . import hysteretic as hysteretic
from . import least_squares as least_squares
from .bayes import BayesResult as BayesResult
from .bayes import fit_bayes as fit_bayes
from .bearing_fit import PARAMETER_NAMES as PARAMETER_NAMES
from .bearing_fit import BearingFit as BearingFit
from .bearing_fit import RecordResidual as RecordResidual
from .bearing_fit import fit_bearing_test as fit_bearing_test
from .bearing_fit import fit_bearing_tests_batch as fit_bearing_tests_batch
from .bearing_fit import parse_free as parse_free
from .bearing_fit import plot_fit as plot_fit
from .bearing_fit import point_branches as point_branches
from .bearing_fit import simulate_record_force as simulate_record_force
from .bearing_fit import write_fit_json as write_fit_json
from .discovery import BASELINES as BASELINES
from .discovery import EFFECT_NAMES as EFFECT_NAMES
from .discovery import EFFECTS as EFFECTS
from .discovery import DiscoveryResult as DiscoveryResult
from .discovery import DiscoveryStep as DiscoveryStep
from .discovery import Effect as Effect
from .discovery import EffectParameter as EffectParameter
from .discovery import discover_effects as discover_effects
from .discovery import locate_residual as locate_residual
from .discovery import regressors as regressors
from .discovery import simulate_augmented as simulate_augmented
from .least_squares import Bounds as Bounds
from .least_squares import LeastSquaresResult as LeastSquaresResult
from .least_squares import covariance_from_jacobian as covariance_from_jacobian
from .least_squares import fit_least_squares as fit_least_squares
from .least_squares import fit_least_squares_batch as fit_least_squares_batch
