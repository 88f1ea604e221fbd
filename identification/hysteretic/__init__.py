"""Identification of a generic hysteretic system: a force-driven oscillator with Bouc-Wen
hysteresis (the Noel & Schoukens 2016 benchmark), with the same least-squares machinery as the
bearing fit."""

from ._fit import HystereticFit as HystereticFit
from ._fit import fit_hysteretic as fit_hysteretic
from ._fit import linear_start as linear_start
from ._model import BENCHMARK as BENCHMARK
from ._model import PARAMETER_NAMES as PARAMETER_NAMES
from ._model import PARAMETER_UNITS as PARAMETER_UNITS
from ._model import fine_input as fine_input
from ._model import simulate_hysteretic as simulate_hysteretic
