"""Record suites: many two-component record pairs (e.g. the 7 or 11 pairs of a design check,
each with its scale factor, and optionally each with its vertical component) through one
bidirectional structure in one vmapped call, with the peaks of every pair, their mean, least
and largest value (failed runs kept out of all three and reported).

`suite_peaks_distributed` runs the same pairs as chunks on a Dask cluster (`_cluster`),
streaming each chunk's peaks into a NetCDF file of the layout `suite_dataset` writes. A pair's
peaks depend on the width of the vmapped call that computed it only in the last digits (XLA's
vectorised CPU code rounds differently for another batch width; seen: 3e-16 relative): with
`chunk_size` equal to the in-process `batch_size` they are the same bit for bit, whatever the
number of workers and whichever worker ran a chunk (every call of a run has the same width:
the last chunk is padded with copies of its last pair).
"""

import dataclasses
import json
import uuid

import jax
import jax.numpy as jnp
import numpy as np

from ..excitation import uniform_signal
from ..systems import (
    flag_pressure_law,
    pressure_law_valid,
    simulate_history,
    step_count,
    step_load_factors,
    uplift_time,
)
from ._cluster import (
    add_attributes,
    check_count,
    check_netcdf_output,
    file_attributes,
    lanes,
    open_finished,
    run_dtype,
    stream_to_netcdf,
    worker_cached,
)
from ._montecarlo_parts import surface_peaks
from ._reducers import response_layout, response_peaks
from ._result_variables import (
    BEYOND_PRESSURE_LAW,
    RUN_FLAGS,
    SURFACE_VARIABLES,
    TIPPED,
    surface_layout,
    surface_shapes,
)
from ._suite_surfaces import (
    split_surfaces,
    suite_surface_columns,
    suite_surface_labels,
    surface_dataset_parts,
    surfaces_from_dataset,
)

SUITE_PEAKS = ("base_disp_resultant_m", "base_disp_x_m", "base_disp_y_m", "base_shear_ratio_resultant")
SUITE_UNITS = {
    "base_disp_resultant_m": ("m", "peak resultant base displacement sqrt(u_x^2 + u_y^2)"),
    "base_disp_x_m": ("m", "peak |base displacement| in x"),
    "base_disp_y_m": ("m", "peak |base displacement| in y"),
    "base_shear_ratio_resultant": ("1", "peak resultant horizontal force above the bearings / weight"),
    "converged": ("1", "every time step's Newton solve converged (False: peaks not trusted)"),
}
"""Variables of a suite's NetCDF file on the "pair" dimension: name -> (units, long name)."""

SUITE_STOREY_UNITS = {
    "storey_drift_max_resultant": ("1", "largest peak resultant interstorey drift / storey height over "
                                   "the storeys (the building, suite_peaks(storey_height=...))"),
}
"""A suite's storey variable, when `suite_peaks` was given the building's storey height."""

SUITE_GROUP_UNITS = {
    "peak_N": ("N", "peak normal load N_g of the bearing group (overturning of a slab)"),
    "min_N": ("N", "least normal load N_g of the bearing group (negative: the tension a bonded support would need)"),
    "uplift_time_s": ("s", "time the bearing group is uplifted (N_g <= 0)"),
}
"""A slab's per-group variables on ("pair", "group") when its plan has overturning: the keys of
`run`'s "normal_load" groups (`slab_on_bearings(height_of_centre_of_mass=...)`)."""

SUITE_VERTICAL_UNITS = {
    "uplift_time_s": ("s", "time the isolators are uplifted, N = W max(1 + a_v / g, 0) <= 0 at a step's end "
                      "(no shear carried)"),
    "min_load_factor": ("1", "least normal load over the weight, N / W, under the vertical component"),
    "max_load_factor": ("1", "largest normal load over the weight, N / W, under the vertical component"),
}
"""A suite's variables on the "pair" dimension when its pairs have vertical components
(`suite_peaks(az=...)`): what `run --record-z` reports as its `uplift`."""

