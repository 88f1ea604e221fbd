"""Results of a Monte Carlo run: statistics over the runs whose solve converged, and the
results as an xarray Dataset (NetCDF, Zarr, CSV) that reads back into the same object.

Dataset layout: dimensions "motion" (index i of the motion: motion i of a stochastic run is
drawn from `fold_in(key, i)`) and, with design variants, "design" (or, in a nested run of a
bearing posterior's draws, "bearing"); data variables the peaks
(`base_disp` [m], `base_shear_ratio` [1], their smooth maxima), `converged` (bool) and `pga`
[m s-2], each with `units` and `long_name` attributes (CF conventions), and where kept the
storeys', the bearing groups' and the surfaces' peaks (`_result_variables`); the design variables
on the "design" dimension; with a bearing posterior `bearing_draw`, the draw each motion
("motion") or each bearing ("bearing") ran; the run's inputs and settings in the Dataset's
attributes.
"""

import csv
import dataclasses
import json
import os
import pathlib
from collections.abc import Sequence

import numpy as np

from ..systems import RESPONSE_NAMES
from ._bearing_variance import percentile_band, variance_split
from ._result_variables import (
    BEARING_DRAW,
    DESIGN_UNITS,
    GROUP_VARIABLES,
    RUN_FLAGS,
    STOREY_VARIABLES,
    SURFACE_VARIABLES,
    VARIABLES,
    surface_columns,
)

FORMATS = (".nc", ".zarr", ".csv", ".npz")
"""File suffixes `save` writes: NetCDF, Zarr (needs the zarr package), CSV, NumPy."""

_SETTINGS = ("n_devices", "chunk_size", "wall_s", "compile_s", "memory_estimate_bytes")


