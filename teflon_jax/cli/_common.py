"""What the sub-commands share: quantity flags read through the one unit parser, the
output-unit family (`--units si|us`), the progress bar and the JSON writer.

A quantity flag is declared with `add_quantity(parser, "--pga", "acceleration", "0.3g", ...)`:
its default is shown with its unit in `--help`, and after `argparse` the text is read by
`teflon_jax.units.parse_quantity` (pint) into SI and range-checked, every error naming the flag
as typed and echoing the value as the user wrote it. `QUANTITY_FLAGS` lists them all.
"""

import argparse
import dataclasses
import json
import math
import pathlib
import re
import sys

from ..units import INCH, KIP, PSI, parse_quantity
from ._provenance import command_line as command_line
from ._provenance import project_version as project_version
from ._provenance import provenance as provenance
from ._provenance import set_command_line as set_command_line


@dataclasses.dataclass(frozen=True)
class QuantityFlag:
    """A command-line flag that is a quantity: `dimension` (a key of `teflon_jax.units.UNITS`),
    `default` (text with its unit, or `None`), `minimum` with `strict` (> or >=), `maximum`,
    `nargs` (None or 2 for a LOW HIGH pair), `none` (a word that means 'not set', or None),
    `levels` (a comma-separated, strictly increasing list: the first value goes to `args.<dest>`,
    all of them to `args.<dest>_levels`), `why` (the physical reason for the range, shown
    with a value outside it)."""

    command: str
    flag: str
    dest: str
    dimension: str
    default: str | None
    minimum: float | None = None
    strict: bool = True
    maximum: float | None = None
    nargs: int | None = None
    none: str | None = None
    levels: bool = False
    why: str = ""


QUANTITY_FLAGS: list[QuantityFlag] = []
"""Every quantity flag of every sub-command, in the order they were declared."""

_UNITS_OF = {
    "length": "in, mm, cm, m, ft",
    "force": "kip, lbf, N, kN",
    "pressure": "psi, ksi, Pa, kPa, MPa",
    "time": "s, ms, min",
    "frequency": "Hz, rad/s, rpm",
    "acceleration": "g, m/s^2, cm/s^2, in/s^2",
    "slowness": "s/in, s/m",
    "dimensionless": "a plain number or %",
    "angle": "deg, rad",
}


# argparse takes '-0.3g' for an option; a number with a unit is a value (then range-checked)
_NEGATIVE_QUANTITY = re.compile(r"^-(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?(?:\s*[A-Za-z%/^*()\d. ]*)?$")


def add_quantity(parser, flag: str, dimension: str, default: str | None, help: str, *,
                 minimum: float | None = None, strict: bool = True, maximum: float | None = None,
                 nargs: int | None = None, none: str | None = None, required: bool = False,
                 levels: bool = False, why: str = ""):
    """Declare a quantity flag on `parser` (see the module docstring)."""
    spec = QuantityFlag(command=parser.prog.split()[-1], flag=flag, dest=flag.lstrip("-").replace("-", "_"),
                        dimension=dimension, default=default, minimum=minimum, strict=strict,
                        maximum=maximum, nargs=nargs, none=none, levels=levels, why=why)
    QUANTITY_FLAGS[:] = [q for q in QUANTITY_FLAGS if (q.command, q.flag) != (spec.command, flag)]
    QUANTITY_FLAGS.append(spec)
    parser._negative_number_matcher = _NEGATIVE_QUANTITY
    shown = " ".join(default) if isinstance(default, (tuple, list)) else default
    text = f"{help} [{_UNITS_OF.get(dimension, dimension)}]"
    if shown is not None:
        text += f" (default {shown})"
    metavar = ("LOW", "HIGH") if nargs == 2 else ("RATIO" if dimension == "dimensionless" else dimension.upper())
    parser.add_argument(flag, default=default, help=text.replace("%", "%%"), nargs=nargs,
                        metavar=metavar, required=required)


def read_quantities(args, command: str) -> None:
    """Replace each quantity flag's text on `args` by its SI value; keep the text as
    `args.<dest>_text`. Raises `ValueError` naming the flag and echoing the text. Reading
    twice is harmless (the second call, which finds the texts kept, does nothing)."""
    specs = [spec for spec in QUANTITY_FLAGS if spec.command == command and hasattr(args, spec.dest)]
    if any(hasattr(args, spec.dest + "_text") for spec in specs):  # read already: the texts are kept
        return
    for spec in specs:
        raw = getattr(args, spec.dest)
        setattr(args, spec.dest + "_text", raw)
        if raw is None:
            continue
        if spec.nargs == 2:
            values = tuple(_one(spec, text) for text in raw)
            if not values[0] < values[1]:
                raise ValueError(f"{spec.flag}: LOW must be below HIGH, got {raw[0]} {raw[1]}.")
            setattr(args, spec.dest, values)
        elif spec.levels:
            values = _levels(spec, raw)
            setattr(args, spec.dest + "_levels", values)
            setattr(args, spec.dest, values[0])
        else:
            setattr(args, spec.dest, _one(spec, raw))


