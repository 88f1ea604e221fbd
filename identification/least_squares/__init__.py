"""Bounded least squares with optimistix: bijections to unconstrained space, covariance, summaries."""

from ._covariance import LeastSquaresResult as LeastSquaresResult
from ._covariance import correlation_from_covariance as correlation_from_covariance
from ._covariance import covariance_from_jacobian as covariance_from_jacobian
from ._least_squares import fit_least_squares as fit_least_squares
from ._least_squares import fit_least_squares_batch as fit_least_squares_batch
from ._transform import Bounds as Bounds
from ._transform import check_bounds as check_bounds
