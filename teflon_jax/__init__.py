"""teflon-jax: differentiable simulation of PTFE sliding bearings for seismic isolation.

Implements and extends Constantinou, Mokha & Reinhorn (1990), "Teflon bearings in base
isolation II: Modeling", J. Struct. Eng. 116(2). SI units throughout (m, s, N, Pa).
"""

from . import units as units
from ._batch import (
    SweepResult as SweepResult,
)
from ._batch import (
    building_sweep as building_sweep,
)
from ._batch import (
    pad_signals as pad_signals,
)
from ._batch import (
    simulate_batch as simulate_batch,
)
from ._batch import (
    stack_systems as stack_systems,
)
from ._bearing import (
    BREAKAWAY_THRESHOLD as BREAKAWAY_THRESHOLD,
)
from ._bearing import (
    DEFAULT_YIELD_DISP as DEFAULT_YIELD_DISP,
)
from ._bearing import (
    SlidingBearing as SlidingBearing,
)
from ._bearing import (
    check_bearing as check_bearing,
)
from ._bearing import (
    paper_bearing as paper_bearing,
)
from ._bearing_test import (
    BearingTestResult as BearingTestResult,
)
from ._bearing_test import (
    BearingTestSystem as BearingTestSystem,
)
from ._bearing_test import (
    force_along_path as force_along_path,
)
from ._bearing_test import (
    simulate_bearing_test as simulate_bearing_test,
)
from ._design import gradient_check as gradient_check
from ._design import optimise_design as optimise_design
from ._friction import (
    FrictionParameters as FrictionParameters,
)
from ._friction import (
    anisotropic_friction as anisotropic_friction,
)
from ._friction import (
    coulomb_friction as coulomb_friction,
)
from ._friction import (
    sliding_friction as sliding_friction,
)
from ._ground_motion import (
    GroundMotion as GroundMotion,
)
from ._ground_motion import (
    IntensityMeasures as IntensityMeasures,
)
from ._ground_motion import (
    integrate_motion as integrate_motion,
)
from ._ground_motion import (
    intensity_measures as intensity_measures,
)
from ._ground_motion_io import (
    external_data_dir as external_data_dir,
)
from ._ground_motion_io import (
    load_record as load_record,
)
from ._ground_motion_io import (
    read_at2 as read_at2,
)
from ._ground_motion_io import (
    read_single_column as read_single_column,
)
from ._ground_motion_io import (
    read_two_column as read_two_column,
)
from ._hysteresis import (
    BoucWen as BoucWen,
)
from ._hysteresis import (
    bouc_wen_exact_update as bouc_wen_exact_update,
)
from ._hysteresis import (
    bouc_wen_rate as bouc_wen_rate,
)
from ._hysteresis import (
    bouc_wen_reversal_length as bouc_wen_reversal_length,
)
from ._hysteresis import (
    park_rate as park_rate,
)
from ._models import (
    BuildingResponse as BuildingResponse,
)
from ._models import (
    building_response_quantities as building_response_quantities,
)
from ._models import (
    rigid_mass as rigid_mass,
)
from ._models import (
    signal_from_motion as signal_from_motion,
)
from ._models import (
    six_storey_building as six_storey_building,
)
from ._models import (
    superstructure_matrices as superstructure_matrices,
)
from ._montecarlo import (
    MonteCarloResult as MonteCarloResult,
)
from ._montecarlo import (
    isolated_structure as isolated_structure,
)
from ._montecarlo import (
    monte_carlo as monte_carlo,
)
from ._montecarlo import (
    monte_carlo_motion as monte_carlo_motion,
)
from ._montecarlo import (
    record_set as record_set,
)
from ._motion import (
    AbstractMotion as AbstractMotion,
)
from ._motion import (
    FigureEightMotion as FigureEightMotion,
)
from ._motion import (
    Signal as Signal,
)
from ._motion import (
    SineMotion as SineMotion,
)
from ._motion import (
    TabulatedMotion as TabulatedMotion,
)
from ._motion import (
    TriangleMotion as TriangleMotion,
)
from ._motion import (
    as_signal as as_signal,
)
from ._motion import (
    tabulated_motion as tabulated_motion,
)
from ._motion import (
    uniform_signal as uniform_signal,
)
from ._records import (
    Protocol as Protocol,
)
from ._records import (
    TestRecord as TestRecord,
)
from ._records import (
    parse_protocol as parse_protocol,
)
from ._records import (
    read_test_record as read_test_record,
)
from ._records import (
    test_record_from_arrays as test_record_from_arrays,
)
from ._records import (
    write_test_record as write_test_record,
)
from ._reproduce import reproduce as reproduce
from ._solver import AbstractSteppedSystem as AbstractSteppedSystem
from ._solver import RiccatiNewmark as RiccatiNewmark
from ._spectra import (
    ResponseSpectrum as ResponseSpectrum,
)
from ._spectra import (
    fourier_amplitude as fourier_amplitude,
)
from ._spectra import (
    response_spectrum as response_spectrum,
)
from ._stochastic import (
    StochasticGroundMotion as StochasticGroundMotion,
)
from ._stochastic import (
    envelope as envelope,
)
from ._stochastic import (
    power_spectral_density as power_spectral_density,
)
from ._stochastic import (
    sample as sample_ground_motions,  # noqa: F401  (public name differs from the module)
)
from ._stochastic import (
    sample_times as sample_times,
)
from ._stochastic import (
    stationary_variance as stationary_variance,
)
from ._stochastic import (
    white_noise_intensity as white_noise_intensity,
)
from ._structure import (
    FRICTION_MODELS as FRICTION_MODELS,
)
from ._structure import (
    StructureOnSliders as StructureOnSliders,
)
from ._structure import (
    StructureResponse as StructureResponse,
)
from ._structure import (
    initial_state as initial_state,
)
from ._structure import (
    simulate_structure as simulate_structure,
)
from ._structure import (
    structure_on_sliders as structure_on_sliders,
)
from ._tables import (
    BuildingData as BuildingData,
)
from ._tables import (
    FrictionTable as FrictionTable,
)
from ._tables import (
    Interface as Interface,
)
from ._tables import (
    friction_table as friction_table,
)
from ._tables import (
    interface_parameters as interface_parameters,
)
from ._tables import (
    load_table1 as load_table1,
)
from ._tables import (
    load_table2 as load_table2,
)
from ._tables import (
    table1_parameters as table1_parameters,
)