_ALL_UNITS = {**SUITE_UNITS, **SUITE_VERTICAL_UNITS, **SUITE_STOREY_UNITS}
_STOREY_LAYOUT = {
    "storey_drift": ("storey", "1", "peak |interstorey drift| / storey height (storey j: level j-1 to j)"),
    "level_acceleration": ("level", "m s-2", "peak |total acceleration| of the level (0: base slab)"),
}


@dataclasses.dataclass(frozen=True)
class SuiteResult:
    """Peaks per pair (arrays (P,)), `converged` (P,), the pair `names`, and `summary`:
    {peak name: {"mean": ..., "min": ..., "max": ...}} over the converged pairs; `storeys`: the building's
    `storey_drift` (P, 2, S) [-] and `level_acceleration` (P, 2, S + 1) [m/s^2] in x and y
    (`suite_peaks(storey_height=...)`, `directional_storeys`), else `None`; `groups`: a slab
    with overturning, {"names": (G,), "peak_N", "min_N", "uplift_time_s": (P, G)} (each
    group's N_g, `SUITE_GROUP_UNITS`), else `None`; `beyond_pressure_law` (P,) bool with
    vertical components: the pairs whose loads took the bearings beyond Table 1's pressure law
    (`BEYOND_PRESSURE_LAW`; not converged, their peaks not trusted), else `None`; `tipped`
    (P,) bool on a plan's overturning loads: the pairs whose first unbalanced step tipped the
    slab (`TIPPED`; the other unconverged pairs' Newton balance missed its tolerance), else
    `None`; `surfaces`: a series pendulum's sliders' peak travel `slider_travel` (P, G, S) [m]
    and the heated surfaces' peak temperature rise `surface_temperature_rise` (P, G, H) [K]
    where the isolator has them, with their labels "slider_names", "heated_surface_names" and
    "group_names" (`_suite_surfaces`; in `summary` as their table columns), else `None`."""

    names: tuple
    peaks: dict
    converged: np.ndarray
    summary: dict
    storeys: dict | None = None
    groups: dict | None = None
    beyond_pressure_law: np.ndarray | None = None
    tipped: np.ndarray | None = None
    surfaces: dict | None = None

    @property
    def surface_peaks(self) -> dict:
        """{"<name>_<unit>_[<group>_]<surface>": (P,)}: the `surfaces` as the table's columns."""
        return suite_surface_columns(self.surfaces)


def _suite_function(build, time_step: float, duration: float, storey_height=None):
    """The jitted function (ax (B, n), ay (B, n)[, az (B, n)]) -> (peaks {name: (B, ...)},
    converged (B,)): the reducers (`response_peaks`) over each pair's `StructureResponse`,
    whatever the structure and isolator; with `storey_height` [m] (the building) also the
    largest resultant drift ratio over the storeys, |(q_j - q_(j-1))_x, (q_j - q_(j-1))_y| / h,
    and the peaks per storey, level and direction; with vertical components, each pair's uplift
    (`vertical_values`) and whether its loads took the bearings beyond Table 1's pressure law
    ("beyond_pressure_law": the pair runs on, `flag_pressure_law`, and is not converged). The
    base's coordinates come from the structure (`response_layout`)."""

    def one(*grounds):
        system = flag_pressure_law(build(*(uniform_signal(g, time_step) for g in grounds)))
        response = simulate_history(system, duration, throw=False)
        layout = response_layout(system)
        values = suite_values(surface_peaks(system, response_peaks(layout, response, storey_height)))
        if layout.overturning and response.tipped is not None:  # did the first unbalanced step tip the slab
            values["tipped"] = ~response.succeeded & response.tipped[jnp.argmin(response.converged)]
        if len(grounds) == 2:
            return values, response.succeeded
        within = jnp.all(pressure_law_valid(system, response))
        values |= vertical_values(system, duration) | {"beyond_pressure_law": ~within}
        return values, response.succeeded & within

    return jax.jit(jax.vmap(one))


