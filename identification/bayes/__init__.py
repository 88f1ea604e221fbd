"""Bayesian identification of the 1990 model's constants: NUTS posteriors through the fitter's
simulator, with documented priors, convergence checks and non-identifiability reports."""

from ._fit import MIN_SAMPLES_PER_PARAMETER as MIN_SAMPLES_PER_PARAMETER
from ._fit import fit_bayes as fit_bayes
from ._priors import PHYSICAL as PHYSICAL
from ._priors import ParameterPrior as ParameterPrior
from ._priors import build_priors as build_priors
from ._result import BayesResult as BayesResult
from ._sampler import SamplingInterrupted as SamplingInterrupted
from ._series import F_MAX_RANGE as F_MAX_RANGE
from ._series import fit_series_bayes as fit_series_bayes
from ._series import series_priors as series_priors
