"""teflon-jax: differentiable simulation of PTFE sliding bearings for seismic isolation.

Implements and extends Constantinou, Mokha & Reinhorn (1990), "Teflon bearings in base
isolation II: Modeling", J. Struct. Eng. 116(2). SI units throughout (m, s, N, Pa).

The sub-packages and the names below load on first use (PEP 562), so that `import teflon_jax`
(and the command line's `--help`) does not import JAX.
"""

import importlib as _importlib

_SUBPACKAGES = (
    "bearing",
    "catalogue",
    "elements",
    "excitation",
    "formats",
    "paper",
    "report",
    "solver",
    "structures",
    "studies",
    "systems",
    "tables",
    "units",
    "validation",
)

_EXPORTS = {
    # sub-package: the names re-exported from it
    "bearing": (
        "BREAKAWAY_THRESHOLD",
        "DEFAULT_YIELD_DISP",
        "Backlash",
        "BoucWen",
        "ConcaveSurface",
        "DirectionAsymmetry",
        "FrictionalHeating",
        "FrictionParameters",
        "PressureDependence",
        "SlidingBearing",
        "Wear",
        "anisotropic_friction",
        "bouc_wen_exact_update",
        "bouc_wen_rate",
        "bouc_wen_reversal_length",
        "check_bearing",
        "concave_surface",
        "coulomb_friction",
        "paper_bearing",
        "park_rate",
        "sliding_friction",
    ),
    "excitation": (
        "AbstractBiaxialMotion",
        "AbstractMotion",
        "AbstractUniaxialMotion",
        "FigureEightMotion",
        "GroundMotion",
        "IntensityMeasures",
        "ResponseSpectrum",
        "Signal",
        "SineMotion",
        "StochasticGroundMotion",
        "TabulatedBiaxialMotion",
        "TabulatedMotion",
        "TriangleMotion",
        "as_signal",
        "envelope",
        "fourier_amplitude",
        "integrate_motion",
        "intensity_measures",
        "power_spectral_density",
        "response_spectrum",
        "sample_times",
        "stationary_variance",
        "tabulated_motion",
        "uniform_signal",
        "white_noise_intensity",
    ),
    "formats": (
        "BearingPosterior",
        "Protocol",
        "TestRecord",
        "external_data_dir",
        "load_bearing",
        "load_bearing_posterior",
        "load_record",
        "parse_protocol",
        "read_at2",
        "read_single_column",
        "read_test_record",
        "read_two_column",
        "save_bearing",
        "test_record_from_arrays",
        "write_test_record",
    ),
    "paper": (
        "reproduce",
    ),
    "solver": (
        "AbstractSteppedSystem",
        "RiccatiNewmark",
    ),
    "structures": (
        "signal_from_motion",
        "superstructure_matrices",
    ),
    "studies": (
        "MonteCarloResult",
        "SweepResult",
        "building_sweep",
        "gradient_check",
        "monte_carlo",
        "monte_carlo_motion",
        "optimise_design",
        "pad_signals",
        "record_set",
        "simulate_batch",
        "stack_systems",
    ),
    "systems": (
        "FRICTION_MODELS",
        "BearingTestResult",
        "BearingTestSystem",
        "SampledPath",
        "StructureOnSliders",
        "StructureResponse",
        "building_response_quantities",
        "imposed_path_test",
        "initial_state",
        "isolated_structure",
        "rigid_mass",
        "sample_velocity",
        "sampled_path",
        "simulate_history",
        "six_storey_building",
        "structure_on_sliders",
    ),
    "tables": (
        "BuildingData",
        "FrictionTable",
        "Interface",
        "friction_table",
        "interface_parameters",
        "load_table1",
        "load_table2",
        "table1_parameters",
    ),
}

_RENAMED = {
    "sample_ground_motions": ("excitation", "sample"),  # public name differs
}

_WHERE = {name: (package, name) for package, names in _EXPORTS.items() for name in names}
_WHERE.update(_RENAMED)

__all__ = sorted((*_SUBPACKAGES, *_WHERE))


def __getattr__(name):
    if name in _SUBPACKAGES:
        return _importlib.import_module(f".{name}", __name__)
    if name not in _WHERE:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    package, attribute = _WHERE[name]
    value = getattr(_importlib.import_module(f".{package}", __name__), attribute)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
