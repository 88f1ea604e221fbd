"""Identification of PTFE bearing models from test records: fitting and model discovery.

Fits the constants of Constantinou, Mokha & Reinhorn (1990) -- f_max, delta_f, rate_a of Eq. 1,
yield_disp of Eq. 3 and breakaway_ratio of Eq. 17 -- to measured or digitised bearing tests
with optimistix least squares, with standard errors and identifiability warnings, and (model
discovery) looks for the effects the 1990 model misses.
"""

from ._augmented import simulate_augmented as simulate_augmented
from ._bearing_fit import (
    PARAMETER_NAMES as PARAMETER_NAMES,
)
from ._bearing_fit import (
    BearingFit as BearingFit,
)
from ._bearing_fit import (
    RecordResidual as RecordResidual,
)
from ._bearing_fit import (
    fit_bearing_test as fit_bearing_test,
)
from ._bearing_fit import (
    fit_bearing_tests_batch as fit_bearing_tests_batch,
)
from ._bearing_fit import (
    parse_free as parse_free,
)
from ._bearing_fit import (
    simulate_record_force as simulate_record_force,
)
from ._damper import read_friction_damper_json as read_friction_damper_json
from ._diagnostics import locate_residual as locate_residual
from ._diagnostics import regressors as regressors
from ._digitised import point_branches as point_branches

# model discovery
from ._discovery import (
    DiscoveryResult as DiscoveryResult,
)
from ._discovery import (
    DiscoveryStep as DiscoveryStep,
)
from ._discovery import (
    discover_effects as discover_effects,
)
from ._effects import (
    BASELINES as BASELINES,
)
from ._effects import (
    EFFECT_NAMES as EFFECT_NAMES,
)
from ._effects import (
    EFFECTS as EFFECTS,
)
from ._effects import (
    Effect as Effect,
)
from ._effects import (
    EffectParameter as EffectParameter,
)
from ._effects import (
    kumar_temperature_factor as kumar_temperature_factor,
)
from ._fit import (
    Bounds as Bounds,
)
from ._fit import (
    LeastSquaresResult as LeastSquaresResult,
)
from ._fit import (
    covariance_from_jacobian as covariance_from_jacobian,
)
from ._fit import (
    fit_least_squares as fit_least_squares,
)
from ._fit import (
    fit_least_squares_batch as fit_least_squares_batch,
)
from ._report import plot_fit as plot_fit
from ._report import write_fit_json as write_fit_json