def vertical_values(system, duration: float) -> dict:
    """The uplift of one pair under its vertical component (`SUITE_VERTICAL_UNITS`): the load
    factor N / W (`system.load_factor`) at the structure's steps over `duration` [s], the time
    of the steps whose end has N <= 0 (`systems.uplift_time`), its least and largest value."""
    dt = system.time_step
    loads = step_load_factors(system, step_count(dt, duration))
    return {"uplift_time_s": uplift_time(loads, dt), "min_load_factor": jnp.min(loads),
            "max_load_factor": jnp.max(loads)}


def suite_values(peaks: dict) -> dict:
    """A suite's variables of one pair from its reducers' peaks (`response_peaks`): the base's
    displacement and shear (`SUITE_PEAKS`), a building's storeys (`storey_drift_max_resultant`,
    `storey_drift` (2, S) [-], `level_acceleration` (2, S + 1) [m/s^2]) where its storey height
    was given, a slab's group loads with overturning (`group_peak_N`, `group_min_N`,
    `group_uplift_time_s`), the isolator's surfaces (`SURFACE_VARIABLES`, (G, S) each) where
    it has them."""
    out = {"base_disp_resultant_m": peaks["base_disp_resultant"], "base_disp_x_m": peaks["base_disp"][0],
           "base_disp_y_m": peaks["base_disp"][1], "base_shear_ratio_resultant": peaks["base_shear_ratio_resultant"]}
    if "storey_drift_ratio" in peaks:
        out |= {"storey_drift_max_resultant": jnp.max(peaks["storey_drift_ratio_resultant"]),
                "storey_drift": peaks["storey_drift_ratio"], "level_acceleration": peaks["level_acceleration"]}
    out |= {name: peaks[name] for name in SURFACE_VARIABLES if name in peaks}
    return out | {f"group_{k}": v for k, v in peaks.get("group_normal_load", {}).items()}


SUMMARY_STATISTICS = ("mean", "min", "max")
"""The rows of a suite's summary over its converged pairs: the least one is the worst of a
variable that matters when small (`min_load_factor`), the largest of a peak."""


def _summary(peaks: dict, ok: np.ndarray) -> dict:
    reducers = {"mean": np.mean, "min": np.min, "max": np.max}
    return {k: {stat: float(reducers[stat](v[ok])) if ok.any() else float("nan") for stat in SUMMARY_STATISTICS}
            for k, v in peaks.items()}


