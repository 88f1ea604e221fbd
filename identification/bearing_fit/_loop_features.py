"""Loop features shared by the time-history and digitised fits: reversals, first friction estimate."""

import dataclasses
import math

import jax.numpy as jnp
import numpy as np

from ._record_force import simulate_record_force

# x at which Z crosses 0 after a reversal from Z = -1 (Bouc-Wen, A = 1, gamma - beta = 0.8):
# x = atan(sqrt(gamma - beta)) / sqrt(gamma - beta), in units of Y.
_ZERO_CROSSING = math.atan(math.sqrt(0.8)) / math.sqrt(0.8)


_MIN_ELASTIC_SAMPLES = 3


# ---------------------------------------------------------------------------------------------
# Data prepared for the residual


@dataclasses.dataclass(frozen=True)
class RecordConfig:
    """Static description of one record for the residual (hashable): a time history along x
    or a digitised loop; `BiaxialRecordConfig` for a time history in the plane."""

    kind: str  # "time" or "digitised"
    interfaces_in_parallel: int = 1
    interfaces_in_series: int = 1

    def time_force(self, values, rec):
        """Model force fx [N] (n,) at the samples of a time history along x, from the state
        `z0`, `z_peak0` the record starts in."""
        return simulate_record_force(
            values, rec["time"], rec["ux"], rec["load"], velocity=rec["velocity"],
            z0=rec["z0"], z_peak0=rec["z_peak0"],
            interfaces_in_parallel=self.interfaces_in_parallel,
            interfaces_in_series=self.interfaces_in_series)


@dataclasses.dataclass(frozen=True)
class BiaxialRecordConfig(RecordConfig):
    """A time history in the plane (ux, uy, fx, fy), from rest; `park_elements` straight
    elements per sample interval of Park's update."""

    park_elements: int = 16

    def time_force(self, values, rec):
        """Model forces (fx, fy) [N] stacked (2n,) at the samples (Park's Z, Eqs. 8-9)."""
        fx, fy = simulate_record_force(
            values, rec["time"], rec["ux"], rec["load"], velocity=rec["velocity"],
            uy=rec["uy"], velocity_y=rec["velocity_y"],
            interfaces_in_parallel=self.interfaces_in_parallel,
            interfaces_in_series=self.interfaces_in_series, park_elements=self.park_elements)
        return jnp.concatenate([fx, fy])


@dataclasses.dataclass
class PreparedRecord:
    """A record ready for fitting (numpy, SI): what the residual needs and what was detected.

    - `name`: the file name or `record <i>`.
    - `kind`: `"time"` (a time history) or `"digitised"` (points of a loop plus a protocol).
    - `arrays`: the pytree of arrays passed to the residual.
    - `first_motion`: whether the record starts from rest (contains the first excursion).
    - `start`: feature-based start values of all five parameters.
    - `warnings`: identifiability and data warnings.
    - `elastic_samples`: median number of samples within 2 Y after a reversal.
    - `interfaces_in_parallel`, `interfaces_in_series`: from the record's metadata.

    A time history in the plane (`uy`, `fy`) is a `PreparedBiaxialRecord`.
    """

    name: str
    kind: str
    arrays: dict
    first_motion: bool
    start: dict
    warnings: list
    elastic_samples: float
    measured: np.ndarray
    ux: np.ndarray
    time: np.ndarray | None
    interfaces_in_parallel: int = 1
    interfaces_in_series: int = 1
    velocity: np.ndarray | None = None
    speed_low: float | None = None
    speed_high: float | None = None

    @property
    def config(self) -> RecordConfig:
        return RecordConfig(self.kind, self.interfaces_in_parallel, self.interfaces_in_series)

    @property
    def residual_velocity(self) -> np.ndarray:
        """Velocity (digitised: branch) whose sign sorts each entry of the residual into
        moving in + or - (the asymmetry check)."""
        return np.asarray(self.velocity) if self.kind == "time" else self.arrays["branch"]

    @property
    def uy(self) -> np.ndarray | None:
        """Displacement along y [m] of a record in the plane, else `None`."""
        return None


@dataclasses.dataclass
class PreparedBiaxialRecord(PreparedRecord):
    """A time history in the plane (ux, uy, fx, fy) ready for fitting: `measured` and the
    residual stack fx and fy; `park_elements` per sample interval of Park's update."""

    park_elements: int = 16

    @property
    def config(self) -> BiaxialRecordConfig:
        return BiaxialRecordConfig(self.kind, self.interfaces_in_parallel,
                                   self.interfaces_in_series, self.park_elements)

    @property
    def residual_velocity(self) -> np.ndarray:
        return np.concatenate([np.asarray(self.velocity), np.asarray(self.arrays["velocity_y"])])

    @property
    def uy(self) -> np.ndarray:
        return self.arrays["uy"]


def _reversals(ux) -> np.ndarray:
    """Indices where the direction of motion changes (the sample at the extreme)."""
    du = np.diff(ux)
    sign = np.sign(du)
    # carry the last non-zero direction over pauses
    for i in range(1, sign.size):
        if sign[i] == 0:
            sign[i] = sign[i - 1]
    change = np.flatnonzero(sign[1:] * sign[:-1] < 0) + 1
    return change


def _excursion(ux, reversals) -> np.ndarray:
    """|u - u at the last reversal (or at the start)| for each sample."""
    anchors = np.zeros(ux.size, dtype=int)
    for r in reversals:
        anchors[r:] = r
    return np.abs(ux - ux[anchors])


def _friction_law_start(speed, mu_sliding):
    """Start values of (f_max, delta_f, rate_a) by a grid over rate_a and linear least squares."""
    v_ref = np.median(speed)
    best = None
    for a in np.geomspace(0.01, 30.0, 80) / max(v_ref, 1e-12):
        e = np.exp(-a * speed)
        design = np.stack([np.ones_like(e), -e], axis=1)
        coef, *_ = np.linalg.lstsq(design, mu_sliding, rcond=None)
        cost = np.sum((design @ coef - mu_sliding) ** 2)
        if coef[0] > 0 and 0 < coef[1] < coef[0] and (best is None or cost < best[0]):
            best = (cost, coef[0], coef[1], a)
    if best is None:
        f = float(np.median(mu_sliding))
        return f, 0.5 * f, 3.0 / max(v_ref, 1e-12)
    _, f_max, delta_f, a = best
    delta_f = float(np.clip(delta_f, 0.05 * f_max, 0.95 * f_max))
    return float(f_max), delta_f, float(a)

