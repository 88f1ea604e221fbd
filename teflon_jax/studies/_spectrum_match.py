"""Amplitude scaling of record pairs to a target spectrum over a period range.

Each pair's two horizontal components (x, y) are combined into one spectrum of 5 %-damped
pseudo-acceleration PSA(T) [m/s^2]:

- "srss": PSA_srss(T) = sqrt(PSA_x(T)^2 + PSA_y(T)^2), the square root of the sum of the
  squares of the components' spectra;
- "rotd100": PSA_rotd100(T) = omega^2 max_t |(u_x(t), u_y(t))|, the largest response of the
  oscillator over all horizontal directions (Boore 2010, "Orientation-independent, nongeometric-
  mean measures of seismic intensity from two horizontal components of motion", BSSA 100(4)),
  u_x, u_y the displacements of one oscillator under the two components (omega = 2 pi / T).

A pair's amplitude factor is the smallest f for which f PSA_i(T) >= r S(T) at every period T
of the checked grid in [T_low, T_high], S the target and r the ratio the scaled spectrum may
not fall below (e.g. 0.9: not more than 10 % below the target):

    f_i = max_T r S(T) / PSA_i(T)                                (one factor per pair),
    f   = max_T r S(T) / stat_i PSA_i(T)                         (one factor for the suite),

stat the mean or the maximum over the pairs. Which ratio, statistic and range a design rule
asks for is the user's choice; nothing here claims a code's compliance. The two-parameter
design shape (`DesignSpectrum`) is the one written out in its docstring.
"""

import dataclasses

import numpy as np

from ..excitation import oscillator_displacement

COMBINATIONS = ("srss", "rotd100")
STATISTICS = ("mean", "max")


@dataclasses.dataclass(frozen=True)
class TabulatedSpectrum:
    """A target PSA(T) [m/s^2] given at `periods` [s] (strictly increasing), linear between them."""

    periods: np.ndarray
    acceleration: np.ndarray

    @property
    def period_range(self) -> tuple[float, float]:
        return float(self.periods[0]), float(self.periods[-1])

    def __call__(self, periods) -> np.ndarray:
        return np.interp(np.asarray(periods, float), self.periods, self.acceleration)

    def grid(self, low: float, high: float) -> np.ndarray:
        """`low`, the tabulated periods strictly between, `high`: where the target has corners."""
        inside = self.periods[(self.periods > low) & (self.periods < high)]
        return np.concatenate([[low], inside, [high]])


@dataclasses.dataclass(frozen=True)
class DesignSpectrum:
    """The two-parameter design shape from S_DS, S_D1 [m/s^2] and the long period T_L [s],
    with T_0 = 0.2 S_D1 / S_DS and T_S = S_D1 / S_DS:

        S(T) = S_DS (0.4 + 0.6 T / T_0)  for T < T_0,     S_DS          for T_0 <= T <= T_S,
        S(T) = S_D1 / T                  for T_S < T <= T_L,  S_D1 T_L / T^2 for T > T_L

    (the shape of ASCE/SEI 7, Sec. 11.4.6, written out here; the values of S_DS, S_D1 and T_L
    are the user's)."""

    s_ds: float
    s_d1: float
    long_period: float

    def __post_init__(self):
        for name in ("s_ds", "s_d1", "long_period"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0):
                raise ValueError(f"{name}: must be finite and > 0, got {value}.")
        if not self.long_period > self.s_d1 / self.s_ds:
            raise ValueError(f"long_period: T_L = {self.long_period:g} s must be above T_S = S_D1 / S_DS = "
                             f"{self.s_d1 / self.s_ds:g} s.")

    @property
    def corners(self) -> tuple[float, float, float]:
        return 0.2 * self.s_d1 / self.s_ds, self.s_d1 / self.s_ds, self.long_period

    @property
    def period_range(self) -> tuple[float, float]:
        return 0.0, np.inf

    def __call__(self, periods) -> np.ndarray:
        t = np.asarray(periods, float)
        t0, ts, tl = self.corners
        return np.select([t < t0, t <= ts, t <= tl],
                         [self.s_ds * (0.4 + 0.6 * t / t0), np.full_like(t, self.s_ds), self.s_d1 / np.maximum(t, ts)],
                         self.s_d1 * tl / np.maximum(t, tl) ** 2)

    def grid(self, low: float, high: float, count: int = 60) -> np.ndarray:
        """60 periods spaced evenly in log between `low` and `high`, and the corners between."""
        corners = [c for c in self.corners if low < c < high]
        return np.unique(np.concatenate([np.geomspace(low, high, count), corners]))