def suite_peaks(build, names, ax, ay, time_step: float, duration: float,
                batch_size: int | None = None, storey_height: float | None = None,
                group_names=None, az=None) -> SuiteResult:
    """Run P record pairs through the structure `build(ground_x, ground_y)` in one vmapped call
    (or in calls of `batch_size` pairs, the last padded: one compilation).

    **Arguments:** `build`: a function of two `Signal`s returning a `StructureOnSliders` under
    both (planar, or on triple or double pendulums with `ground_y`), of
    three with `az` (the third the vertical component, `systems.with_vertical_motion`);
    `names` (P,); `ax`, `ay` (P, n) ground accelerations [m/s^2] (already scaled, common step);
    `az` (P, n) [m/s^2, up +] the pairs' vertical components on the same grid, or `None`
    (the peaks then hold each pair's uplift too, `SUITE_VERTICAL_UNITS`);
    `time_step` [s] of the records; `duration` [s]; `storey_height` [m]: the
    building's storey height, to keep `storey_drift_max_resultant` and `SuiteResult.storeys` too;
    `group_names` (G,): the bearing groups of a plan (default g0, g1, ...), the labels of a
    slab's loads with overturning and of the surfaces.

    **Returns:** a `SuiteResult`; the base shear ratio is the total horizontal force on the
    structure above the bearings over its weight.
    """
    names = tuple(names)
    count = len(names)
    width = count if batch_size is None else min(check_count("batch_size", batch_size, 1), count)
    grounds = _grounds(count, ax, ay, az)
    function = _suite_function(build, time_step, duration, storey_height)
    parts = []
    for start in range(0, count, width):
        index = lanes(start, min(start + width, count), width)
        parts.append(jax.device_get(function(*(jnp.asarray(g[index]) for g in grounds))))
    joined = {k: np.concatenate([p[0][k] for p in parts])[:count] for k in parts[0][0]}
    surfaces = split_surfaces(joined, suite_surface_labels(build, time_step, grounds)[1], group_names)
    flags = {name: None if name not in joined else joined.pop(name).astype(bool) for name in RUN_FLAGS}
    groups = {k.removeprefix("group_"): joined.pop(k) for k in list(joined) if k.startswith("group_")} or None
    if groups is not None:
        width = groups["peak_N"].shape[1]
        groups["names"] = tuple(f"g{i}" for i in range(width)) if group_names is None else tuple(group_names)
        if len(groups["names"]) != width:
            raise ValueError(f"group_names: {len(groups['names'])} names for the structure's {width} groups.")
    peaks = {k: v for k, v in joined.items() if v.ndim == 1}
    storeys = {k: v for k, v in joined.items() if v.ndim > 1} or None
    ok = np.concatenate([np.asarray(p[1], dtype=bool) for p in parts])[:count]
    return SuiteResult(names=names, peaks=peaks, converged=ok, summary=_summary({**peaks, **suite_surface_columns(surfaces)}, ok),
                       storeys=storeys, groups=groups, surfaces=surfaces, **flags)


def _grounds(count: int, ax, ay, az=None) -> tuple:
    """(ax, ay[, az]) as float arrays (P, n) for the `count` pair names; `ValueError` naming the
    arrays whose shapes differ."""
    grounds = tuple(np.asarray(g, dtype=float) for g in (ax, ay) + (() if az is None else (az,)))
    names = "ax, ay" + ("" if az is None else ", az")
    if count < 1 or any(g.shape != grounds[0].shape for g in grounds) or grounds[0].ndim != 2 \
            or grounds[0].shape[0] != count:
        raise ValueError(f"{names}: need (P, n) arrays of one shape for the {count} pair names, got "
                         f"{', '.join(str(g.shape) for g in grounds)}.")
    return grounds


def _checked_pairs(names, ax, ay, chunk_size, retries, az=None):
    """(names, grounds (ax, ay[, az]), chunk, retries) of a suite run on a cluster: the P pair
    names as strings, the (P, n) ground accelerations as float arrays (`_grounds`), the chunk
    width (at most P) and the retries, each refused by name where it is wrong."""
    names = tuple(str(n) for n in names)
    grounds = _grounds(len(names), ax, ay, az)
    return names, grounds, min(check_count("chunk_size", chunk_size, 1), len(names)), check_count("retries", retries, 0)


def _pair_chunks(grounds, chunk: int, offset: int = 0) -> list:
    """`stream_to_netcdf`'s chunks of the pairs: (offset + start, offset + stop, rows of each of
    `grounds` (ax, ay[, az]))."""
    count = grounds[0].shape[0]
    return [(offset + start, offset + min(start + chunk, count), tuple(g[start:start + chunk] for g in grounds))
            for start in range(0, count, chunk)]


def _chunk_peaks(function, chunk: int, count: int, payload) -> dict:
    """The peaks and "converged" of the first `count` pairs of `payload` (ax, ay[, az]), run
    through the chunk function at its width `chunk` (the rest padded with copies of the last
    pair)."""
    index = lanes(0, count, chunk)
    peaks, ok = function(*(jnp.asarray(g[index]) for g in payload))
    out = {k: np.asarray(v)[:count] for k, v in peaks.items()}
    out["converged"] = np.asarray(ok, dtype=bool)[:count]
    return out


