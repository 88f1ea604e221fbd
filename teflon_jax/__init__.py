"""teflon-jax: differentiable simulation of PTFE sliding bearings for seismic isolation.

Implements and extends Constantinou, Mokha & Reinhorn (1990), "Teflon bearings in base
isolation II: Modeling", J. Struct. Eng. 116(2). SI units throughout (m, s, N, Pa).
"""

from ._bearing import (
    BREAKAWAY_THRESHOLD as BREAKAWAY_THRESHOLD,
    DEFAULT_YIELD_DISP as DEFAULT_YIELD_DISP,
    SlidingBearing as SlidingBearing,
    check_bearing as check_bearing,
    paper_bearing as paper_bearing,
)
from ._bearing_test import (
    BearingTestResult as BearingTestResult,
    BearingTestSystem as BearingTestSystem,
    simulate_bearing_test as simulate_bearing_test,
)
from ._friction import (
    FrictionParameters as FrictionParameters,
    anisotropic_friction as anisotropic_friction,
    coulomb_friction as coulomb_friction,
    sliding_friction as sliding_friction,
)
from ._hysteresis import (
    BoucWen as BoucWen,
    bouc_wen_exact_update as bouc_wen_exact_update,
    bouc_wen_rate as bouc_wen_rate,
    park_rate as park_rate,
)
from ._motion import (
    AbstractMotion as AbstractMotion,
    FigureEightMotion as FigureEightMotion,
    Signal as Signal,
    SineMotion as SineMotion,
    TabulatedMotion as TabulatedMotion,
    TriangleMotion as TriangleMotion,
    as_signal as as_signal,
    uniform_signal as uniform_signal,
    tabulated_motion as tabulated_motion,
)
from ._solver import AbstractSteppedSystem as AbstractSteppedSystem, RiccatiNewmark as RiccatiNewmark
from ._tables import (
    BuildingData as BuildingData,
    FrictionTable as FrictionTable,
    Interface as Interface,
    friction_table as friction_table,
    interface_parameters as interface_parameters,
    load_table1 as load_table1,
    load_table2 as load_table2,
    table1_parameters as table1_parameters,
)
from . import units as units
from ._structure import (
    FRICTION_MODELS as FRICTION_MODELS,
    StructureOnSliders as StructureOnSliders,
    StructureResponse as StructureResponse,
    initial_state as initial_state,
    simulate_structure as simulate_structure,
    structure_on_sliders as structure_on_sliders,
)
from ._records import (
    Protocol as Protocol,
    TestRecord as TestRecord,
    parse_protocol as parse_protocol,
    read_test_record as read_test_record,
    test_record_from_arrays as test_record_from_arrays,
    write_test_record as write_test_record,
)
from ._ground_motion import (
    GroundMotion as GroundMotion,
    IntensityMeasures as IntensityMeasures,
    integrate_motion as integrate_motion,
    intensity_measures as intensity_measures,
)
from ._ground_motion_io import (
    external_data_dir as external_data_dir,
    load_record as load_record,
    read_at2 as read_at2,
    read_single_column as read_single_column,
    read_two_column as read_two_column,
)
from ._spectra import (
    ResponseSpectrum as ResponseSpectrum,
    fourier_amplitude as fourier_amplitude,
    response_spectrum as response_spectrum,
)
from ._stochastic import (
    StochasticGroundMotion as StochasticGroundMotion,
    envelope as envelope,
    power_spectral_density as power_spectral_density,
    sample as sample_ground_motions,
    sample_times as sample_times,
    stationary_variance as stationary_variance,
    white_noise_intensity as white_noise_intensity,
)
from ._models import (
    BuildingResponse as BuildingResponse,
    building_response_quantities as building_response_quantities,
    rigid_mass as rigid_mass,
    signal_from_motion as signal_from_motion,
    six_storey_building as six_storey_building,
    superstructure_matrices as superstructure_matrices,
)
from ._batch import (
    SweepResult as SweepResult,
    building_sweep as building_sweep,
    pad_signals as pad_signals,
    simulate_batch as simulate_batch,
    stack_systems as stack_systems,
)
from ._reproduce import reproduce as reproduce
from ._montecarlo import (
    MonteCarloResult as MonteCarloResult,
    isolated_structure as isolated_structure,
    monte_carlo as monte_carlo,
    record_set as record_set,
)
from ._design import optimise_design as optimise_design, gradient_check as gradient_check