def _one(spec: QuantityFlag, text: str):
    if spec.none is not None and str(text).strip().lower() == spec.none:
        return None
    value = parse_quantity(text, spec.dimension, where=spec.flag)
    if not math.isfinite(value):
        raise ValueError(f"{spec.flag}: must be finite, got {text}.")
    if spec.minimum is not None and not (value > spec.minimum if spec.strict else value >= spec.minimum):
        bound = _in_units_of(spec.minimum, text, spec)
        hint = f" (or '{spec.none}')" if spec.none else ""
        raise ValueError(f"{spec.flag}: must be {'>' if spec.strict else '>='} {bound}{hint}, got {text}.")
    if spec.maximum is not None and not value <= spec.maximum:
        why = f" ({spec.why})" if spec.why else ""
        raise ValueError(f"{spec.flag}: must be <= {_in_units_of(spec.maximum, text, spec)}{why}, got {text}"
                         f"{_percent_hint(spec, text, value)}.")
    return value


def _percent_hint(spec: QuantityFlag, text: str, value: float) -> str:
    """For a plain number above the maximum of a ratio flag that reads as a percentage (67
    for 67 %): how to write it, else ''."""
    if spec.dimension != "dimensionless" or "%" in str(text) or not value / 100 <= spec.maximum:
        return ""
    return (f"; a plain number is a ratio, so {text} is {value:g} times, not {value:g} %: "
            f"write {value / 100:g} or {value:g}%")


def _levels(spec: QuantityFlag, text: str) -> tuple:
    """The comma-separated values of a `levels` flag, each with its unit, strictly increasing."""
    items = [item.strip() for item in str(text).split(",")]
    if any(not item for item in items):
        raise ValueError(f"{spec.flag}: an empty item in {text!r}; write e.g. 0.1g,0.2g,0.3g.")
    values = tuple(_one(spec, item) for item in items)
    for j in range(1, len(values)):
        if not values[j] > values[j - 1]:
            raise ValueError(f"{spec.flag}: levels must increase; {items[j]} (level {j + 1}) is not above "
                             f"{items[j - 1]} (level {j}). Sort them.")
    return values


def _in_units_of(value: float, text: str, spec: QuantityFlag) -> str:
    """`value` [SI] written in the unit the user typed in `text` (e.g. '0g', '1 in')."""
    unit = re.sub(r"^\s*[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?\s*", "", str(text))
    if value == 0 or not unit:
        return f"{value:g}{unit}"
    return f"{value / parse_quantity('1' + unit, spec.dimension, where=spec.flag):.6g}{unit}"


def add_units_flag(parser, *, default: str = "us") -> None:
    """`--units si|us`: the unit family of printed and plotted output (JSON keys name theirs)."""
    parser.add_argument("--units", default=default, type=str.lower, choices=("si", "us"),
                        help="units of printed and plotted output: si (mm, kN, MPa) or us (in, kip, "
                        f"psi, as in the paper) (default {default})")


@dataclasses.dataclass(frozen=True)
class OutputUnits:
    """The family chosen by `--units`: name and SI factor of a length, force and pressure."""

    length: tuple[str, float]
    force: tuple[str, float]
    pressure: tuple[str, float]

    def show(self, value: float, dimension: str, digits: int = 4) -> str:
        name, factor = getattr(self, dimension)
        return f"{value / factor:.{digits}g} {name}"


def output_units(family: str) -> OutputUnits:
    if family == "si":
        return OutputUnits(length=("mm", 1e-3), force=("kN", 1e3), pressure=("MPa", 1e6))
    return OutputUnits(length=("in", INCH), force=("kip", KIP), pressure=("psi", PSI))


def name_value_items(text, flag: str = "--fixed") -> list[str]:
    """The non-empty items of a NAME=VALUE[,...] flag: its text, or the list the repeated flag
    gives, split at the commas; `ValueError` naming `flag` and a NAME given twice."""
    parts = [] if not text else [text] if isinstance(text, str) else text
    items = [item for part in parts for item in part.split(",") if item.strip()]
    seen = {}
    for item in items:
        name = item.partition("=")[0].strip()
        if name in seen:
            raise ValueError(f"{flag}: {name} given twice ({seen[name].strip()}, then {item.strip()}); "
                             "give each parameter once.")
        seen[name] = item
    return items


