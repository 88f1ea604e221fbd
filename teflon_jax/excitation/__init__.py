"""What drives a system: imposed test motions, time signals, recorded and stochastic ground
motions, their intensity measures and spectra."""

from ._ground_motion import GroundMotion as GroundMotion
from ._ground_motion import IntensityMeasures as IntensityMeasures
from ._ground_motion import integrate_motion as integrate_motion
from ._ground_motion import intensity_measures as intensity_measures
from ._imposed import AbstractMotion as AbstractMotion
from ._imposed import FigureEightMotion as FigureEightMotion
from ._imposed import SineMotion as SineMotion
from ._imposed import TabulatedMotion as TabulatedMotion
from ._imposed import TriangleMotion as TriangleMotion
from ._imposed import tabulated_motion as tabulated_motion
from ._signal import Signal as Signal
from ._signal import as_signal as as_signal
from ._signal import uniform_signal as uniform_signal
from ._spectra import ResponseSpectrum as ResponseSpectrum
from ._spectra import fourier_amplitude as fourier_amplitude
from ._spectra import response_spectrum as response_spectrum
from ._stochastic import StochasticGroundMotion as StochasticGroundMotion
from ._stochastic import envelope as envelope
from ._stochastic import num_time_steps as num_time_steps
from ._stochastic import power_spectral_density as power_spectral_density
from ._stochastic import sample as sample
from ._stochastic import sample_times as sample_times
from ._stochastic import stationary_variance as stationary_variance
from ._stochastic import white_noise_intensity as white_noise_intensity
