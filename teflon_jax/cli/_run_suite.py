"""`teflon-jax run --suite FILE`: record pairs with scale factors, listed in a small CSV
(columns `record_x`, `record_y` (may be empty), `scale`, optional `name` and `record_z`, the
vertical component; paths relative to the CSV), through one structure in one vmapped call;
per-pair peaks (with a vertical component, each pair's uplift too), mean, least and largest in one
table and one NetCDF.
With `--scheduler local:N|ADDRESS` the pairs run as chunks of `--chunk-size` on a Dask cluster,
their peaks streamed to `--out FILE.nc` (`teflon_jax.studies.suite_peaks_distributed`)."""

import csv
import pathlib
import sys

import numpy as np

from ._common import _write_json, add_cluster_flags, output_units
from ._engineering import add_suite_pelicun_flag, suite_pelicun_peaks
from ._normal_load import NORMAL_LOAD_NOTE, suite_normal_load
from ._provenance import note_input_file, provenance_attributes
from ._record_checks import RECORD_FLAGS, RecordFiles, check_record_units
from ._run_stop import failed_pairs, pair_flags
from ._spectrum import add_spectrum_flags, check_unscaled, read_target, scale_to_target
from ._suite_bounding import add_suite_bounding_flag, read_suite_factors


def add_suite_arguments(parser) -> None:
    """The flags of a suite run on a Dask cluster (`teflon-jax run --suite`)."""
    add_cluster_flags(
        parser, "with --suite: run chunks of pairs as tasks", "",
        out="with --suite: the NetCDF file of the per-pair peaks (default <json stem>.nc; with "
        "--property-factors the file of all three cases, written only when given)",
        chunk_size="with --suite: record pairs per compiled call, a task with --scheduler (default: "
        "all in one call on a CPU, on a GPU the largest power of two up to 65536 that fits in half "
        "its free memory; 8 per task on a cluster); the same N gives the same peaks bit for bit here "
        "and on a cluster")
    add_spectrum_flags(parser)
    add_suite_bounding_flag(parser)
    add_suite_pelicun_flag(parser)


def check_suite_flags(args) -> None:
    """The cluster flags are only for suites: refuse them on a single-record run; and a single
    run's plot and histories on a suite, which writes its per-pair peaks instead."""
    if args.suite is not None:
        for flag, value in (("--plot", args.plot), ("--histories", args.histories)):
            if value is not None:
                raise ValueError(f"{flag}: belongs to a single record's run (--record-x); a suite writes each "
                                 "pair's peaks (--json, with its .csv and .nc beside it, or --out); leave "
                                 f"{flag} out, or run the pair alone.")
    if args.suite is None:
        read_target(args)  # a target or its flags without a suite: refused by name
        read_suite_factors(args)
        for flag, value in (("--scheduler", args.scheduler), ("--out", args.out), ("--chunk-size", args.chunk_size),
                            ("--pelicun-demands", args.pelicun_demands)):
            if value is not None:
                raise ValueError(f"{flag}: only used with --suite FILE (a single record runs here).")


SUITE_COLUMNS = ("record_x", "record_y", "scale", "name", "record_z")
"""The columns of a suite CSV (`record_x` required)."""

SUMMARY_ROWS = ("mean", "min", "max")
"""The rows the suite table adds after the pairs: a pair may not take their names."""


