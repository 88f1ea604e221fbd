"""The Dask engine shared by the distributed studies (Monte Carlo, record suites, design sweeps).

A study cuts its work into chunks of consecutive items (motions, record pairs, design points);
each chunk is one Dask task. A task runs on a worker through one compiled, vmapped function
that the worker builds on its first chunk and keeps for the run (`worker_cached`), so a worker
compiles once whatever the number of its chunks. The driver (`run_chunks`) writes each finished
chunk into a NetCDF file created beforehand with the full layout (`create_netcdf`), at the
chunk's place, and forgets it: its memory holds the chunks in flight, not the run. A worker
that dies takes only its running chunks with it; the scheduler runs them again elsewhere. A
task that raises is run again `retries` times; after that the run stops with an error naming
the chunk (its items) and the reason. `stream_to_netcdf` is a whole run as the three studies
(`monte_carlo_distributed`, `suite_peaks_distributed`, `design_sweep_distributed`) make it:
client, file, chunks, and the `complete` attribute that `open_finished` (and
`MonteCarloResult.open`) read before trusting a file.

Schedulers (`start_client`): "local:N" starts a `LocalCluster` of N single-threaded worker
processes on this machine, in the caller's precision (`JAX_ENABLE_X64`, set before the workers
start); any other string is the address of a running scheduler ("tcp://host:8786"), e.g. one
of `dask-jobqueue` on a SLURM or PBS queue (docs/distributed.md); an address that does not
answer within `connect_timeout` seconds is a `ConnectionError` naming it. Remote workers in
another precision than the driver fail their first task with an error naming `JAX_ENABLE_X64`.
"""

import contextlib
import json
import pathlib
import time
from collections.abc import Callable, Mapping, Sequence

import jax.numpy as jnp
import numpy as np

from ._results import check_complete, check_output_path

_CACHE: dict = {}  # per worker process: run token -> compiled chunk function


def run_dtype() -> str:
    """The float type JAX computes in here ("float64" or "float32")."""
    return str(jnp.result_type(float))


class ClusterRunError(RuntimeError):
    """A chunk of a distributed run failed on the cluster after its retries (the run stopped)."""


def worker_cached(spec: Mapping, build: Callable):
    """The chunk function of the run `spec["token"]` on this worker, built by `build(spec)` on
    the first chunk and kept for the later ones (one run at a time per worker). Raises when
    this worker computes in another precision than `spec["dtype"]`, the driver's."""
    dtype = run_dtype()
    if dtype != spec["dtype"]:
        raise RuntimeError(
            f"worker computes in {dtype} but the run asked for {spec['dtype']}: start the workers "
            f"with JAX_ENABLE_X64={'1' if spec['dtype'] == 'float64' else '0'}."
        )
    function = _CACHE.get(spec["token"])
    if function is None:
        function = build(spec)
        _CACHE.clear()
        _CACHE[spec["token"]] = function
    return function


def lanes(start: int, stop: int, width: int) -> np.ndarray:
    """Item indices start..stop-1 padded to `width` with copies of the last one: every call
    of a chunk function has the same batch width (one compilation)."""
    return np.minimum(np.arange(start, start + width), stop - 1)


def check_netcdf_output(out, flag: str = "out") -> pathlib.Path:
    """`out` as a `Path` once it is known that a NetCDF file can be written there (suffix
    ".nc", library installed, writable folder); a `ValueError` naming `flag` otherwise, before
    anything is computed or a cluster is started."""
    try:
        path = check_output_path(out)
    except ValueError as error:
        raise ValueError(f"{flag}: {error}") from None
    if path.suffix != ".nc":
        raise ValueError(f"{flag}: {path}: a distributed run streams its results to NetCDF; give a .nc file.")
    return path