def _suite_task(spec: dict, start: int, stop: int, payload):
    """Peaks of pairs start..stop-1 (a Dask task; runs on a worker)."""
    function = worker_cached(spec, lambda s: _suite_function(s["build"], s["time_step"], s["duration"]))
    return _chunk_peaks(function, spec["chunk"], stop - start, payload)


def suite_peaks_distributed(
    build,
    names,
    ax,
    ay,
    time_step: float,
    duration: float,
    *,
    out,
    scheduler: str = "local:2",
    chunk_size: int = 8,
    retries: int = 2,
    connect_timeout: float = 10.0,
    compilation_cache=None,
    progress=None,
    attrs: dict | None = None,
    group_names=None,
    az=None,
) -> SuiteResult:
    """`suite_peaks` on a Dask cluster, chunks of `chunk_size` pairs as tasks, the peaks
    streamed to the NetCDF file `out` (checked writable before anything starts).

    **Arguments** (as `suite_peaks` otherwise; `build` must pickle, e.g. a module-level
    function or a closure over plain values and equinox modules): `scheduler` "local:N" or a
    scheduler address; `retries`: runs again of a task that raised (a dead worker's tasks are
    rerun whatever this is); `connect_timeout` [s]; `compilation_cache`: folder of JAX's
    persistent compilation cache (local workers); `progress(done, total)` after each chunk;
    `attrs`: more attributes of the file (the run's inputs); `group_names` (G,): the bearing
    groups of a plan, the labels of the "group" axis of the per-group loads of a slab with
    overturning (`SuiteResult.groups`; a structure that reports them needs them) and of the
    surfaces (default g0, g1, ...); `az`: the pairs' vertical
    components (`suite_peaks`).

    **Returns:** the `SuiteResult` read back from `out` (`open_suite`): each pair's peaks are
    those of `suite_peaks(..., batch_size=chunk_size)` bit for bit, whatever the number of
    workers (module docstring).
    `ConnectionError` naming the address when no scheduler answers.
    """
    out = check_netcdf_output(out)
    names, grounds, chunk, retries = _checked_pairs(names, ax, ay, chunk_size, retries, az)
    count = len(names)
    dtype = run_dtype()
    spec = {"build": build, "time_step": float(time_step), "duration": float(duration),
            "chunk": chunk, "dtype": dtype,
            "token": uuid.uuid4().hex}
    settings = {"n_pairs": count, "record_time_step_s": float(time_step), "duration_s": float(duration),
                "scheduler": scheduler, "chunk_size": chunk, "precision": dtype}

    groups = None if group_names is None else tuple(str(g) for g in group_names)
    surfaces = surface_shapes(*suite_surface_labels(build, time_step, grounds))

    def write(handle, start, stop, part):
        reported = {k.removeprefix("group_") for k in part if k.startswith("group_")}
        width = part["group_peak_N"].shape[1] if reported else 0
        if reported and width != (0 if groups is None else len(groups)):
            raise ValueError(f"group_names: {0 if groups is None else len(groups)} names for the structure's "
                             f"{width} bearing groups with per-group loads (a slab with overturning).")
        flags = ("converged", *RUN_FLAGS)
        for name in (*SUITE_UNITS, *(SUITE_VERTICAL_UNITS if az is not None else ()),
                     *(("beyond_pressure_law",) if az is not None else ()), *(("tipped",) if reported else ())):
            values = part[name].astype(np.int8) if name in flags else part[name]
            handle.variables[name][start:stop] = values
        for name in reported:
            handle.variables[f"group_{name}"][start:stop, :] = part[f"group_{name}"]
        for name in surfaces[0]:
            handle.variables[name][start:stop] = part[name]

    chunks = _pair_chunks(grounds, chunk)
    layout = _suite_layout(names, {**settings, **(attrs or {})}, groups, az is not None, surfaces)
    stream_to_netcdf(out, layout, _suite_task, spec, chunks, write,
                     scheduler=scheduler, connect_timeout=connect_timeout, compilation_cache=compilation_cache,
                     retries=retries, progress=progress, what="pairs")
    result = open_suite(out)
    add_attributes(out, _summary_attrs(result.summary))
    return result


