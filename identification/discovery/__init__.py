"""Model discovery: candidate physical effects, the augmented simulator, residual diagnostics
and forward selection."""

from ._augmented import AugmentedData as AugmentedData
from ._augmented import BiaxialAugmentedData as BiaxialAugmentedData
from ._augmented import UniaxialAugmentedData as UniaxialAugmentedData
from ._augmented import active_mask as active_mask
from ._augmented import candidate_bearing as candidate_bearing
from ._augmented import candidate_start as candidate_start
from ._augmented import default_parameters as default_parameters
from ._augmented import discovered_bearing as discovered_bearing
from ._augmented import prepare_record as prepare_record
from ._augmented import simulate_augmented as simulate_augmented
from ._diagnostics import effective_samples as effective_samples
from ._diagnostics import half_cycle_index as half_cycle_index
from ._diagnostics import ljung_box as ljung_box
from ._diagnostics import locate_residual as locate_residual
from ._diagnostics import regressors as regressors
from ._diagnostics import residual_correlation as residual_correlation
from ._discovery import TABLE1_RATE_RANGE as TABLE1_RATE_RANGE
from ._discovery import discover_effects as discover_effects
from ._discovery import stack_check as stack_check
from ._effects import BASELINES as BASELINES
from ._effects import EFFECT_NAMES as EFFECT_NAMES
from ._effects import EFFECTS as EFFECTS
from ._effects import Effect as Effect
from ._effects import EffectParameter as EffectParameter
from ._report import write_report as write_report
from ._result import DiscoveryResult as DiscoveryResult
from ._result import DiscoveryStep as DiscoveryStep
from ._result import confidence_wording as confidence_wording
from ._series_discovery import SERIES_BASELINE as SERIES_BASELINE
from ._series_discovery import SERIES_EFFECTS as SERIES_EFFECTS
from ._series_discovery import SeriesDiscoveryResult as SeriesDiscoveryResult
from ._series_discovery import discover_series_effects as discover_series_effects
from ._series_report import write_series_report as write_series_report
