"""Named unit constants (factors to SI) and the quantity parser used at the boundaries."""

from ._units import (
    CM as CM,
)
from ._units import (
    FOOT as FOOT,
)
from ._units import (
    INCH as INCH,
)
from ._units import (
    KIP as KIP,
)
from ._units import (
    KN as KN,
)
from ._units import (
    KPA as KPA,
)
from ._units import (
    KSI as KSI,
)
from ._units import (
    LBF as LBF,
)
from ._units import (
    MM as MM,
)
from ._units import (
    MPA as MPA,
)
from ._units import (
    PSI as PSI,
)
from ._units import (
    STANDARD_GRAVITY as STANDARD_GRAVITY,
)
from ._units import (
    UNITS as UNITS,
)
from ._units import (
    parse_quantity as parse_quantity,
)
from ._units import (
    unit_factor as unit_factor,
)
