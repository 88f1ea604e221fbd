"""The bearing-file flags: `--save-bearing FILE` (fit, diagnose) and `--bearing FILE` (every
command that simulates), checked before any work starts."""

import pathlib
import sys

from ._common import flags_given

BEARING_OPTIONS = ("ptfe", "pressure", "direction", "breakaway", "interfaces_in_series", "yield_disp",
                   "anisotropic", "lay_angle")
"""Flags that describe the bearing; with `--bearing FILE` they may not be given as well."""


def add_bearing_flag(parser, *, replaces: str) -> None:
    """`--bearing FILE`: run the bearing of a bearing file instead of `replaces`. Call after
    the bearing's own flags are declared (their defaults are kept to refuse both at once)."""
    parser.add_argument("--bearing", default=None, metavar="FILE", type=pathlib.Path,
                        help="bearing file written by `fit` or `diagnose --save-bearing` (its "
                             f"friction law and optional parts replace {replaces})")
    declared = {action.dest for action in parser._actions}
    parser.set_defaults(bearing_option_defaults={
        name: parser.get_default(name) for name in BEARING_OPTIONS if name in declared})


def add_save_bearing_flag(parser) -> None:
    """`--save-bearing FILE`: write the bearing the command found."""
    parser.add_argument("--save-bearing", default=None, metavar="FILE", type=pathlib.Path,
                        help="write the fitted bearing (its parts, each constant with unit and "
                             "standard error, the records it came from) as a bearing file, "
                             "which `simulate-test`, `run`, `montecarlo` and `design` read "
                             "with --bearing")


def check_output_file(path, flag: str) -> None:
    """`ValueError` naming `flag` when `path` cannot be written as a file (a folder, or a
    parent folder that does not exist)."""
    if path is None:
        return
    path = pathlib.Path(path)
    if path.is_dir():
        raise ValueError(f"{flag} {path}: is a folder; give a file name, e.g. {path / 'out.json'}.")
    if not path.parent.exists():
        raise ValueError(f"{flag} {path}: the folder {path.parent} does not exist; create it first.")


def warn_unidentified(args, read) -> None:
    """A warning on stderr for each constant of `--bearing FILE` (`read`, its `BearingFile`) that
    the fit which wrote the file could not determine (`formats.unidentified_constants`): the run
    takes its value, that fit's start or a guess, as written."""
    for name, value in read.unidentified:
        print(f"teflon-jax {args.command}: warning: --bearing {args.bearing}: {name} = {value:.6g} was not "
              "determined by the fit that wrote the file (the records did not constrain it: its standard error is "
              "null), so it is that fit's start or a guess; it is run as written (edit the file to set it).",
              file=sys.stderr)


def read_bearing_flag(args):
    """The `BearingFile` of `--bearing FILE` (its bearing, posterior and mixture), or `None` when
    not given: the file read and parsed here, once per command (the caller passes on what it
    returns), its unidentified constants warned of (`warn_unidentified`). A bearing flag that
    differs from its default as well is refused (the file says what the bearing is), except
    `--pressure` for a bearing with heating or pressure dependence: the bearings' contact
    pressure in the structure."""
    from ..formats import read_bearing_file
    from ._provenance import note_bearing_file

    if getattr(args, "bearing", None) is None:
        return None
    try:
        read = read_bearing_file(args.bearing)
    except ValueError as error:
        raise ValueError(f"--bearing {error}") from None
    warn_unidentified(args, read)
    bearing = read.bearing
    takes_pressure = bearing.heating is not None or bearing.pressure_dependence is not None
    note_bearing_file(args.bearing, takes_pressure)
    allowed = {"pressure"} if takes_pressure else set()
    defaults = {name: default for name, default in getattr(args, "bearing_option_defaults", {}).items()
                if name not in allowed}
    given = flags_given(args, defaults)
    if given:
        flag = given[0]
        raise ValueError(f"{flag}: the bearing comes from --bearing {args.bearing}; leave "
                         f"{flag} out (or edit the bearing file)"
                         + (" (--pressure is the contact pressure of a bearing with "
                            "heating or pressure dependence)." if flag == "--pressure"
                            else "."))
    return read


def save_bearing_flag(args, bearing, *, standard_errors, sources, fit) -> None:
    """Write `bearing` where `--save-bearing` says (nothing when not given)."""
    from ..formats import save_bearing

    if getattr(args, "save_bearing", None) is None:
        return
    save_bearing(args.save_bearing, bearing, standard_errors=standard_errors, sources=sources,
                 fit=fit)