def read_suite(path_text):
    """[(name, x path, y path or None, z path or None, scale)] from the suite CSV; errors name
    file and line, also for a file that is not UTF-8 text, for a column the suite does not
    take and for a pair name that is another pair's or a summary row's (`SUMMARY_ROWS`)."""
    path = pathlib.Path(path_text)
    if not path.is_file():
        raise ValueError(f"--suite: {path} is not a file.")
    try:
        with path.open(newline="", encoding="utf-8") as handle:
            rows = list(csv.DictReader(handle))
    except UnicodeDecodeError as error:
        raise ValueError(f"--suite: {path}: not a text (UTF-8) CSV file (byte {error.start} cannot be read); "
                         "give the CSV of record pairs: record_x, record_y, scale, name.") from None
    if not rows or "record_x" not in rows[0]:
        raise ValueError(f"--suite: {path}, line 1: expected the columns record_x, record_y, scale.")
    unknown = [c for c in rows[0] if c is not None and c.strip() not in SUITE_COLUMNS]
    if unknown:
        raise ValueError(f"--suite: {path}, line 1: unknown column {unknown[0]!r}; the suite takes "
                         f"{', '.join(SUITE_COLUMNS)}.")
    pairs, lines = [], {}
    for line, row in enumerate(rows, start=2):
        x = (row.get("record_x") or "").strip()
        if not x:
            raise ValueError(f"--suite: {path}, line {line}: record_x is empty.")
        y = (row.get("record_y") or "").strip() or None
        z = (row.get("record_z") or "").strip() or None
        try:
            scale = float(row.get("scale") or 1.0)
        except ValueError:
            raise ValueError(f"--suite: {path}, line {line}: scale {row.get('scale')!r} is not a number.") from None
        if not (np.isfinite(scale) and scale > 0):
            raise ValueError(f"--suite: {path}, line {line}: scale must be a finite number > 0, got "
                             f"{row.get('scale').strip()}.")
        resolve = lambda p: str(p if pathlib.Path(p).is_absolute() else path.parent / p)  # noqa: E731
        name = (row.get("name") or "").strip() or pathlib.Path(x).stem
        for column, record in (("record_x", x), ("record_y", y), ("record_z", z)):
            if record is not None and not pathlib.Path(resolve(record)).is_file():
                raise ValueError(f"--suite: {path}, line {line}, pair {name}: {column} {record} is not a file (looked "
                                 f"for {resolve(record)}: a relative path is read from the suite file's folder).")
        _check_name(path, line, name, lines)
        lines[name] = line
        pairs.append((name, resolve(x), None if y is None else resolve(y), None if z is None else resolve(z), scale))
    for name, *records, _ in pairs:  # inputs of the run, hashed in its results
        for column, record in zip(("record_x", "record_y", "record_z"), records):
            if record is not None:
                note_input_file(f"--suite {path}: {name}.{column}", record)
    return pairs


def _check_name(path, line: int, name: str, lines: dict) -> None:
    """`ValueError` naming the suite file and line for a pair `name` that a summary row or an
    earlier pair (`lines`: name -> line) has."""
    if name.lower() in SUMMARY_ROWS:
        raise ValueError(f"--suite: {path}, line {line}: the pair name {name!r} is that of a summary row of "
                         f"the results ({', '.join(SUMMARY_ROWS)}); rename the pair.")
    if name in lines:
        raise ValueError(f"--suite: {path}, line {line}: the pair name {name!r} is also that of line "
                         f"{lines[name]}; give each pair its own name (a 'name' column, or records with "
                         "different file names).")


def check_pairs(args, pairs) -> list:
    """`pairs` (`read_suite`) once they are checked: `ValueError` naming --record-units when
    every record of the suite is an AT2 file (`check_record_units`), or --json when a table
    the suite writes beside its JSON (<stem>.csv and .nc, <stem>-<case>.csv and .nc; stem
    `suite` without --json) is the suite file or a record."""
    import os

    from ..studies import BOUNDING_CASES

    check_record_units(args.record_units, [("--suite", path) for _, *records, _ in pairs for path in records
                                           if path is not None])
    stem = pathlib.Path(args.json).with_suffix("") if args.json else pathlib.Path("suite")
    tables = [pathlib.Path(f"{stem}{case}{suffix}") for case in ("", *(f"-{c}" for c in BOUNDING_CASES))
              for suffix in (".csv", ".nc")]
    inputs = [("the --suite file", args.suite), *((f"pair {name}'s record", path) for name, *records, _ in pairs
                                                  for path in records if path is not None)]
    for table in tables:
        for name, source in inputs:
            if table.exists() and os.path.samefile(table, source):
                given = f"--json {args.json}" if args.json else "--json (not given: the tables are suite.*)"
                raise ValueError(f"{given}: the suite's results would go to {table}, {name}, and replace it; "
                                 "give --json a name of its own, e.g. results.json.")
    return pairs


