"""Value checks shared by the model builders: concrete inputs are checked, traced ones pass."""

from ._checks import concrete as concrete
from ._checks import given_options as given_options
from ._checks import require as require
from ._checks import require_positive as require_positive
