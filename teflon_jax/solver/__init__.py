"""`RiccatiNewmark`: the diffrax solver whose step is not bounded by the stiffness of Z;
`implicit_root`: the implicit derivative of a step's balance, whatever iteration found it;
the iterations on a step's balance, chosen by the shape of its unknowns (`bracketed_newton`,
`damped_newton`, `planar_newton`, `coupled_newton`) with their structured solves
(`sherman_morrison`, `woodbury`, `solve_blocks`), and Coulomb friction's step
(`coulomb_disc_forces`)."""

from ._coupled import affine as affine
from ._coupled import block_matvec as block_matvec
from ._coupled import coulomb_disc_forces as coulomb_disc_forces
from ._coupled import coupled_newton as coupled_newton
from ._coupled import matvec as matvec
from ._coupled import solve_blocks as solve_blocks
from ._implicit import implicit_root as implicit_root
from ._newton import RESCUE_ITERATIONS as RESCUE_ITERATIONS
from ._newton import RESCUE_SMALLEST as RESCUE_SMALLEST
from ._newton import SMALLEST_STEP as SMALLEST_STEP
from ._newton import bracketed_newton as bracketed_newton
from ._newton import damped_newton as damped_newton
from ._newton import sherman_morrison as sherman_morrison
from ._park_path import park_path_update as park_path_update
from ._park_path import park_substeps as park_substeps
from ._park_update import park_exact_update as park_exact_update
from ._park_update import park_exact_update_and_slope as park_exact_update_and_slope
from ._planar import SECANT_ITERATIONS as SECANT_ITERATIONS
from ._planar import broyden_blocks as broyden_blocks
from ._planar import inverse2 as inverse2
from ._planar import planar_newton as planar_newton
from ._planar import woodbury as woodbury
from ._riccati_newmark import AbstractSteppedSystem as AbstractSteppedSystem
from ._riccati_newmark import RiccatiNewmark as RiccatiNewmark
from ._riccati_newmark import require_riccati_form as require_riccati_form
from ._riccati_newmark import structure_step_end as structure_step_end
from ._solve import solve_on_grid as solve_on_grid
from ._solve import solve_with_controller as solve_with_controller
