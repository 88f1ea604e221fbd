"""Studies over many runs: the Fig. 11 sweep, record sets, Monte Carlo (over intensity levels, with
fragility fits) and gradient-based design."""

from ._bidirectional_study import (
    BidirectionalIsolatedStructure as BidirectionalIsolatedStructure,
)
from ._bidirectional_study import BidirectionalPeaks as BidirectionalPeaks
from ._bidirectional_study import (
    bidirectional_isolated_structure as bidirectional_isolated_structure,
)
from ._bidirectional_study import bidirectional_peak_response as bidirectional_peak_response
from ._bounding import BOUNDING_CASES as BOUNDING_CASES
from ._bounding import bounding_design as bounding_design
from ._bounding import check_property_factors as check_property_factors
from ._bounding import governing_cases as governing_cases
from ._bounding import scaled_friction as scaled_friction
from ._bounding import series_bounding_design as series_bounding_design
from ._bounding import surface_frictions as surface_frictions
from ._chunks import CPU_CHUNK as CPU_CHUNK
from ._chunks import LARGEST_CHUNK as LARGEST_CHUNK
from ._chunks import default_chunk_size as default_chunk_size
from ._chunks import device_chunk_size as device_chunk_size
from ._chunks import monte_carlo_chunk_size as monte_carlo_chunk_size
from ._cluster import ClusterRunError as ClusterRunError
from ._cluster import check_netcdf_output as check_netcdf_output
from ._cpu_vectors import prefer_wide_cpu_vectors as prefer_wide_cpu_vectors
from ._design import LIMIT_STATISTICS as LIMIT_STATISTICS
from ._design import DesignResult as DesignResult
from ._design import constrained_response as constrained_response
from ._design import design_bounds as design_bounds
from ._design import expected_response as expected_response
from ._design import forward_mode_gradient as forward_mode_gradient
from ._design import gradient_check as gradient_check
from ._design import optimise_design as optimise_design
from ._design import penalised_objective as penalised_objective
from ._design_check import BOUND_TOLERANCE as BOUND_TOLERANCE
from ._design_check import GRADIENT_TOLERANCE as GRADIENT_TOLERANCE
from ._design_check import design_gradient_check as design_gradient_check
from ._design_check import percentile_disp_gradient_check as percentile_disp_gradient_check
from ._design_contact import CONTACT_TOLERANCE as CONTACT_TOLERANCE
from ._design_contact import restrainer_contact_check as restrainer_contact_check
from ._design_kinks import kink_gradient_check as kink_gradient_check
from ._design_problem import default_design_problem as default_design_problem
from ._design_sweep import design_sweep as design_sweep
from ._design_sweep import design_sweep_distributed as design_sweep_distributed
from ._design_sweep import open_sweep as open_sweep
from ._design_sweep import sweep_dataset as sweep_dataset
from ._design_sweep import sweep_objective as sweep_objective
from ._design_sweep import sweep_start as sweep_start
from ._distributed import monte_carlo_distributed as monte_carlo_distributed
from ._distributed import monte_carlo_levels_distributed as monte_carlo_levels_distributed
from ._fragility import FragilityBand as FragilityBand
from ._fragility import FragilityFit as FragilityFit
from ._fragility import check_exceedances as check_exceedances
from ._fragility import fit_fragility as fit_fragility
from ._fragility import fragility_band as fragility_band
from ._intensity_levels import check_levels as check_levels
from ._intensity_levels import exceedance_counts as exceedance_counts
from ._intensity_levels import levels_dataset as levels_dataset
from ._intensity_levels import monte_carlo_levels as monte_carlo_levels
from ._intensity_levels import save_levels as save_levels
from ._montecarlo import monte_carlo as monte_carlo
from ._motion_source import monte_carlo_motion as monte_carlo_motion
from ._motion_source import motions_at_level as motions_at_level
from ._record_set import RecordSet as RecordSet
from ._record_set import record_set as record_set
from ._results import FORMATS as FORMATS
from ._results import MonteCarloResult as MonteCarloResult
from ._results import check_output_path as check_output_path
from ._save import save_montecarlo as save_montecarlo
from ._spectrum_match import COMBINATIONS as COMBINATIONS
from ._spectrum_match import DesignSpectrum as DesignSpectrum
from ._spectrum_match import TabulatedSpectrum as TabulatedSpectrum
from ._spectrum_match import amplitude_factors as amplitude_factors
from ._spectrum_match import check_factor_limit as check_factor_limit
from ._spectrum_match import check_period_range as check_period_range
from ._spectrum_match import combined_spectrum as combined_spectrum
from ._spectrum_match import suite_statistic as suite_statistic
from ._suite_cases import open_suite_cases as open_suite_cases
from ._suite_cases import save_suite_cases as save_suite_cases
from ._suite_cases import suite_cases_distributed as suite_cases_distributed
from ._suites import SuiteResult as SuiteResult
from ._suites import open_suite as open_suite
from ._suites import save_suite as save_suite
from ._suites import suite_dataset as suite_dataset
from ._suites import suite_peaks as suite_peaks
from ._suites import suite_peaks_distributed as suite_peaks_distributed
from ._sweep import SweepResult as SweepResult
from ._sweep import building_peaks as building_peaks
from ._sweep import building_sweep as building_sweep
from ._sweep import pad_signals as pad_signals
from ._sweep import simulate_batch as simulate_batch
from ._sweep import stack_systems as stack_systems
