"""What every result a command writes says of its inputs: the one provenance block.

`main` records the command line (`set_command_line`) and the parsed arguments of the command
it runs with its output flags (`set_arguments`), which hashes every input file before any work;
every writer of results then takes the same block:

- `provenance()`: what every JSON a command writes starts with: `teflon_jax_version`,
  `command_line` and, while a command runs, `inputs`;
- `run_inputs()`: the JSON block `inputs`, with
  - `files`: each input file as {"flag", "path", "sha256"} (records, suite, plan, bearing
    file, isolator file, test records, and the files those name, e.g. a plan group's
    isolator file or a suite's records: `note_input_file`), SHA-256 of its bytes as read;
  - `settings`: every other flag of the command as run, keyed by the flag, as typed (with its
    unit) or its default (the defaults that the command resolves, e.g. the isolation period of
    `montecarlo`, as resolved);
  - `replaced`: the flags that a bearing file (`--bearing`) or an isolator file
    (`--isolator-file`) replaced, each with that file: they are not in `settings`, since they
    were not run;
  - `output_units`: the unit family of printed and plotted output (`--units`); the JSON's
    keys and the NetCDF variables' `units` attributes name their own units;
- `provenance_attributes()`: the global attributes of a NetCDF file: `teflon_jax_version`,
  `command_line` and `teflon_jax_inputs` (the `inputs` block as JSON);
- `stamp_netcdf(path)`: those attributes added to a NetCDF file already written, and
  `stamp_outputs(since)`: to every NetCDF output of the command written since `since`;
- `record_metadata()`: the same as `# key: value` lines of a test-record CSV;
- `isolator_as_run(args)`: the isolator and bearing a Monte Carlo command ran.
"""

import hashlib
import json
import pathlib
import shlex

_COMMAND_LINE: list[str] = []
"""The words of the running command line, after `teflon-jax` (`set_command_line`)."""

_RUN: dict = {}
"""The command being run: "args" (its parsed arguments), "outputs" (the attributes of `args`
that are output paths, with their kind: "file", "image" or "folder"), "files" (the input
files with their hashes) and "takes_pressure" (for each bearing file the command read, whether
its bearing takes the contact pressure: `note_bearing_file`); empty outside a command."""

_NOT_SETTINGS = {"command", "command_function", "bearing_option_defaults", "json_path"}
"""Attributes of the parsed arguments that are no flag of the command."""


def set_command_line(argv) -> None:
    """Record the command line being run, for `provenance`; `main` calls it first."""
    _COMMAND_LINE[:] = [str(word) for word in argv]


def command_line() -> str:
    """The command line being run, as typed (quoted for a shell)."""
    return shlex.join(["teflon-jax", *_COMMAND_LINE])


def project_version() -> str:
    """The installed version of teflon-jax ("unknown" when it is not installed)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("teflon-jax")
    except PackageNotFoundError:
        return "unknown"


def provenance() -> dict:
    """What every JSON a command writes starts with: the project version, the command line
    as typed (quoted for a shell) and, while a command runs, its `inputs` (`run_inputs`)."""
    inputs = run_inputs()
    return {"teflon_jax_version": project_version(), "command_line": command_line(),
            **({"inputs": inputs} if inputs is not None else {})}


def file_hash(path) -> str:
    """SHA-256 of the bytes of the file `path`, as 64 hexadecimal digits."""
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


_POSITIONAL = ("records", "record")
"""The positional arguments of the commands (fit's test records, diagnose's record)."""


def _flag(dest: str) -> str:
    """How the input `dest` of the parsed arguments is named: its flag, or a positional's name."""
    return dest if dest in _POSITIONAL else "--" + dest.replace("_", "-")


def set_arguments(args, outputs) -> None:
    """Record `args` as those of the command being run, `outputs` its output flags as
    (attribute, flag, "file" | "image" | "folder", example) (`_paths.OUTPUT_FLAGS`), with the
    SHA-256 of each input file (hashed now, before any work, as the command reads them)."""
    _RUN.clear()
    _RUN.update(args=args, outputs={dest: kind for dest, _, kind, _ in outputs}, files=[], takes_pressure={})
    for dest, value in vars(args).items():
        if dest in _RUN["outputs"] or dest in _NOT_SETTINGS or dest.startswith("_"):
            continue
        for item in value if isinstance(value, (list, tuple)) else (value,):
            if isinstance(item, (str, pathlib.PurePath)) and str(item).strip() and pathlib.Path(item).is_file():
                note_input_file(_flag(dest), item)


def clear_arguments() -> None:
    """No command is being run any more (`main` calls it when the command ends)."""
    _RUN.clear()


def note_input_file(flag: str, path) -> None:
    """Add the file `path` (an input of the running command, named by `flag`: the flag, or the
    file and key that name it) to `inputs.files`, with its hash; nothing outside a command or
    for a file already there."""
    if "files" not in _RUN or not pathlib.Path(path).is_file():
        return
    text = str(path)
    if any(entry["flag"] == flag and entry["path"] == text for entry in _RUN["files"]):
        return
    _RUN["files"].append({"flag": flag, "path": text, "sha256": file_hash(path)})


def _plain(value):
    """`value` as JSON takes it (paths and other objects as text)."""
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    if isinstance(value, (list, tuple)):
        return [_plain(item) for item in value]
    return str(value)


