"""`run --histories FILE`: the response histories as CSV (each column's name ends in its SI
unit) or NetCDF (each variable with its `units` and `long_name`, the command's version,
command line and inputs in the global attributes)."""

import pathlib

import numpy as np

HISTORY_VARIABLES = {
    "ground_x_mps2": ("m s-2", "ground acceleration, x component"),
    "ground_y_mps2": ("m s-2", "ground acceleration, y component"),
    "base_disp_x_m": ("m", "base displacement relative to the ground, x"),
    "base_disp_y_m": ("m", "base displacement relative to the ground, y"),
    "bearing_force_x_N": ("N", "force of the bearings on the structure above them, x"),
    "bearing_force_y_N": ("N", "force of the bearings on the structure above them, y"),
    "base_shear_ratio_x": ("1", "base shear / weight above the bearings, x"),
    "base_shear_ratio_y": ("1", "base shear / weight above the bearings, y"),
    "rotation_rad": ("rad", "rotation of the slab about the vertical axis"),
    "load_factor": ("1", "normal load of the bearings / their static load (vertical ground motion)"),
}
"""The histories of `run` (the key names its SI unit): name -> (units, long name), written as
the NetCDF variables' `units` and `long_name` (CF conventions); others by `history_units`."""

_UNIT_SUFFIXES = (("_mps2", "m s-2"), ("_m", "m"), ("_N", "N"), ("_K", "K"), ("_rad", "rad"), ("_s", "s"))


def history_units(name: str) -> tuple:
    """(units, long name) of the history `name`: from `HISTORY_VARIABLES`, else from the unit
    its name ends in (a slider's displacement `slider_inner_m`, a surface's temperature rise
    `temperature_rise_A_bottom_K`), "1" for none."""
    if name in HISTORY_VARIABLES:
        return HISTORY_VARIABLES[name]
    units = next((unit for suffix, unit in _UNIT_SUFFIXES if name.endswith(suffix)), "1")
    return units, name.replace("_", " ")


def write_histories(path, histories) -> None:
    """The histories (SI, keys in `HISTORY_VARIABLES`, `time_s` their time) as CSV (the unit
    in each column's name) or NetCDF (each variable with its `units` and `long_name`; the
    command's version, command line and inputs in the global attributes)."""
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if path.suffix == ".csv":
        names = list(histories)
        table = np.column_stack([histories[k] for k in names])
        np.savetxt(path, table, delimiter=",", header=",".join(names), comments="")
    elif path.suffix == ".nc":
        import xarray

        from ._provenance import provenance_attributes

        time = histories["time_s"]
        data = {}
        for name, values in histories.items():
            if name != "time_s":
                units, long_name = history_units(name)
                data[name] = ("time", values, {"units": units, "long_name": long_name})
        attrs = {"Conventions": "CF-1.8", "title": "teflon-jax run histories", **provenance_attributes()}
        xarray.Dataset(data, coords={"time": ("time", time, {"units": "s", "long_name": "time"})},
                       attrs=attrs).to_netcdf(path)
    else:
        raise ValueError(f"--histories: {path} must end in .nc or .csv.")
