"""Bearing physics: Eq. 1 friction, the hysteretic variable Z (Eqs. 3, 8-9), breakaway (Eq. 17),
anisotropy, stacks, and the optional parts beyond the 1990 model (pressure dependence,
frictional heating, wear, direction asymmetry, backlash), and the concave surface of the
friction pendulum (single, and double or triple as sliders in series)."""

from ._bearing import BREAKAWAY_THRESHOLD as BREAKAWAY_THRESHOLD
from ._bearing import DEFAULT_YIELD_DISP as DEFAULT_YIELD_DISP
from ._bearing import EFFECT_FIELDS as EFFECT_FIELDS
from ._bearing import SlidingBearing as SlidingBearing
from ._bearing import check_bearing as check_bearing
from ._bearing import check_hysteresis as check_hysteresis
from ._bearing import paper_bearing as paper_bearing
from ._bearing import sliding_speed as sliding_speed
from ._bounds import PARAMETER_BOUNDS as PARAMETER_BOUNDS
from ._bounds import ConstantBounds as ConstantBounds
from ._effects import AMBIENT_TEMPERATURE as AMBIENT_TEMPERATURE
from ._effects import STEEL_CONDUCTIVITY as STEEL_CONDUCTIVITY
from ._effects import STEEL_DIFFUSIVITY as STEEL_DIFFUSIVITY
from ._effects import Backlash as Backlash
from ._effects import DirectionAsymmetry as DirectionAsymmetry
from ._effects import FrictionalHeating as FrictionalHeating
from ._effects import PressureDependence as PressureDependence
from ._effects import Wear as Wear
from ._effects import advance_heat_states as advance_heat_states
from ._effects import backlash_update as backlash_update
from ._effects import heat_kernel_exponentials as heat_kernel_exponentials
from ._effects import kumar_temperature_factor as kumar_temperature_factor
from ._effects import surface_temperature_coefficient as surface_temperature_coefficient
from ._elementary import vector_arctan as vector_arctan
from ._friction import FrictionParameters as FrictionParameters
from ._friction import anisotropic_friction as anisotropic_friction
from ._friction import coulomb_friction as coulomb_friction
from ._friction import sliding_friction as sliding_friction
from ._hysteresis import BoucWen as BoucWen
from ._hysteresis import bouc_wen_exact_update as bouc_wen_exact_update
from ._hysteresis import bouc_wen_rate as bouc_wen_rate
from ._hysteresis import bouc_wen_reversal_length as bouc_wen_reversal_length
from ._hysteresis import park_rate as park_rate
from ._isolators import ISOLATORS as ISOLATORS
from ._isolators import SERIES_PENDULUMS as SERIES_PENDULUMS
from ._isolators import check_series_pendulum as check_series_pendulum
from ._isolators import series_pendulum_class as series_pendulum_class
from ._pendulum import ConcaveSurface as ConcaveSurface
from ._pendulum import concave_surface as concave_surface
from ._series_pendulum import DoublePendulum as DoublePendulum
from ._series_pendulum import SeriesPendulum as SeriesPendulum
from ._series_pendulum import check_double_pendulum as check_double_pendulum
from ._surface import SURFACE_PARTS as SURFACE_PARTS
from ._surface import SurfaceParts as SurfaceParts
from ._surface import check_friction as check_friction
from ._surface import check_surface_parts as check_surface_parts
from ._surface import surface_coefficients as surface_coefficients
from ._triple_pendulum import STOP_STIFFNESS_RATIO as STOP_STIFFNESS_RATIO
from ._triple_pendulum import TriplePendulum as TriplePendulum
from ._triple_pendulum import check_triple_pendulum as check_triple_pendulum
from ._triple_pendulum import triple_pendulum_backbone as triple_pendulum_backbone
