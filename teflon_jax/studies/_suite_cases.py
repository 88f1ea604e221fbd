"""Several structures under the same record suite, on a Dask cluster or in one file: the
bounding cases of `run --suite --property-factors` (the nominal, upper- and lower-bound
bearings of `bounding_design`), each a `SuiteResult`, stored together on the dimensions
("case", "pair") (with "group", or "direction" and "storey"/"level", where the structure
reports them).

`suite_cases_distributed` cuts the work into (case, chunk of pairs) tasks: item k of the run is
pair k mod P of case k // P, a chunk never spans two cases, and each worker compiles the chunk
function of a case on its first chunk of that case (one compilation per case and worker). A
pair's peaks are those of `suite_peaks(build, ..., batch_size=chunk_size)` of its case bit for
bit (the argument of `_suites`' module docstring: every call has the same width).
"""

import uuid
from collections.abc import Callable, Mapping

import jax
import numpy as np

from ._cluster import (
    add_attributes,
    check_netcdf_output,
    file_attributes,
    open_finished,
    run_dtype,
    stream_to_netcdf,
    worker_cached,
)
from ._result_variables import RUN_FLAGS, SURFACE_VARIABLES, surface_layout
from ._suite_surfaces import suite_surface_labels
from ._suites import (
    _STOREY_LAYOUT,
    SUITE_GROUP_UNITS,
    SUITE_STOREY_UNITS,
    SUITE_UNITS,
    SUITE_VERTICAL_UNITS,
    SUMMARY_STATISTICS,
    SuiteResult,
    _checked_pairs,
    _chunk_peaks,
    _pair_chunks,
    _suite_function,
    suite_dataset,
    suite_from_dataset,
)


def suite_cases_distributed(
    builds: Mapping[str, Callable],
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
    storey_height: float | None = None,
    group_names=None,
    az=None,
) -> dict[str, SuiteResult]:
    """`suite_peaks` of every structure of `builds` under the same pairs on a Dask cluster, the
    peaks streamed to the NetCDF file `out` on ("case", "pair").

    **Arguments** (as `suite_peaks_distributed` otherwise): `builds`: {case name: build(ground_x,
    ground_y) -> structure}, each picklable; `storey_height` [m]: the building's, to keep the
    storey peaks (`suite_peaks(storey_height=...)`); `group_names` (G,): the bearing groups of
    a slab with overturning (default g0, g1, ...); `az`: the pairs' vertical components (each
    build then takes three signals, `suite_peaks`).

    **Returns:** {case: `SuiteResult`} read back from `out` (`open_suite_cases`); each case's
    peaks are those of `suite_peaks(builds[case], ..., batch_size=chunk_size)` bit for bit.
    """
    out = check_netcdf_output(out)
    cases = tuple(str(c) for c in builds)
    if not cases:
        raise ValueError("builds: give at least one case.")
    names, grounds, chunk, retries = _checked_pairs(names, ax, ay, chunk_size, retries, az)
    count = len(names)
    dtype = run_dtype()
    spec = {"builds": tuple(builds.values()), "n_pairs": count, "time_step": float(time_step),
            "duration": float(duration), "storey_height": None if storey_height is None else float(storey_height), "chunk": chunk,
            "dtype": dtype, "token": uuid.uuid4().hex}
    shapes = jax.eval_shape(_case_function(spec, 0),
                            *(jax.ShapeDtypeStruct((chunk, g.shape[1]), dtype) for g in grounds))[0]
    settings = {"n_pairs": count, "cases": ",".join(cases), "record_time_step_s": float(time_step),
                "duration_s": float(duration), "scheduler": scheduler, "chunk_size": chunk, "precision": dtype}
    labels = suite_surface_labels(spec["builds"][0], time_step, grounds)[1]  # every case: the same isolator
    layout = _cases_layout(cases, names, shapes, group_names, {**settings, **(attrs or {})}, labels)

    def write(handle, start, stop, part):
        case, first = divmod(start, count)
        for name, values in part.items():
            handle.variables[name][case, first:first + stop - start] = (
                values.astype(np.int8) if name in ("converged", *RUN_FLAGS) else values)

    chunks = [item for c in range(len(cases)) for item in _pair_chunks(grounds, chunk, offset=c * count)]
    stream_to_netcdf(out, layout, _case_task, spec, chunks, write, scheduler=scheduler,
                     connect_timeout=connect_timeout, compilation_cache=compilation_cache, retries=retries,
                     progress=progress, what="case-pair items")
    results = open_suite_cases(out)
    add_attributes(out, _case_summary_attrs(results))
    return results