def parse_name_values(text, dimensions: dict, flag: str) -> dict:
    """`flag` NAME=VALUE[,...] (`name_value_items`) -> {name: SI value}, each value a quantity
    of `dimensions[name]` (`parse_quantity`: e.g. rate_a=0.6s/in); `ValueError` naming `flag`
    and the item that is not NAME=VALUE, or the unknown name with the known ones (the keys of
    `dimensions`, in their order). The one reader of `--fixed` and `--known`."""
    values = {}
    for item in name_value_items(text, flag):
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep:
            raise ValueError(f"{flag}: expected NAME=VALUE (e.g. rate_a=0.6s/in), got '{item}'.")
        if name not in dimensions:
            raise ValueError(f"{flag}: unknown parameter '{name}'; the parameters are {', '.join(dimensions)}.")
        values[name] = parse_quantity(value, dimensions[name], where=f"{flag} {name}")
    return values


def flags_given(args, defaults: dict) -> list[str]:
    """The flags (`--name`) among `defaults` ({attribute: its parser default}) whose value as
    typed (a quantity's `<attribute>_text`) is not that default, in the order of `defaults`."""
    return ["--" + name.replace("_", "-") for name, default in defaults.items()
            if getattr(args, name + "_text", getattr(args, name, default)) != default]