def _summary_attrs(summary: dict) -> dict:
    return {f"{k}_{s}": v[s] for k, v in summary.items() for s in SUMMARY_STATISTICS}


def _suite_layout(names, attrs: dict, groups=None, vertical: bool = False, surfaces=({}, {})) -> dict:
    """`create_netcdf`'s arguments for a suite's file (the layout of `suite_dataset`), with the
    slab's per-group variables on ("pair", "group") where `groups` names them, the uplift
    (`SUITE_VERTICAL_UNITS`) with `vertical` components and the isolator's `surfaces`
    (`surface_shapes`) on ("pair", "group", surface)."""
    units = {**SUITE_UNITS, **(SUITE_VERTICAL_UNITS if vertical else {})}
    if vertical:
        units["beyond_pressure_law"] = BEYOND_PRESSURE_LAW
    if groups is not None:
        units["tipped"] = TIPPED
    variables = {name: (("pair",), unit, long_name, "bool" if name in ("converged", *RUN_FLAGS) else "f8")
                 for name, (unit, long_name) in units.items()}
    dims = {"pair": len(names)}
    coords = {"pair": ("pair", np.array(names, dtype=str), None, "record pair")}
    if groups is not None:
        dims["group"] = len(groups)
        coords["group"] = ("group", np.array(groups, dtype=str), None, "bearing group")
        variables |= {f"group_{name}": (("pair", "group"), units, long_name, "f8")
                      for name, (units, long_name) in SUITE_GROUP_UNITS.items()}
    surface_dims, surface_coords, surface_variables = surface_layout(*surfaces, groups, ("pair",))
    dims, coords, variables = dims | surface_dims, surface_coords | coords, variables | surface_variables
    return {"dims": dims, "coords": coords, "variables": variables,
            "attrs": file_attributes("teflon-jax record suite peak responses", attrs)}


def suite_dataset(result: SuiteResult, attrs: dict | None = None):
    """The suite as an `xarray.Dataset`: the peaks and `converged` on the "pair" dimension
    (labelled by the pair names) with units and long names, the mean, least and largest
    value over the converged pairs in the attributes (`<peak>_mean`, `<peak>_min`, `<peak>_max`), `attrs` added."""
    import xarray

    data = {k: ("pair", np.asarray(result.peaks[k]), {"units": u, "long_name": n})
            for k, (u, n) in _ALL_UNITS.items() if k in result.peaks}
    units, long_name = SUITE_UNITS["converged"]
    data["converged"] = ("pair", np.asarray(result.converged, bool), {"units": units, "long_name": long_name})
    for name, (units, long_name) in RUN_FLAGS.items():
        if getattr(result, name) is not None:
            data[name] = ("pair", np.asarray(getattr(result, name), bool), {"units": units, "long_name": long_name})
    file_attrs = {"Conventions": "CF-1.8", "title": "teflon-jax record suite peak responses",
                  "teflon_jax_attrs": json.dumps(attrs or {}), **(attrs or {}), **_summary_attrs(result.summary)}
    coords = {"pair": ("pair", np.array(result.names, dtype=str), {"long_name": "record pair"})}
    for name, (dim, units, long_name) in ({} if result.storeys is None else _STOREY_LAYOUT).items():
        data[name] = (("pair", "direction", dim), np.asarray(result.storeys[name]), {"units": units, "long_name": long_name})
    if result.storeys is not None:
        coords["direction"] = ("direction", np.array(["x", "y"]))
    if result.groups is not None:
        coords["group"] = ("group", np.array(result.groups["names"], dtype=str), {"long_name": "bearing group"})
        for name, (units, long_name) in SUITE_GROUP_UNITS.items():
            data[f"group_{name}"] = (("pair", "group"), np.asarray(result.groups[name]),
                                     {"units": units, "long_name": long_name})
    surface_data, surface_coords = surface_dataset_parts(result.surfaces)
    data, coords = data | surface_data, surface_coords | coords
    return xarray.Dataset(data, coords=coords, attrs=file_attrs)