def _pair_records(args, pairs):
    """(records [(name, ax, ay, dt)], ax, ay (P, n) [m/s^2] on one grid, its step dt [s], notes,
    az (P, n) [m/s^2] or None) of the suite's `pairs`, each read as `run` reads one pair
    (`load_components`, `vertical_component`) and the shorter ones continued with zero ground
    acceleration; `ValueError` naming --suite for pairs of different time steps, and naming the
    pair for a vertical record that does not fit its pair. Where some pairs have a vertical
    component, those without one run without it (N = W), as the notes say. A record in several
    pairs is read once (`read_once`)."""
    from ._run_records import load_components, read_once, vertical_component

    records, notes, verticals = [], [], []
    read = read_once()
    for name, x, y, z, scale in pairs:
        files = RecordFiles(x, y, z, scale * args.scale)
        try:
            ax, ay, dt, pair_notes = load_components(args, files, read)
        except ValueError as error:  # worded for run's flags: named here by the suite's columns
            text = str(error)
            for dest, flag in RECORD_FLAGS:
                text = text.replace(flag, dest)
            raise ValueError(f"--suite: {args.suite}, pair {name!r}: {text}") from None
        verticals.append(vertical_component(args, dt, ax.size, f"--suite {args.suite}, pair {name}: record_z",
                                            files, read))
        records.append((name, ax, ay, dt))
        notes += [f"{name}: {n}" for n in pair_notes]
    steps = {dt for *_, dt in records}
    if len(steps) > 1:
        listing = ", ".join(f"{name} {dt:g} s" for name, _, _, dt in records)
        raise ValueError(f"--suite: the pairs have different time steps ({listing}); resample them first.")
    dt = steps.pop()
    n = max(ax.size for _, ax, _, _ in records)
    if any(ax.size != n for _, ax, _, _ in records):
        notes.append(f"pairs shorter than {(n - 1) * dt:g} s continue with zero ground acceleration")
    ax = np.stack([np.pad(a, (0, n - a.size)) for _, a, _, _ in records])
    ay = np.stack([np.pad(a, (0, n - a.size)) for _, _, a, _ in records])
    if all(v is None for v in verticals):
        return records, ax, ay, dt, notes, None
    missing = [name for (name, *_), v in zip(records, verticals) if v is None]
    if missing:
        notes.append(f"pairs without a vertical component (record_z empty) run with N = W: {', '.join(missing)}")
    az = np.stack([np.zeros(n) if v is None else np.pad(v, (0, n - v.size)) for v in verticals])
    return records, ax, ay, dt, notes, az


def _vertical(args, isolator, plan, az, names, notes):
    """(az (P, n) [m/s^2], the pressure law of `run --record-z`, the pair `names`) of a suite
    whose pairs have vertical components, with the note of the contact pressures Table 1 is
    read at added to `notes`; None without them."""
    if az is None:
        return None
    from ._normal_load import pressure_law, pressure_note

    law = pressure_law(args, isolator, plan)
    note = pressure_note(law, az.ravel())
    if note is not None:
        notes.append(note)
    return az, law, names


def summary_lines(summary: dict, units) -> list[str]:
    """The suite's summary ({name: {"mean": ..., "min": ..., "max": ...}}, SI) as lines on the console, a
    length (a name ending in _m) in the `--units` family `units`, a time (_s) in seconds."""
    lines = []
    for name, stats in summary.items():
        if name.endswith("_m"):
            shown = {row: units.show(value, "length") for row, value in stats.items()}
        else:
            shown = {row: f"{value:.4g}{' s' if name.endswith('_s') else ''}" for row, value in stats.items()}
        label = name[:-2] if name.endswith(("_m", "_s")) else name
        lines.append(f"{label.replace('_', ' ')}: " + ", ".join(f"{row} {text}" for row, text in shown.items()))
    return lines