def integer_at_least(text: str, minimum: int, words: str) -> int:
    """The integer of a flag's `text`, at least `minimum`; `argparse.ArgumentTypeError`
    "expected `words`, got ..." otherwise."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected {words}, got {text!r}") from None
    if value < minimum:
        raise argparse.ArgumentTypeError(f"expected {words}, got {value}")
    return value


def _positive_int(text: str) -> int:
    return integer_at_least(text, 1, "a positive integer")


MAX_SEED = 2**32 - 1
"""Largest seed a command takes (a 32-bit unsigned integer, as JAX's and NumPy's generators
take on every platform)."""


def seed_value(text: str) -> int:
    """A `--seed`-like flag: an integer from 0 to `MAX_SEED`; `argparse.ArgumentTypeError`
    otherwise."""
    value = integer_at_least(text, 0, f"an integer from 0 to {MAX_SEED}")
    if value > MAX_SEED:
        raise argparse.ArgumentTypeError(f"expected an integer from 0 to {MAX_SEED}, got {value}")
    return value


def _write_json(path, payload: dict, **dumps) -> None:
    """Write `payload` to the JSON file `path` (None: nothing), after `provenance()`; its
    folder is created if missing. `dumps`: options of `json.dumps` (e.g. allow_nan=False)."""
    if path is not None:
        path = pathlib.Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps({**provenance(), **payload}, indent=2, **dumps) + "\n")


def add_scheduler_flag(parser, tasks: str, after: str = "") -> None:
    """`--scheduler local:N|ADDRESS`: `tasks` ("run the chunks as tasks") on a Dask cluster,
    its help ending with `after`."""
    parser.add_argument("--scheduler", default=None, metavar="local:N|ADDRESS",
                        help=f"{tasks} on a Dask cluster: 'local:N' starts N worker processes here, an "
                        "address (tcp://host:8786) uses a running scheduler (SLURM/PBS: see "
                        f"docs/distributed.md); needs --out FILE.nc{after}")


def add_cluster_flags(parser, tasks: str, after: str, out: str, chunk_size: str) -> None:
    """`--scheduler` (`add_scheduler_flag` of `tasks`, `after`), `--out FILE.nc` and
    `--chunk-size N`, with the helps `out` and `chunk_size`."""
    add_scheduler_flag(parser, tasks, after)
    parser.add_argument("--out", type=pathlib.Path, default=None, metavar="FILE.nc", help=out)
    parser.add_argument("--chunk-size", type=_positive_int, default=None, metavar="N", help=chunk_size)


def check_scheduler(args) -> None:
    """`ValueError` naming --scheduler and the extra to install when it is given and Dask's
    distributed package cannot be imported (before any work)."""
    if getattr(args, "scheduler", None) is None:
        return
    try:
        import distributed  # noqa: F401
    except ImportError as error:
        raise ValueError(f"--scheduler: needs Dask's distributed package ({error}); install the "
                         "extra: pip install \"teflon-jax[distributed]\" (from a clone: pip install -e "
                         "\".[distributed]\"), or leave --scheduler out to run here.") from None


def read_bearing_record(path):
    """A `TestRecord` from a test-record CSV or a friction-damper JSON file: the one reader that
    `fit` and `diagnose` share (errors name the file)."""
    path = pathlib.Path(path)
    if not path.is_file():
        raise ValueError(f"{path}: no such file.")
    if path.suffix.lower() == ".json":
        from ..formats import read_friction_damper_json

        return read_friction_damper_json(path)
    from ..formats import read_test_record

    return read_test_record(path)


def check_time_step(time_step: float, time_text: str, record_step: float, record_text: str) -> None:
    """`ValueError` naming --time-step and the record when the solver step `time_step` [s] is
    longer than the record step `record_step` [s]: the solver would step over samples of the
    ground acceleration and report the peaks of a motion it never saw."""
    if time_step <= record_step * (1 + 1e-9):
        return
    raise ValueError(f"--time-step {time_text}: longer than the record step {record_text}; the solver "
                     "would step over samples of the ground acceleration and miss its peaks. Give a "
                     f"--time-step of at most {record_step * 1e3:.4g}ms, e.g. {record_step * 500:.4g}ms.")


def warn_time_step(command: str, time_step: float, time_text: str, record_step: float, record_text: str) -> None:
    """`check_time_step`, then a warning (stderr) when the solver step `time_step` [s] does not
    divide the record step `record_step` [s]: the ground acceleration is then interpolated
    inside steps, and the peaks are less accurate (1.8 % at 1/150 s against 0.2 % at 5 ms for
    0.01 s records)."""
    check_time_step(time_step, time_text, record_step, record_text)
    ratio = record_step / time_step
    if ratio >= 1 and abs(ratio - round(ratio)) <= 1e-6 * ratio:
        return
    divisor = record_step / max(math.ceil(ratio - 1e-9), 1)
    print(f"teflon-jax {command}: warning: --time-step {time_text} does not divide the record step "
          f"{record_text} (ratio {ratio:.4g}); the peaks are less accurate than with a divisor "
          f"such as {divisor * 1e3:.4g}ms.", file=sys.stderr)


def check_table1(ptfe: str, pressure: float, pressure_text: str, flag: str = "--pressure",
                 direction: str = "P", extrapolate: bool = False) -> None:
    """A `ValueError` naming `flag` and the pressure as typed when Table 1 has no row for
    `ptfe` at `pressure` [Pa] (or naming --ptfe or --direction when that is unknown)."""
    from ..tables import DIRECTIONS, PTFE_TYPES, interface_parameters

    if ptfe.upper() not in PTFE_TYPES:  # named as typed (the table reads it in capitals)
        raise ValueError(f"--ptfe: unknown PTFE type {ptfe!r}; accepted values: {', '.join(PTFE_TYPES)}.")
    if direction.upper() not in DIRECTIONS:
        raise ValueError(f"--direction: unknown direction {direction!r}; accepted values: P (parallel to lay), "
                         "T (perpendicular to lay).")
    try:
        interface_parameters(ptfe.upper(), pressure, direction.upper(), extrapolate=extrapolate)
    except (ValueError, KeyError) as error:
        text = str(error).strip("'\"")
        name, _, reason = text.partition(": ")
        rows = re.search(r"\(\d+-\d+ psi\)", reason)
        if name == "pressure" and rows:
            raise ValueError(f"{flag}: {pressure_text} is outside Table 1's rows for {ptfe.upper()} "
                             f"{rows.group(0)}; choose a pressure in that range.") from None
        if name == "pressure":
            raise ValueError(f"{flag}: must be > 0, got {pressure_text}.") from None
        raise ValueError(f"--{name if name in ('ptfe', 'direction') else 'ptfe'}: {reason or text}") from None


def motion_bar(total: int, disable: bool):
    """The progress bar of the motions run, with their rate in motions per second and the
    time left (counts in k, M from 1000 motions on)."""
    from tqdm import tqdm

    return tqdm(total=total, unit=" motions", unit_scale=total >= 1000, disable=disable)


def as_flags(message: str) -> str:
    """An API message with its option `reference_load` named as the flag `--reference-load`
    (not a file key such as `pressure_dependence.reference_load`), and one that opens with the
    search's `candidates` named as `--candidates`."""
    message = re.sub(r"^candidates:", "--candidates:", message)
    return re.sub(r"(?<![.\w])reference_load\b", "--reference-load", message)