def check_count(name: str, value, low: int) -> int:
    """`value` as an int when it is an integer >= `low`; a `ValueError` naming `name` otherwise."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < low:
        raise ValueError(f"{name}: must be an integer >= {low}, got {value!r}.")
    return int(value)


def start_client(scheduler, connect_timeout: float, dtype: str, cache_dir=None):
    """(Client, LocalCluster or None) for "local:N" or a scheduler address (module docstring)."""
    from distributed import Client, LocalCluster

    if not isinstance(scheduler, str):
        raise ValueError(f"scheduler: give 'local:N' or a scheduler address, got {scheduler!r}.")
    if scheduler.startswith("local:"):
        try:
            workers = int(scheduler.split(":", 1)[1])
        except ValueError:
            workers = 0
        if workers < 1:
            raise ValueError(f"scheduler: 'local:N' needs a number of workers N >= 1, got {scheduler!r}.")
        env = {"JAX_ENABLE_X64": "1" if dtype == "float64" else "0", "JAX_PLATFORMS": "cpu"}
        if cache_dir is not None:
            env["JAX_COMPILATION_CACHE_DIR"] = str(cache_dir)
            env["JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS"] = "0"
        # set before the worker processes start: JAX reads them when it is first imported,
        # which may be as soon as the worker unpickles the caller's main module
        import dask

        spawn_env = {**dask.config.get("distributed.nanny.pre-spawn-environ", {}), **env}
        with dask.config.set({"distributed.nanny.pre-spawn-environ": spawn_env}):
            # the status page on a free port: None would mean the default 8787, which a second
            # local cluster on the machine finds taken (Dask then retries, leaking a socket)
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                   dashboard_address=":0")
        return Client(cluster), cluster
    try:
        return Client(scheduler, timeout=connect_timeout), None
    except (OSError, TimeoutError) as error:
        raise ConnectionError(
            f"scheduler: no Dask scheduler answered at {scheduler} within {connect_timeout:g} s "
            f"({type(error).__name__}: {error}); check the address and that the scheduler runs."
        ) from None


@contextlib.contextmanager
def cluster_client(scheduler, connect_timeout: float, dtype: str, cache_dir=None):
    """`start_client` as a context: the client (and a local cluster) closed on leaving."""
    client, cluster = start_client(scheduler, connect_timeout, dtype, cache_dir)
    try:
        yield client
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def create_netcdf(path, dims: Mapping, coords: Mapping, variables: Mapping, attrs: Mapping):
    """An open NetCDF4 file with the full layout of a run, its data still unwritten.

    `dims`: name -> size; `coords`: name -> (dim, values, units or None, long name or None), the
    variables written now (coordinates, and inputs such as the design variables of each variant);
    `variables`: name -> (dims tuple, units, long name, kind) with kind "f8", "i8" or "bool"
    (stored as int8 with the `dtype: bool` attribute xarray decodes back to bool); `attrs`:
    the file's attributes (numbers, strings)."""
    import netCDF4

    handle = netCDF4.Dataset(path, "w", format="NETCDF4")
    try:
        for name, size in dims.items():
            handle.createDimension(name, size)
        for name, (dim, values, units, long_name) in coords.items():
            values = np.asarray(values)
            kind = str if values.dtype.kind in "US" else values.dtype
            variable = handle.createVariable(name, kind, (dim,))
            variable[:] = values.astype(object) if kind is str else values
            variable.setncatts({k: v for k, v in (("units", units), ("long_name", long_name)) if v})
        for name, (var_dims, units, long_name, kind) in variables.items():
            if kind == "bool":
                variable = handle.createVariable(name, "i1", tuple(var_dims))
                variable.setncatts({"units": units, "long_name": long_name, "dtype": "bool"})
            else:
                variable = handle.createVariable(name, kind, tuple(var_dims))
                variable.setncatts({"units": units, "long_name": long_name})
        handle.setncatts(dict(attrs))
    except Exception:
        handle.close()
        raise
    return handle


