"""Plots of results (loops, Monte Carlo, design); matplotlib only, nothing traced."""

from ._design_plot import plot_design as plot_design
from ._fit_plot import fit_figure as fit_figure
from ._fit_plot import plot_fit as plot_fit
from ._fragility_plot import plot_fragility as plot_fragility
from ._loop_plot import plot_loop as plot_loop
from ._montecarlo_plot import montecarlo_figure as montecarlo_figure
from ._montecarlo_plot import plot_montecarlo as plot_montecarlo
from ._parameter_units import PARAMETER_SYMBOLS as PARAMETER_SYMBOLS
from ._parameter_units import parameter_unit as parameter_unit
from ._residual_plot import ROBUST_PERCENTILES as ROBUST_PERCENTILES
from ._residual_plot import residual_maps as residual_maps
from ._residual_plot import robust_limits as robust_limits