@dataclasses.dataclass
class MonteCarloResult:
    """Peaks of a Monte Carlo run, as NumPy arrays labelled by `dims`.

    - `base_disp` [m], `base_shear_ratio` [-]: shape (N,) or (D, N) with design variants;
    - `smooth_base_disp`, `smooth_base_shear_ratio`: the smooth maxima (same shapes);
    - `converged` (bool, same shape): every step's solve converged and, with Table 1's
      pressure law under a vertical component, the law gave Eq. 1 constants throughout (see
      `beyond_pressure_law`); `pga` (N,) [m/s^2]: peak |a_g| of each motion;
    - `design`: dict name -> (D,) values (empty without variants);
    - `dims`: axis names, ("motion",), ("design", "motion"), or ("bearing", "motion") for K
      draws of a bearing posterior each run on the same motions (statistics then pool the
      K x N runs; `variance_split`, `percentile_band` split them);
    - `n_devices`, `chunk_size`, `wall_s` (total), `compile_s` (first chunk's compile),
      `memory_estimate_bytes` (one chunk); `attrs`: description of the run;
    - `storey_drift` [-] (N, S) or (D, N, S), `floor_acceleration` [m/s^2] (N, S + 1) or
      (D, N, S + 1): a building's peak drift ratio per storey (storey 1 first) and total
      acceleration per level (0 the base slab, then floors 1..S) (`monte_carlo(storey_height=...)`),
      with two components an axis of the two directions (x, y) before the last; else `None`;
    - `uplift_time` [s] (N,) or (D, N): with a vertical component, how long each run's
      isolators had N <= 0 (no shear; 0: no uplift); their peaks are kept in the statistics
      (the uplift is part of the modelled response); else `None`.
    - `group_peak_load`, `group_min_load` [N], `group_uplift_time` [s] (N, G) or (D, N, G): a
      structure on a plan whose G groups share the weight unevenly, each group's largest and
      least normal load and its time at N_g <= 0 (`GROUP_VARIABLES`); else `None`.
    - `beyond_pressure_law` (bool, shape of `converged`): with Table 1's pressure law under a
      vertical component, the runs whose contact pressure went beyond where its extended rows
      give Eq. 1 constants (left out of the statistics by `converged`); else `None`.
    - `tipped` (bool, shape of `converged`): on a plan whose groups carry the overturning
      loads, the runs whose first unbalanced step was one on which the slab (or the building's
      base) could not rest on its groups (`TIPPED`); the other unconverged runs' Newton balance
      missed its tolerance; else `None`.
    - `bearing_draw` (N,) or (K,) ints: the posterior draw each motion, or each bearing of a
      nested run, took (`monte_carlo(bearings=...)`); else `None`.
    - `slider_travel` [m] (N, G, S) or (D, N, G, S): a series pendulum's peak travel of each
      of its S sliders on its surface (`attrs["slider_names"]`), per bearing group (G = 1
      without a plan); else `None`.
    - `surface_temperature_rise` [K] (N, G, H) or (D, N, G, H): the peak temperature rise s dT
      of each of the H heated surfaces (`attrs["heated_surface_names"]`), per group; else `None`.
    """

    base_disp: np.ndarray
    base_shear_ratio: np.ndarray
    smooth_base_disp: np.ndarray
    smooth_base_shear_ratio: np.ndarray
    converged: np.ndarray
    pga: np.ndarray
    design: dict
    dims: tuple
    n_devices: int
    chunk_size: int
    wall_s: float
    compile_s: float
    memory_estimate_bytes: int
    attrs: dict = dataclasses.field(default_factory=dict)
    storey_drift: np.ndarray | None = None
    floor_acceleration: np.ndarray | None = None
    uplift_time: np.ndarray | None = None
    bearing_draw: np.ndarray | None = None
    group_peak_load: np.ndarray | None = None
    group_min_load: np.ndarray | None = None
    group_uplift_time: np.ndarray | None = None
    beyond_pressure_law: np.ndarray | None = None
    tipped: np.ndarray | None = None
    slider_travel: np.ndarray | None = None
    surface_temperature_rise: np.ndarray | None = None

    @property
    def group_names(self) -> list:
        """The bearing groups' names (`attrs["group_names"]`, else "group 1", ...); [] without
        a peak per group."""
        if self.group_peak_load is not None:
            count = np.shape(self.group_peak_load)[-1]
        elif self.surfaces:
            count = np.shape(getattr(self, next(iter(self.surfaces))))[-2]
        else:
            return []
        return list(self.attrs.get("group_names") or [f"group {i + 1}" for i in range(count)])

    @property
    def surfaces(self) -> dict:
        """{name: (dimension, labels)} of the `SURFACE_VARIABLES` kept, their labels
        `attrs["<dimension>_names"]` (else "1", "2", ...)."""
        out = {}
        for name, (dim, _, _) in SURFACE_VARIABLES.items():
            values = getattr(self, name)
            if values is not None:
                count = np.shape(values)[-1]
                out[name] = (dim, list(self.attrs.get(f"{dim}_names") or [str(i + 1) for i in range(count)]))
        return out

    @property
    def surface_peaks(self) -> dict:
        """{"<name>_<unit>_[<group>_]<surface>": array of `converged`'s shape} [SI]: the surface
        peaks one per group and surface (`surface_columns`), as the CSV's columns."""
        arrays = {name: getattr(self, name) for name in self.surfaces}
        labels = {f"{dim}_names": names for dim, names in self.surfaces.values()}
        return surface_columns(arrays, labels, self.group_names)

    @property
    def nested(self) -> bool:
        """Whether the runs are K bearings x N motions (dims ("bearing", "motion"))."""
        return tuple(self.dims)[0] == "bearing"

    @property
    def n_uplifted(self) -> int | list | None:
        """Runs whose isolators uplifted (N <= 0 at some step), a list per design variant;
        `None` without a vertical component."""
        if self.uplift_time is None:
            return None
        counts = np.sum(np.asarray(self.uplift_time) > 0, axis=-1)
        return int(counts) if counts.ndim == 0 else counts.tolist()

    @property
    def beyond_flags(self) -> np.ndarray:
        """`beyond_pressure_law` as a bool array of `converged`'s shape (all False without
        Table 1's pressure law)."""
        return self._flags(self.beyond_pressure_law)

    @property
    def tipped_flags(self) -> np.ndarray:
        """`tipped` as a bool array of `converged`'s shape (all False without overturning loads)."""
        return self._flags(self.tipped)

    def _flags(self, values) -> np.ndarray:
        """A run flag (`RUN_FLAGS`) as bools of `converged`'s shape, all False where not kept."""
        return np.zeros(np.shape(self.converged), bool) if values is None else np.asarray(values, bool)

    @property
    def n_motions(self) -> int:
        return int(self.pga.shape[0])

    @property
    def n_converged(self) -> int | list:
        """Runs whose every step's Newton solve converged: the runs the statistics rest on
        (a list per design variant when there are several)."""
        counts = np.sum(np.asarray(self.converged, bool), axis=None if self.nested else -1)
        return int(counts) if counts.ndim == 0 else counts.tolist()

    @property
    def n_failed(self) -> int:
        """Runs (all variants together) left out of the statistics: their solve failed."""
        return int(np.sum(~np.asarray(self.converged, bool)))

    def converged_values(self, name: str, variant: int | None = None) -> np.ndarray:
        """The peaks `name` of the converged runs only, for one design `variant` (index into
        the "design" axis; required when there are variants, ignored otherwise); of a nested
        run the K x N runs pooled (`variant` None) or bearing `variant`'s. `name`: a peak of
        `RESPONSE_NAMES` (or its smooth maximum), or a surface column of `surface_peaks`
        (e.g. "slider_travel_m_inner") [SI]."""
        values = np.asarray(self._peaks(name))
        ok = np.asarray(self.converged, bool)
        if self.nested and variant is None:
            return values[ok]
        if values.ndim == 2:
            if variant is None:
                raise ValueError("variant: this result has design variants; give the index of one.")
            values, ok = values[variant], ok[variant]
        return values[ok]

    def _peaks(self, name: str) -> np.ndarray:
        """The peaks `name` of every run (`converged_values`' names); `ValueError` naming the
        accepted ones."""
        if name in RESPONSE_NAMES + ("smooth_base_disp", "smooth_base_shear_ratio"):
            return getattr(self, name)
        columns = self.surface_peaks
        if name not in columns:
            raise ValueError(f"name: unknown {name!r}; accepted: {', '.join(RESPONSE_NAMES + tuple(columns))}.")
        return columns[name]

    def percentiles(self, q: Sequence[float] = (5, 16, 50, 84, 95)) -> dict:
        """{"base_disp_m": {"p50": .., "mean": .., "std": .., "n": ..}, "base_shear_ratio": {..},
        each surface column of `surface_peaks` [SI], "n_converged": .., "n_failed": ..} over the
        converged runs ("n" of them; a run with a failed step left out). Per design variant
        (lists) when there are several; a nested run's K x N runs pooled; `None` over no run."""
        pooled = np.ndim(self.converged) == 1 or self.nested
        variants = [None] if pooled else list(range(np.shape(self.converged)[0]))
        names = {"base_disp_m": "base_disp", "base_shear_ratio": "base_shear_ratio"}
        names |= {column: column for column in self.surface_peaks}
        out = {}
        for key, name in names.items():
            per_variant = [_statistics(self.converged_values(name, variant), q) for variant in variants]
            if variants == [None]:
                out[key] = per_variant[0]
            else:
                out[key] = {k: [s[k] for s in per_variant] for k in per_variant[0]}
        out["n_converged"] = self.n_converged
        out["n_failed"] = self.n_failed
        return out

    def exceedance(self, name: str, variant: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Empirical exceedance curve of `name` ("base_disp", "base_shear_ratio" or a surface
        column of `surface_peaks`, e.g. "slider_travel_m_inner") over the n converged runs (of
        design `variant` when there are several): sorted levels x_(k) and P[X > x] estimated
        as (n - k) / n, k = 1..n."""
        accepted = RESPONSE_NAMES + tuple(self.surface_peaks)
        if name not in accepted:
            raise ValueError(f"name: unknown {name!r}; accepted: {', '.join(accepted)}.")
        values = np.sort(self.converged_values(name, variant))
        n = values.shape[-1]
        return values, (n - np.arange(1, n + 1)) / max(n, 1)

    def variance_split(self, name: str) -> dict:
        """`variance_split` of the converged peaks `name` (e.g. "base_disp") of a nested run:
        Var = E_k[Var_m] + Var_k[E_m], the bearing part and its share of the total."""
        return variance_split(self._nested_peaks(name), self.converged)

    def percentile_band(self, name: str, q: float = 95.0, band=(5.0, 95.0)) -> dict:
        """`percentile_band` of the converged peaks `name` of a nested run: the qth percentile
        pooled, and the `band` percentiles of the K per-bearing qth percentiles."""
        return percentile_band(self._nested_peaks(name), self.converged, q=q, band=band)

    def _nested_peaks(self, name):
        if not self.nested:
            raise ValueError("the result is not a nested run of bearing draws (dims ('bearing', "
                             f"'motion')); its dims are {tuple(self.dims)}.")
        return self._peaks(name)

    # ----------------------------------------------------------------------- files

    def to_dataset(self):
        """The result as an `xarray.Dataset` (layout in the module docstring)."""
        import xarray

        dims = tuple(self.dims)
        data = {}
        for name, (units, long_name) in VARIABLES.items():
            data[name] = (dims, np.asarray(getattr(self, name)), {"units": units, "long_name": long_name})
        for name, (dim, units, long_name) in STOREY_VARIABLES.items():
            if getattr(self, name) is not None:
                values = np.asarray(getattr(self, name))
                direction = ("direction",) if values.ndim == len(dims) + 2 else ()  # two components: x, y
                data[name] = (dims + direction + (dim,), values,
                              {"units": units, "long_name": long_name})
        if self.uplift_time is not None:
            data["uplift_time"] = (dims, np.asarray(self.uplift_time),
                                   {"units": "s", "long_name": "time with the isolators' normal load <= 0"})
        for name, (units, long_name) in RUN_FLAGS.items():
            if getattr(self, name) is not None:
                data[name] = (dims, np.asarray(getattr(self, name)), {"units": units, "long_name": long_name})
        for name, (units, long_name) in GROUP_VARIABLES.items():
            if getattr(self, name) is not None:
                data[name] = (dims + ("group",), np.asarray(getattr(self, name)), {"units": units, "long_name": long_name})
        for name, (dim, _) in self.surfaces.items():
            units, long_name = SURFACE_VARIABLES[name][1:]
            data[name] = (dims + ("group", dim), np.asarray(getattr(self, name)), {"units": units, "long_name": long_name})
        data["pga"] = (("motion",), np.asarray(self.pga),
                       {"units": "m s-2", "long_name": "peak |ground acceleration| of the motion"})
        if self.bearing_draw is not None:
            data["bearing_draw"] = (dims[:1], np.asarray(self.bearing_draw, np.int64),
                                    {"units": BEARING_DRAW[0], "long_name": BEARING_DRAW[1]})
        for name, values in self.design.items():
            units, long_name = DESIGN_UNITS.get(name, ("1", name))
            data[f"design_{name}"] = (("design",), np.asarray(values), {"units": units, "long_name": long_name})
        coords = {"motion": np.arange(self.n_motions)}
        if self.storey_drift is not None:
            coords["storey"] = np.arange(1, np.shape(self.storey_drift)[-1] + 1)
            coords["level"] = np.arange(np.shape(self.floor_acceleration)[-1])
            if np.ndim(self.storey_drift) == len(dims) + 2:
                coords["direction"] = np.array(["x", "y"])
        if self.group_names:
            coords["group"] = np.array(self.group_names)
        coords.update({dim: np.array(labels) for dim, labels in self.surfaces.values()})
        if dims[0] in ("design", "bearing"):
            coords[dims[0]] = np.arange(np.shape(self.converged)[0])
        attrs = {k: _attribute(v) for k, v in self.attrs.items()}
        attrs.update({k: _attribute(getattr(self, k)) for k in _SETTINGS})
        attrs["teflon_jax_attrs"] = json.dumps(self.attrs, default=str)
        attrs["n_converged"] = np.asarray(self.n_converged, dtype=np.int64)
        attrs["Conventions"] = "CF-1.8"
        attrs["title"] = "teflon-jax Monte Carlo peak responses"
        return xarray.Dataset(data, coords=coords, attrs=attrs)

    @classmethod
    def from_dataset(cls, dataset) -> "MonteCarloResult":
        """The `MonteCarloResult` a `to_dataset` (or a file it was written to) holds."""
        dims = tuple(dataset["base_disp"].dims)
        design = {k[len("design_"):]: np.asarray(v.values) for k, v in dataset.data_vars.items()
                  if k.startswith("design_")}
        settings = {k: dataset.attrs[k] for k in _SETTINGS}
        return cls(
            **{name: np.asarray(dataset[name].values) for name in VARIABLES},
            pga=np.asarray(dataset["pga"].values),
            design=design,
            dims=dims,
            n_devices=int(settings["n_devices"]),
            chunk_size=int(settings["chunk_size"]),
            wall_s=float(settings["wall_s"]),
            compile_s=float(settings["compile_s"]),
            memory_estimate_bytes=int(settings["memory_estimate_bytes"]),
            attrs=json.loads(dataset.attrs.get("teflon_jax_attrs", "{}")),
            **{name: np.asarray(dataset[name].values) for name in STOREY_VARIABLES if name in dataset},
            uplift_time=np.asarray(dataset["uplift_time"].values) if "uplift_time" in dataset else None,
            bearing_draw=np.asarray(dataset["bearing_draw"].values) if "bearing_draw" in dataset else None,
            **{name: np.asarray(dataset[name].values) for name in GROUP_VARIABLES if name in dataset},
            **{name: np.asarray(dataset[name].values, bool) if name in dataset else None
               for name in RUN_FLAGS},
            **{name: np.asarray(dataset[name].values) for name in SURFACE_VARIABLES if name in dataset},
        )

    def to_csv(self, path) -> pathlib.Path:
        """The peak table as CSV: one row per motion (and design variant), columns design
        (bearing in a nested run), motion, bearing_draw (with a bearing posterior), the design
        variables, pga_m_s2, base_disp_m, base_shear_ratio, the smooth maxima and converged, then
        the uplift time, storey peaks, each bearing group's peaks (`<field>_<unit>_<group>`) and
        the surfaces' peaks (`<field>_<unit>_[<group>_]<surface>`) where kept."""
        path = pathlib.Path(path)
        rows = np.asarray(self.base_disp).reshape(-1, self.n_motions)
        n_designs = rows.shape[0]
        columns = {"bearing" if self.nested else "design": np.repeat(np.arange(n_designs), self.n_motions),
                   "motion": np.tile(np.arange(self.n_motions), n_designs)}
        if self.bearing_draw is not None:
            draws = np.asarray(self.bearing_draw)
            columns["bearing_draw"] = np.repeat(draws, self.n_motions) if self.nested else draws
        for name, values in self.design.items():
            columns[name] = np.repeat(np.asarray(values), self.n_motions)
        columns["pga_m_s2"] = np.tile(np.asarray(self.pga), n_designs)
        for name, label in (("base_disp", "base_disp_m"), ("base_shear_ratio", "base_shear_ratio"),
                            ("smooth_base_disp", "smooth_base_disp_m"),
                            ("smooth_base_shear_ratio", "smooth_base_shear_ratio"),
                            ("converged", "converged")):
            columns[label] = np.asarray(getattr(self, name)).reshape(-1)
        if self.uplift_time is not None:
            columns["uplift_time_s"] = np.asarray(self.uplift_time).reshape(-1)
        for name in RUN_FLAGS:
            if getattr(self, name) is not None:
                columns[name] = np.asarray(getattr(self, name)).reshape(-1)
        for name, unit, first in (("storey_drift", "", 1), ("floor_acceleration", "_m_s2", 0)):
            values = getattr(self, name)
            if values is not None:
                two = np.ndim(values) == len(self.dims) + 2
                values = np.asarray(values).reshape(columns["motion"].size, -1, np.shape(values)[-1])
                for d, axis in enumerate(("_x", "_y") if two else ("",)):
                    for j in range(values.shape[2]):
                        columns[f"{name}{axis}_{j + first}{unit}"] = values[:, d, j]
        for name, (unit, _) in GROUP_VARIABLES.items():
            values = getattr(self, name)
            if values is not None:
                values = np.asarray(values).reshape(columns["motion"].size, -1)
                for j, group in enumerate(self.group_names):
                    columns[f"{name}_{unit}_{group}"] = values[:, j]
        columns.update({k: np.reshape(v, -1) for k, v in self.surface_peaks.items()})
        with open(path, "w") as handle:
            csv.writer(handle, lineterminator="\n").writerow(columns)  # a group's name quoted where it must be
            for i in range(columns["motion"].size):
                handle.write(",".join(_cell(c[i]) for c in columns.values()) + "\n")
        return path

    def save(self, path) -> pathlib.Path:
        """Write the result in the format its suffix names (`FORMATS`): ".nc" NetCDF, ".zarr"
        Zarr, ".csv" the peak table, ".npz" NumPy arrays with the Dataset's attributes as JSON.
        Any other suffix, a missing NetCDF/Zarr library or an unwritable place is a
        `ValueError` saying so; nothing is written in another format than asked."""
        path = check_output_path(path)
        if path.suffix == ".csv":
            return self.to_csv(path)
        if path.suffix == ".npz":
            dataset = self.to_dataset()
            arrays = {k: v.values for k, v in dataset.data_vars.items()}
            meta = {"dims": list(self.dims), "attrs": {k: _json(v) for k, v in dataset.attrs.items()},
                    "units": {k: v.attrs["units"] for k, v in dataset.data_vars.items()}}
            np.savez(path, metadata=json.dumps(meta), **arrays)
            return path
        if path.suffix == ".zarr":
            self.to_dataset().to_zarr(path, mode="w")
            return path
        self.to_dataset().to_netcdf(path, engine=netcdf_engine())
        return path

    @classmethod
    def open(cls, path) -> "MonteCarloResult":
        """Read a result written by `save` (".nc" or ".zarr") or by `monte_carlo_distributed`
        (refused, `ValueError`, when that run did not finish: `check_complete`)."""
        import xarray

        path = pathlib.Path(path)
        if not path.exists():
            raise ValueError(f"{path}: no such results file.")
        if path.suffix == ".zarr":
            with xarray.open_zarr(path) as dataset:
                dataset = dataset.load()
        else:
            with xarray.open_dataset(path, engine=netcdf_engine()) as dataset:
                dataset = dataset.load()
        check_complete(dataset, path)
        return cls.from_dataset(dataset)


def check_complete(dataset, path) -> None:
    """`ValueError` naming `path` when the Dataset's `complete` attribute is not 1: the run that
    streamed it chunk by chunk stopped before every chunk was in, and the items it lacks hold
    fill values (files written in one piece have no such attribute)."""
    if dataset.attrs.get("complete", 1) != 1:
        raise ValueError(f"{path}: the run that wrote this file did not finish (a chunk failed or the run "
                         "was stopped); the items it lacks hold fill values. Run it again.")


def netcdf_engine() -> str:
    """The xarray engine that writes NetCDF here ("netcdf4" or "h5netcdf"); `ValueError`
    with the reason when neither library is installed."""
    import importlib.util

    for module, engine in (("netCDF4", "netcdf4"), ("h5netcdf", "h5netcdf")):
        if importlib.util.find_spec(module) is not None:
            return engine
    raise ValueError("NetCDF output needs the netCDF4 or h5netcdf package: pip install netCDF4 "
                     "(or write .csv / .npz).")


def check_output_path(path) -> pathlib.Path:
    """`path` as a `Path` once it is known that a result can be written there: a suffix of
    `FORMATS`, its library installed, an existing writable folder. A `ValueError` naming the
    path and the reason otherwise, before anything is computed."""
    import importlib.util

    path = pathlib.Path(path)
    if path.suffix not in FORMATS:
        raise ValueError(f"{path}: unknown results format {path.suffix!r}; accepted: {', '.join(FORMATS)}.")
    if path.suffix == ".nc":
        netcdf_engine()
    if path.suffix == ".zarr" and importlib.util.find_spec("zarr") is None:
        raise ValueError(f"{path}: Zarr output needs the zarr package (pip install zarr), or write .nc.")
    folder = path.parent if str(path.parent) else pathlib.Path(".")
    if not folder.is_dir():
        raise ValueError(f"{path}: cannot write results, folder {folder} does not exist.")
    if not os.access(folder, os.W_OK | os.X_OK) or (path.exists() and not os.access(path, os.W_OK)):
        raise ValueError(f"{path}: cannot write results there (permission denied).")
    return path


def _attribute(value):
    if value is None:
        return "none"
    if isinstance(value, (bool, np.bool_)):
        return int(value)
    if isinstance(value, (int, float, str, np.integer, np.floating)):
        return value
    return json.dumps(value, default=str)


def _json(value):
    return value.tolist() if isinstance(value, np.ndarray | np.generic) else value


def _cell(value):
    if isinstance(value, (bool, np.bool_)):
        return str(bool(value))
    if isinstance(value, (np.integer, int)):
        return str(int(value))
    return f"{float(value):.17g}"


def _statistics(values: np.ndarray, q: Sequence[float]) -> dict:
    """The percentiles `q` ("p<q>"), mean, std and count "n" of `values` (`None` over none)."""
    stats = {f"p{g:g}": (float(np.percentile(values, g)) if values.size else None) for g in q}
    stats["mean"] = float(np.mean(values)) if values.size else None
    stats["std"] = float(np.std(values)) if values.size else None
    return stats | {"n": int(values.size)}