def _case_function(spec: dict, case: int):
    return _suite_function(spec["builds"][case], spec["time_step"], spec["duration"], spec["storey_height"])


def _case_task(spec: dict, start: int, stop: int, payload):
    """Peaks of items start..stop-1, pairs of one case (a Dask task; runs on a worker)."""
    functions = worker_cached(spec, lambda s: {})  # case -> its compiled chunk function
    case = start // spec["n_pairs"]
    if case not in functions:
        functions[case] = _case_function(spec, case)
    return _chunk_peaks(functions[case], spec["chunk"], stop - start, payload)


def _cases_layout(cases, names, shapes: dict, group_names, attrs: dict, labels: dict) -> dict:
    """`create_netcdf`'s arguments: every reported peak on ("case", "pair") and its own axes
    (the surfaces' labelled by `labels`, `surface_attributes`)."""
    dims = {"case": len(cases), "pair": len(names)}
    coords = {"case": ("case", np.array(cases, dtype=str), None, "structure (bounding case)"),
              "pair": ("pair", np.array(names, dtype=str), None, "record pair")}
    variables = {"converged": (("case", "pair"), *SUITE_UNITS["converged"], "bool")}
    for name, shape in shapes.items():
        if name in SURFACE_VARIABLES:
            continue  # below
        if name in _STOREY_LAYOUT:
            axis, units, long_name = _STOREY_LAYOUT[name]
            dims |= {"direction": 2, axis: shape.shape[-1]}
            coords["direction"] = ("direction", np.array(["x", "y"]), None, None)
            variables[name] = (("case", "pair", "direction", axis), units, long_name, "f8")
        elif name in RUN_FLAGS:
            variables[name] = (("case", "pair"), *RUN_FLAGS[name], "bool")
        elif name.startswith("group_"):
            width = shape.shape[-1]
            groups = [f"g{i}" for i in range(width)] if group_names is None else [str(g) for g in group_names]
            if len(groups) != width:
                raise ValueError(f"group_names: {len(groups)} names for the structure's {width} bearing groups.")
            dims["group"] = width
            coords["group"] = ("group", np.array(groups, dtype=str), None, "bearing group")
            variables[name] = (("case", "pair", "group"), *SUITE_GROUP_UNITS[name.removeprefix("group_")], "f8")
        else:
            variables[name] = (("case", "pair"), *{**SUITE_UNITS, **SUITE_VERTICAL_UNITS, **SUITE_STOREY_UNITS}[name],
                               "f8")
    surfaces = {name: shape.shape for name, shape in shapes.items() if name in SURFACE_VARIABLES}
    surface_dims, surface_coords, surface_variables = surface_layout(surfaces, labels, group_names, ("case", "pair"))
    dims, coords, variables = dims | surface_dims, surface_coords | coords, variables | surface_variables
    return {"dims": dims, "coords": coords, "variables": variables,
            "attrs": file_attributes("teflon-jax record suite peak responses, several structures", attrs)}


def _case_summary_attrs(results: Mapping[str, SuiteResult]) -> dict:
    return {f"{case}_{k}_{s}": v[s] for case, r in results.items() for k, v in r.summary.items()
            for s in SUMMARY_STATISTICS}


def open_suite_cases(path) -> dict[str, SuiteResult]:
    """{case: `SuiteResult`} of a file of several structures under one suite
    (`suite_cases_distributed`, `save_suite_cases`), refused while it is incomplete."""
    dataset = open_finished(path)
    return {str(c): suite_from_dataset(dataset.isel(case=i)) for i, c in enumerate(dataset["case"].values)}


def save_suite_cases(results: Mapping[str, SuiteResult], path, attrs: dict | None = None) -> None:
    """One NetCDF file of every case (`suite_dataset` of each, stacked on "case"), with each
    case's mean, least and largest value in the attributes `<case>_<peak>_<stat>` and `attrs` added."""
    import pathlib

    import xarray

    dataset = xarray.concat([suite_dataset(r) for r in results.values()], dim="case", combine_attrs="drop_conflicts")
    dataset = dataset.assign_coords(case=("case", np.array(list(results), dtype=str)))
    dataset.attrs = {"Conventions": "CF-1.8", "title": "teflon-jax record suite peak responses, several structures",
                     **(attrs or {}), **_case_summary_attrs(results)}
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    dataset.to_netcdf(path)