def replaced_flags(args) -> dict:
    """{flag: the file that replaced it} of the bearing flags at their defaults (and the
    isolation period and damping) when a bearing file or a series isolator's file is run."""
    from ..catalogue import IN_SERIES

    defaults = getattr(args, "bearing_option_defaults", {})
    bearing = getattr(args, "bearing", None)
    isolator_file = getattr(args, "isolator_file", None)
    names, source = [], None
    if bearing is not None:
        source = f"--bearing {bearing}"
        names = [name for name in defaults if name != "pressure" or not _uses_pressure(bearing)]
    elif getattr(args, "isolator", None) in IN_SERIES and isolator_file is not None:
        source = f"--isolator-file {isolator_file}"
        names = [*defaults, "isolation_period", "isolation_damping"]
    return {_flag(name): source for name in names if hasattr(args, name)}


def note_bearing_file(path, takes_pressure: bool) -> None:
    """Record that the running command read the bearing file `path` (`read_bearing_flag`, its one
    read) and whether its bearing takes the contact pressure (heating or pressure dependence):
    then --pressure is run beside the file, not replaced by it. Nothing outside a command."""
    if "takes_pressure" in _RUN:
        _RUN["takes_pressure"][str(path)] = bool(takes_pressure)


def _uses_pressure(path) -> bool:
    """Whether the bearing of the bearing file `path`, as the running command read it
    (`note_bearing_file`), takes the contact pressure; False for a file it did not read."""
    return _RUN.get("takes_pressure", {}).get(str(path), False)


def run_inputs() -> dict | None:
    """The `inputs` block of the command being run (module docstring); `None` outside one."""
    if "args" not in _RUN:
        return None
    args, outputs = _RUN["args"], _RUN["outputs"]
    replaced = replaced_flags(args)
    settings = {}
    for dest, value in vars(args).items():
        if (dest in outputs or dest in _NOT_SETTINGS or dest.startswith("_") or dest.endswith(("_text", "_levels"))
                or _flag(dest) in replaced or dest in _POSITIONAL):
            continue
        settings[_flag(dest)] = _plain(getattr(args, dest + "_text", value))
    return {"files": [dict(entry) for entry in _RUN["files"]], "settings": settings, "replaced": replaced,
            "output_units": getattr(args, "units", None)}


def provenance_attributes() -> dict:
    """The global attributes of a NetCDF file a command writes: `teflon_jax_version`,
    `command_line` and `teflon_jax_inputs` (`run_inputs()` as JSON, "{}" outside a command)."""
    return {"teflon_jax_version": project_version(), "command_line": command_line(),
            "teflon_jax_inputs": json.dumps(run_inputs() or {})}


def stamp_netcdf(path) -> None:
    """Add `provenance_attributes()` to the global attributes of the NetCDF file `path`
    (NetCDF-4, as every command writes)."""
    import netCDF4

    with netCDF4.Dataset(path, "a") as handle:
        handle.setncatts(provenance_attributes())


def stamp_outputs(since: float) -> list:
    """`stamp_netcdf` on every NetCDF file among the outputs of the command being run (its
    files, and the .nc files in its output folders) that was written since the time `since`
    [s since the epoch] and lacks the attributes; returns their paths."""
    import os

    found = []
    for dest, kind in _RUN.get("outputs", {}).items():
        value = getattr(_RUN["args"], dest, None)
        if value is None or not str(value).strip():
            continue
        path = pathlib.Path(value)
        found += sorted(path.glob("*.nc")) if kind == "folder" and path.is_dir() else [path]
    stamped = []
    for path in found:
        if path.suffix != ".nc" or not path.is_file() or os.path.getmtime(path) < since:
            continue
        if "teflon_jax_inputs" not in _global_attributes(path):
            stamp_netcdf(path)
            stamped.append(path)
    return stamped


def _global_attributes(path) -> dict:
    import netCDF4

    with netCDF4.Dataset(path, "r") as handle:
        return {name: handle.getncattr(name) for name in handle.ncattrs()}


def isolator_as_run(args, pressure=("Pa", 1.0)) -> dict:
    """The isolator and bearing a Monte Carlo command ran, from its parsed `args` (SI, the
    pressure in `pressure` = (name, SI factor)): isolator, PTFE, pressure, isolation period
    [s] and damping, radius [m] (None but on a single pendulum), and a bearing or isolator file by its path and SHA-256,
    without the flags such a file replaced (`replaced_flags`)."""
    replaced = replaced_flags(args)
    period = args.isolation_period
    entries = (("--ptfe", "ptfe", args.ptfe),
               ("--pressure", f"pressure_{pressure[0]}", None if args.pressure is None else args.pressure / pressure[1]),
               ("--isolation-period", "isolation_period_s", "none" if period is None else period),
               ("--isolation-damping", "isolation_damping", args.isolation_damping))
    out = {"isolator": args.isolator}
    out.update({name: value for flag, name, value in entries if flag not in replaced})
    out["radius_m"] = args.radius  # of --isolator single-fp; None on the others
    for name, path in (("bearing_file", args.bearing), ("isolator_file", args.isolator_file)):
        if path is not None:
            out.update({name: str(path), f"{name}_sha256": file_hash(path)})
    return out


def record_metadata() -> dict:
    """The provenance as metadata of a test-record CSV a command writes (`# key: value` lines,
    keys that every reader keeps): `teflon_jax_version`, `command_line` and, when the command
    read files, `input_files` ('FLAG PATH sha256 HASH' for each, separated by '; ')."""
    files = _RUN.get("files", [])
    listed = "; ".join(f"{entry['flag']} {entry['path']} sha256 {entry['sha256']}" for entry in files)
    return {"teflon_jax_version": project_version(), "command_line": command_line(),
            **({"input_files": listed} if listed else {})}
