"""Record suites: many two-component record pairs (e.g. the 7 or 11 pairs of a design check,
each with its scale factor) through one bidirectional structure in one vmapped call, with the
peaks of every pair, their mean and maximum (failed runs kept out of both and reported)."""

import dataclasses

import diffrax
import jax
import jax.numpy as jnp
import numpy as np

from ..excitation import uniform_signal
from ..systems import BidirectionalStructure, simulate_bidirectional
from ..units import STANDARD_GRAVITY

SUITE_PEAKS = ("base_disp_resultant_m", "base_disp_x_m", "base_disp_y_m", "base_shear_ratio_resultant")


@dataclasses.dataclass(frozen=True)
class SuiteResult:
    """Peaks per pair (arrays (P,)), `converged` (P,), the pair `names`, and `summary`:
    {peak name: {"mean": ..., "max": ...}} over the converged pairs."""

    names: tuple
    peaks: dict
    converged: np.ndarray
    summary: dict


def suite_peaks(build, names, ax, ay, time_step: float, duration: float, base_index=(0, 1)) -> SuiteResult:
    """Run P record pairs through the structure `build(ground_x, ground_y)` in one vmapped call.

    **Arguments:** `build`: a function of two `Signal`s returning a `BidirectionalStructure`;
    `names` (P,); `ax`, `ay` (P, n) ground accelerations [m/s^2] (already scaled, common step);
    `time_step` [s] of the records; `duration` [s]; `base_index`: the coordinates of the base in
    x and y (rigid mass (0, 1), building (0, 7), slab (0, 1)).

    **Returns:** a `SuiteResult`; the base shear ratio is the total horizontal force on the
    structure above the bearings over its weight.
    """
    ix, iy = base_index

    def one(x, y):
        system: BidirectionalStructure = build(uniform_signal(x, time_step), uniform_signal(y, time_step))
        r = simulate_bidirectional(system, duration, throw=False)
        total = r.acceleration + r.ground @ system.influence.T
        force = jnp.einsum("tn,n,nd->td", total, system.mass, system.influence)
        weight = jnp.sum(system.mass * system.influence[:, 0]) * STANDARD_GRAVITY
        bx, by = r.q[:, ix], r.q[:, iy]
        return {
            "base_disp_resultant_m": jnp.max(jnp.hypot(bx, by)),
            "base_disp_x_m": jnp.max(jnp.abs(bx)),
            "base_disp_y_m": jnp.max(jnp.abs(by)),
            "base_shear_ratio_resultant": jnp.max(jnp.hypot(force[:, 0], force[:, 1])) / weight,
        }, r.result == diffrax.RESULTS.successful

    peaks, ok = jax.jit(jax.vmap(one))(jnp.asarray(ax), jnp.asarray(ay))
    peaks = {k: np.asarray(v) for k, v in peaks.items()}
    ok = np.asarray(ok, dtype=bool)
    summary = {
        k: {"mean": float(np.mean(v[ok])) if ok.any() else float("nan"),
            "max": float(np.max(v[ok])) if ok.any() else float("nan")}
        for k, v in peaks.items()
    }
    return SuiteResult(names=tuple(names), peaks=peaks, converged=ok, summary=summary)


def save_suite(result: SuiteResult, table_path=None, netcdf_path=None) -> None:
    """One CSV table (a row per pair, then mean and max rows) and one NetCDF file."""
    import pathlib

    if table_path is not None:
        path = pathlib.Path(table_path)
        path.parent.mkdir(parents=True, exist_ok=True)
        lines = ["pair," + ",".join(SUITE_PEAKS) + ",converged"]
        for i, name in enumerate(result.names):
            row = ",".join(f"{result.peaks[k][i]:.6g}" for k in SUITE_PEAKS)
            lines.append(f"{name},{row},{bool(result.converged[i])}")
        for stat in ("mean", "max"):
            lines.append(f"{stat}," + ",".join(f"{result.summary[k][stat]:.6g}" for k in SUITE_PEAKS) + ",")
        path.write_text("\n".join(lines) + "\n")
    if netcdf_path is not None:
        import xarray

        data = {k: ("pair", v) for k, v in result.peaks.items()}
        data["converged"] = ("pair", result.converged.astype(np.int8))
        attrs = {f"{k}_{s}": v[s] for k, v in result.summary.items() for s in ("mean", "max")}
        path = pathlib.Path(netcdf_path)
        path.parent.mkdir(parents=True, exist_ok=True)
        xarray.Dataset(data, coords={"pair": list(result.names)}, attrs=attrs).to_netcdf(path)
