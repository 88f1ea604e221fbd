"""Identification of PTFE bearing models from test records: fitting and model discovery.

Fits the constants of Constantinou, Mokha & Reinhorn (1990) -- f_max, delta_f, rate_a of Eq. 1,
yield_disp of Eq. 3 and breakaway_ratio of Eq. 17 -- to measured or digitised bearing tests
with optimistix least squares, with standard errors and identifiability warnings, and (model
discovery) looks for the effects the 1990 model misses.
"""

from ._bearing_fit import (
    PARAMETER_NAMES as PARAMETER_NAMES,
    BearingFit as BearingFit,
    RecordResidual as RecordResidual,
    fit_bearing_test as fit_bearing_test,
    fit_bearing_tests_batch as fit_bearing_tests_batch,
    parse_free as parse_free,
    simulate_record_force as simulate_record_force,
)
from ._damper import read_friction_damper_json as read_friction_damper_json
from ._digitised import point_branches as point_branches
from ._fit import (
    Bounds as Bounds,
    LeastSquaresResult as LeastSquaresResult,
    covariance_from_jacobian as covariance_from_jacobian,
    fit_least_squares as fit_least_squares,
    fit_least_squares_batch as fit_least_squares_batch,
)
from ._report import plot_fit as plot_fit, write_fit_json as write_fit_json

# model discovery
from ._discovery import (
    DiscoveryResult as DiscoveryResult,
    DiscoveryStep as DiscoveryStep,
    discover_effects as discover_effects,
)
from ._effects import (
    BASELINES as BASELINES,
    EFFECT_NAMES as EFFECT_NAMES,
    EFFECTS as EFFECTS,
    Effect as Effect,
    EffectParameter as EffectParameter,
    kumar_temperature_factor as kumar_temperature_factor,
)
from ._augmented import simulate_augmented as simulate_augmented
from ._diagnostics import locate_residual as locate_residual, regressors as regressors
