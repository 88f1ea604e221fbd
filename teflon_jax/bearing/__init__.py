"""Bearing physics: Eq. 1 friction, the hysteretic variable Z (Eqs. 3, 8-9), breakaway (Eq. 17),
anisotropy, stacks, and the Table 1 interfaces."""

from ._bearing import BREAKAWAY_THRESHOLD as BREAKAWAY_THRESHOLD
from ._bearing import DEFAULT_YIELD_DISP as DEFAULT_YIELD_DISP
from ._bearing import SlidingBearing as SlidingBearing
from ._bearing import check_bearing as check_bearing
from ._bearing import check_hysteresis as check_hysteresis
from ._bearing import paper_bearing as paper_bearing
from ._bearing import sliding_speed as sliding_speed
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
