"""Writing Monte Carlo results to files."""

import numpy as np

from ._montecarlo import MonteCarloResult

# --------------------------------------------------------------------------- output


def save_montecarlo(result: MonteCarloResult, path) -> list:
    """Save `result` as labelled arrays: NetCDF through xarray when `path` ends in ".nc" and
    xarray is installed; otherwise a NumPy ".npz" (arrays plus `dims`, design values and
    attributes as JSON) and, for up to 10,000 rows, a CSV beside it (one row per motion and
    design variant). Returns the paths written."""
    import json
    import pathlib

    path = pathlib.Path(path)
    names = ("base_disp", "base_shear_ratio", "smooth_base_disp", "smooth_base_shear_ratio", "converged")
    written = []
    if path.suffix == ".nc":
        try:
            import xarray
        except ImportError:
            path = path.with_suffix(".npz")
        else:
            coords = {"motion": np.arange(result.n_motions)}
            if result.design:
                coords["design"] = np.arange(len(next(iter(result.design.values()))))
            data = {n: (result.dims, getattr(result, n)) for n in names}
            data["pga"] = (("motion",), result.pga)
            for k, v in result.design.items():
                data[k] = (("design",), v)
            xarray.Dataset(data, coords=coords, attrs={k: str(v) for k, v in result.attrs.items()}).to_netcdf(path)
            return [path]
    if path.suffix != ".npz":
        path = path.with_suffix(".npz")
    meta = {
        "dims": list(result.dims),
        "units": {"base_disp": "m", "base_shear_ratio": "-", "pga": "m/s^2"},
        "n_devices": result.n_devices,
        "attrs": result.attrs,
    }
    arrays = {n: getattr(result, n) for n in names}
    arrays["pga"] = result.pga
    arrays.update({f"design_{k}": v for k, v in result.design.items()})
    np.savez(path, metadata=json.dumps(meta), **arrays)
    written.append(path)
    rows = result.base_disp.size
    if rows <= 10_000:
        csv = path.with_suffix(".csv")
        with open(csv, "w") as handle:
            design_names = list(result.design)
            handle.write(",".join(["design", "motion", *design_names, "pga_m_s2", "base_disp_m",
                                   "base_shear_ratio", "converged"]) + "\n")
            disp = result.base_disp.reshape(-1, result.n_motions)
            shear = result.base_shear_ratio.reshape(-1, result.n_motions)
            ok = result.converged.reshape(-1, result.n_motions)
            for d in range(disp.shape[0]):
                values = [f"{result.design[k][d]:.9g}" for k in design_names]
                for i in range(result.n_motions):
                    handle.write(",".join([str(d), str(i), *values, f"{result.pga[i]:.9g}",
                                           f"{disp[d, i]:.9g}", f"{shear[d, i]:.9g}",
                                           str(bool(ok[d, i]))]) + "\n")
        written.append(csv)
    return written