def check_period_range(target, low: float, high: float, where: str = "period range") -> np.ndarray:
    """The periods [s] at which the scaled spectra are checked (`target.grid`), once `low` <
    `high` lie within the periods the target is given at; `ValueError` naming `where`."""
    first, last = target.period_range
    if not (np.isfinite(low) and np.isfinite(high) and 0 < low < high):
        raise ValueError(f"{where}: need 0 < LOW < HIGH, got {low:g} s, {high:g} s.")
    if low < first or high > last:
        raise ValueError(f"{where}: {low:g}-{high:g} s lies outside the target spectrum's periods "
                         f"{first:g}-{last:g} s; give a range within them or a wider spectrum.")
    return target.grid(low, high)


def combined_spectrum(ax, ay, time_step: float, periods, *, method: str = "srss", damping: float = 0.05) -> np.ndarray:
    """The pair's combined 5 %-damped PSA(T) [m/s^2] at `periods` [s] (module docstring);
    `ay` None: the x component's PSA alone. `ax`, `ay` (nt,) [m/s^2] every `time_step` [s]."""
    if method not in COMBINATIONS:
        raise ValueError(f"method: unknown {method!r}; accepted: {', '.join(COMBINATIONS)}.")
    periods = np.asarray(periods, float)
    omega2 = (2 * np.pi / periods) ** 2
    ux = oscillator_displacement(ax, time_step, periods, damping=damping)
    if ay is None:
        return omega2 * np.abs(ux).max(axis=0)
    uy = oscillator_displacement(ay, time_step, periods, damping=damping)
    if method == "srss":
        return omega2 * np.hypot(np.abs(ux).max(axis=0), np.abs(uy).max(axis=0))
    return omega2 * np.hypot(ux, uy).max(axis=0)


def amplitude_factors(spectra, target, *, min_ratio: float = 1.0, per: str = "pair",
                      statistic: str = "mean") -> tuple[np.ndarray, np.ndarray]:
    """(factors (P,), index of the governing period (P,)) that lift the pairs' combined
    `spectra` (P, K) [m/s^2] to `min_ratio` x `target` (K,) [m/s^2] at every checked period
    (module docstring): `per` "pair" (each its own factor) or "suite" (one factor on the
    `statistic` "mean" or "max" over the pairs). `ValueError` for a zero spectral value."""
    spectra, target = np.asarray(spectra, float), np.asarray(target, float)
    if per not in ("pair", "suite") or statistic not in STATISTICS:
        raise ValueError(f"per / statistic: expected 'pair' or 'suite' / {' or '.join(STATISTICS)}, got "
                         f"{per!r} / {statistic!r}.")
    if not (np.isfinite(min_ratio) and min_ratio > 0):
        raise ValueError(f"min_ratio: must be finite and > 0, got {min_ratio}.")
    if np.any(spectra <= 0):
        pair, k = np.argwhere(spectra <= 0)[0]
        raise ValueError(f"spectra: pair {pair + 1} has no spectral acceleration at check period {k + 1}; "
                         "it cannot be scaled to the target.")
    if per == "suite":
        suite = spectra.mean(axis=0) if statistic == "mean" else spectra.max(axis=0)
        needed = min_ratio * target / suite
        k = int(np.argmax(needed))
        return np.full(spectra.shape[0], needed[k]), np.full(spectra.shape[0], k)
    needed = min_ratio * target[None, :] / spectra
    return needed.max(axis=1), needed.argmax(axis=1)


def check_factor_limit(names, factors, max_factor: float | None, where: str = "max factor") -> None:
    """`ValueError` naming every pair whose factor is above `max_factor` (none clipped)."""
    if max_factor is None:
        return
    over = [f"{name} ({factor:.4g})" for name, factor in zip(names, factors) if factor > max_factor]
    if over:
        raise ValueError(f"{where}: {len(over)} pair(s) would be scaled by more than {max_factor:g}: "
                         f"{', '.join(over)}; choose other records, a lower target or a higher limit.")


def suite_statistic(spectra, factors, statistic: str = "mean") -> np.ndarray:
    """The scaled suite's `statistic` over pairs of f_i PSA_i(T) (K,) [m/s^2]."""
    scaled = np.asarray(factors, float)[:, None] * np.asarray(spectra, float)
    return scaled.mean(axis=0) if statistic == "mean" else scaled.max(axis=0)