def open_suite(path) -> SuiteResult:
    """The `SuiteResult` a suite NetCDF file holds (`save_suite`, `suite_peaks_distributed`)."""
    return suite_from_dataset(open_finished(path))


def suite_from_dataset(dataset) -> SuiteResult:
    """The `SuiteResult` of a loaded suite Dataset (one bounding case of a file with a "case"
    dimension too, selected with `isel(case=i)`)."""
    peaks = {k: np.asarray(dataset[k].values, dtype=float) for k in _ALL_UNITS
             if k != "converged" and k in dataset}
    ok = np.asarray(dataset["converged"].values, dtype=bool)
    names = tuple(str(n) for n in dataset["pair"].values)
    storeys = {k: np.asarray(dataset[k].values, dtype=float) for k in _STOREY_LAYOUT if k in dataset} or None
    groups = None
    if "group_peak_N" in dataset:
        groups = {k: np.asarray(dataset[f"group_{k}"].values, dtype=float) for k in SUITE_GROUP_UNITS}
        groups["names"] = tuple(str(g) for g in dataset["group"].values)
    flags = {name: np.asarray(dataset[name].values, bool) if name in dataset else None for name in RUN_FLAGS}
    surfaces = surfaces_from_dataset(dataset)
    return SuiteResult(names=names, peaks=peaks, converged=ok, summary=_summary({**peaks, **suite_surface_columns(surfaces)}, ok),
                       storeys=storeys, groups=groups, surfaces=surfaces, **flags)


def _group_columns(result: SuiteResult) -> dict:
    """{"<group>_peak_N" ...: (P,)}: a slab's per-group columns of the suite table (or {})."""
    if result.groups is None:
        return {}
    return {f"{g}_{k}": np.asarray(result.groups[k])[:, j]
            for j, g in enumerate(result.groups["names"]) for k in SUITE_GROUP_UNITS}


def save_suite(result: SuiteResult, table_path=None, netcdf_path=None, attrs: dict | None = None) -> None:
    """One CSV table (a row per pair, then mean, min and max rows) and one NetCDF file
    (`suite_dataset`, `attrs` the run's inputs)."""
    import pathlib

    if table_path is not None:
        path = pathlib.Path(table_path)
        path.parent.mkdir(parents=True, exist_ok=True)
        names = [k for k in _ALL_UNITS if k in result.peaks]
        groups = _group_columns(result)
        surfaces = result.surface_peaks
        flags = {name: getattr(result, name) for name in RUN_FLAGS if getattr(result, name) is not None}
        lines = ["pair," + ",".join(names + list(groups) + list(surfaces)) + ",converged"
                 + "".join(f",{k}" for k in flags)]
        for i, name in enumerate(result.names):
            row = ",".join([f"{result.peaks[k][i]:.6g}" for k in names] + [f"{v[i]:.6g}" for v in groups.values()]
                           + [f"{v[i]:.6g}" for v in surfaces.values()])
            lines.append(f"{name},{row},{bool(result.converged[i])}" + "".join(f",{bool(v[i])}" for v in flags.values()))
        for stat in SUMMARY_STATISTICS:
            lines.append(f"{stat}," + ",".join([f"{result.summary[k][stat]:.6g}" for k in names] + [""] * len(groups)
                                               + [f"{result.summary[k][stat]:.6g}" for k in surfaces])
                         + "," + "," * len(flags))
        path.write_text("\n".join(lines) + "\n")
    if netcdf_path is not None:
        path = pathlib.Path(netcdf_path)
        path.parent.mkdir(parents=True, exist_ok=True)
        suite_dataset(result, attrs).to_netcdf(path)
