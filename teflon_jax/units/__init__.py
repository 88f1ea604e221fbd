"""Named unit constants (factors to SI) and the quantity parser used at the boundaries."""

from ._constants import CM as CM
from ._constants import FOOT as FOOT
from ._constants import INCH as INCH
from ._constants import KIP as KIP
from ._constants import KN as KN
from ._constants import KPA as KPA
from ._constants import KSI as KSI
from ._constants import LBF as LBF
from ._constants import MM as MM
from ._constants import MPA as MPA
from ._constants import PSI as PSI
from ._constants import STANDARD_GRAVITY as STANDARD_GRAVITY
from ._quantity import UNITS as UNITS
from ._quantity import example as example
from ._quantity import is_unit as is_unit
from ._quantity import parse_quantity as parse_quantity
from ._quantity import unit_factor as unit_factor
