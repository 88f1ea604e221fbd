"""`RiccatiNewmark`: the diffrax solver whose step is not bounded by the stiffness of Z;
`implicit_root`: the implicit derivative of a step's balance, whatever iteration found it."""

from ._implicit import implicit_root as implicit_root
from ._park_path import park_path_update as park_path_update
from ._park_path import park_substeps as park_substeps
from ._park_update import park_exact_update as park_exact_update
from ._riccati_newmark import AbstractSteppedSystem as AbstractSteppedSystem
from ._riccati_newmark import RiccatiNewmark as RiccatiNewmark
from ._riccati_newmark import require_riccati_form as require_riccati_form
from ._solve import solve_on_grid as solve_on_grid
from ._solve import solve_with_controller as solve_with_controller