def run_chunks(
    client,
    task: Callable,
    spec: dict,
    chunks: Sequence,
    write: Callable,
    *,
    retries: int,
    progress: Callable[[int, int], None] | None = None,
    what: str = "items",
) -> None:
    """Run `task(spec, start, stop, payload)` for every `(start, stop, payload)` of `chunks`
    as Dask tasks (spec sent once to every worker) and call `write(start, stop, result)` in
    the driver as each finishes, then `progress(done items, total items)`.

    A task that raises is run `retries` more times (a dead worker's tasks are rerun by the
    scheduler whatever this is); a chunk that still fails stops the run with a
    `ClusterRunError` naming its `what` start..stop-1 and the reason, the other tasks cancelled."""
    from distributed import as_completed

    spec_future = client.scatter(spec, broadcast=True)
    spans = {}
    for start, stop, payload in chunks:
        future = client.submit(task, spec_future, start, stop, payload, retries=retries, pure=False,
                               key=f"teflon-jax-{spec['token']}-{start}")
        spans[future.key] = (future, start, stop)
    total = sum(stop - start for _, start, stop in spans.values())
    done = 0
    try:
        for future in as_completed([f for f, _, _ in spans.values()]):
            _, start, stop = spans[future.key]
            try:
                part = future.result()
            except Exception as error:
                raise ClusterRunError(
                    f"{what} {start}..{stop - 1} failed on the cluster after {retries} retries: "
                    f"{type(error).__name__}: {error}"
                ) from error
            write(start, stop, part)
            future.release()
            done += stop - start
            if progress is not None:
                progress(done, total)
    finally:
        client.cancel([f for f, _, _ in spans.values()])


def open_finished(path):
    """The loaded xarray Dataset of a streamed results file, refused (`ValueError` naming the file)
    while its `complete` attribute says a chunk is missing (`check_complete`)."""
    import xarray

    with xarray.open_dataset(path) as dataset:
        dataset = dataset.load()
    check_complete(dataset, path)
    return dataset


def file_attributes(title: str, inputs: Mapping) -> dict:
    """The attributes of a streamed results file: CF conventions, `title`, the run's `inputs`
    (numbers, strings and their lists; a nested list, which NetCDF's attributes cannot hold, as
    JSON; all of them also as JSON in `teflon_jax_attrs`) and `complete` = 0, set to 1 by
    `stream_to_netcdf` once every chunk is in."""
    flat = {key: json.dumps(value) if np.ndim(value) > 1 else value for key, value in inputs.items()}
    return {"Conventions": "CF-1.8", "title": title, "teflon_jax_attrs": json.dumps(dict(inputs), default=str),
            **flat, "complete": 0}


def stream_to_netcdf(
    out,
    layout: Mapping,
    task: Callable,
    spec: dict,
    chunks: Sequence,
    write: Callable,
    *,
    scheduler,
    connect_timeout: float,
    compilation_cache=None,
    retries: int,
    progress: Callable[[int, int], None] | None = None,
    what: str = "items",
    finish: Callable[[dict], Mapping] | None = None,
) -> None:
    """One distributed run from start to end: start the client of `scheduler` (`cluster_client`,
    in the precision `spec["dtype"]`), create the NetCDF file `out` (`create_netcdf(out,
    **layout)`, its attributes from `file_attributes`), run `chunks` (`run_chunks`) with
    `write(handle, start, stop, result)` putting each finished chunk at its place, and close
    the file with the attributes `n_workers`, `wall_s` [s] (from the start of this call),
    those of `finish(those two)` and `complete` = 1. A run that stops (`ClusterRunError`, an
    interrupt) leaves the file closed with `complete` = 0, which `open_finished` refuses."""
    tic = time.perf_counter()
    with cluster_client(scheduler, connect_timeout, spec["dtype"], compilation_cache) as client:
        handle = create_netcdf(out, **layout)
        try:
            run_chunks(client, task, spec, chunks, lambda start, stop, part: write(handle, start, stop, part),
                       retries=retries, progress=progress, what=what)
            done = {"n_workers": len(client.scheduler_info()["workers"]), "wall_s": time.perf_counter() - tic}
            handle.setncatts({**done, **(finish(done) if finish else {}), "complete": 1})
        finally:
            handle.close()


def add_attributes(path, attrs: Mapping) -> None:
    """Add (or replace) attributes of the NetCDF file `path`, e.g. statistics of the finished run."""
    import netCDF4

    with netCDF4.Dataset(path, "a") as handle:
        handle.setncatts(dict(attrs))