def run_suite(args, isolator) -> int:
    """Run the suite on `isolator` (`read_isolator`) through the structure of `run`'s flags."""
    from ..studies import (
        check_netcdf_output,
        save_suite,
        suite_peaks,
        suite_peaks_distributed,
    )

    if args.scheduler is not None and args.out is None:
        raise ValueError("--scheduler: a distributed suite streams its results to a file; add --out FILE.nc.")
    if args.out is not None:
        check_netcdf_output(args.out, "--out")  # before any record is read or run
    if args.pelicun_demands is not None:
        from ..formats import check_pelicun_path

        check_pelicun_path(args.pelicun_demands)
        if args.scheduler is not None:
            raise ValueError("--pelicun-demands: the storey results are kept in this process; leave out --scheduler.")
    spectrum = read_target(args)  # target, range and limits checked before any record is read
    bounding = read_suite_factors(args, isolator)
    pairs = check_pairs(args, read_suite(args.suite))
    from ._run_structure import read_structure, suite_build

    flags = read_structure(args, isolator)  # the structure flags and the plan, before any record
    if spectrum is not None:
        check_unscaled(pairs, args)
    records, ax, ay, dt, notes, az = _pair_records(args, pairs)
    n = ax.shape[1]
    scaling = None
    if spectrum is not None:  # factors checked against --max-factor before any run
        factors, scaling = scale_to_target(args, spectrum, [r[0] for r in records], ax, ay, dt)
        ax, ay = factors[:, None] * ax, factors[:, None] * ay
        if az is not None:
            az = factors[:, None] * az
            notes.append("each pair's vertical component is scaled by its pair's factor (the recorded ratio of "
                         "vertical to horizontal kept)")
    vertical = _vertical(args, isolator, flags.plan, az, [r[0] for r in records], notes)
    if bounding is not None:
        from ._suite_bounding import run_suite_bounding

        return run_suite_bounding(args, bounding, isolator, [r[0] for r in records], ax, ay, dt, notes, scaling,
                                  vertical)
    build, dofs, plan = suite_build(args, isolator, ax[0], ay[0], dt, vertical=vertical)
    group_names = None if plan is None else [g["name"] for g in plan["groups"]]  # loads', surfaces' labels
    names = [r[0] for r in records]
    stem = pathlib.Path(args.json).with_suffix("") if args.json else pathlib.Path("suite")
    netcdf = stem.with_suffix(".nc") if args.out is None else args.out
    attrs = {"structure": args.structure, "suite": str(args.suite), **provenance_attributes()}
    if args.scheduler is None:
        from ..tables import load_table2

        storeys = args.structure == "building" and args.pelicun_demands is not None  # as on a cluster otherwise
        from ..studies import device_chunk_size

        # default: all pairs in one call on a CPU; on a GPU as many as fit in half its memory
        batch = args.chunk_size or device_chunk_size((2 if az is None else 3) * n, dofs, cpu=len(names))
        result = suite_peaks(build, names, ax, ay, dt, (n - 1) * dt, batch_size=batch,
                             storey_height=load_table2().storey_height if storeys else None,
                             group_names=group_names, az=az)
        save_suite(result, table_path=stem.with_suffix(".csv"), netcdf_path=netcdf, attrs=attrs)
    else:
        from ._main import compile_cache_dir

        result = suite_peaks_distributed(
            build, names, ax, ay, dt, (n - 1) * dt, out=args.out, scheduler=args.scheduler,
            chunk_size=8 if args.chunk_size is None else args.chunk_size, attrs=attrs,
            compilation_cache=None if getattr(args, "no_compile_cache", False) else str(compile_cache_dir()),
            group_names=group_names, az=az)
        save_suite(result, table_path=stem.with_suffix(".csv"))
    payload = {"structure": args.structure, "suite": str(args.suite), "notes": notes, "netcdf": str(netcdf),
               "records": {name: {"record_x": x, "record_y": y, "record_z": z, "scale": scale * args.scale}
                           for name, x, y, z, scale in pairs},
               "pairs": {name: {k: float(v[i]) for k, v in (result.peaks | result.surface_peaks).items()}
                         | {"converged": bool(result.converged[i])}
                         | pair_flags(result, i)
                         | ({} if result.groups is None else suite_normal_load(plan, result.groups, i))
                         for i, name in enumerate(result.names)},
               "summary": result.summary, "failed": int(np.sum(~result.converged))}
    if result.groups is not None:
        payload["normal_load_note"] = NORMAL_LOAD_NOTE
    if scaling is not None:
        payload["spectrum_scaling"] = scaling
    if args.pelicun_demands is not None:
        from ..formats import write_pelicun_demands

        payload["pelicun_demands"] = str(write_pelicun_demands(args.pelicun_demands, **suite_pelicun_peaks(result, ax, ay)))
    print("\n".join(summary_lines(payload["summary"], output_units(args.units))))
    if args.json:
        _write_json(args.json, payload)
    failed = failed_pairs(result)
    if failed:
        print(f"teflon-jax run: error: {failed}; they are marked converged: false and left out of the summary.",
              file=sys.stderr)
    return 1 if failed else 0
