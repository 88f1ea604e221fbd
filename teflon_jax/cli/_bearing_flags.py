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


def _bearing_file(args):
    """(the `SlidingBearing` of `--bearing FILE`, its unidentified constants
    (`formats.unidentified_constants`)), or `None` when not given: the file read once per
    command (kept on `args`, as its `ValueError` naming what is wrong with it)."""
    path = getattr(args, "bearing", None)
    if path is None:
        return None
    kept = getattr(args, "_bearing_file", None)
    if kept is None or kept[0] != path:
        from ..formats import bearing_from_dict, read_json_document, unidentified_constants

        try:
            document = read_json_document(path, "bearing file")
            loaded = bearing_from_dict(document, where=str(path)), unidentified_constants(document)
        except ValueError as error:
            loaded = error
        kept = args._bearing_file = (path, loaded)
    if isinstance(kept[1], ValueError):
        raise kept[1]
    return kept[1]


def warn_unidentified(args) -> None:
    """A warning on stderr for each constant of `--bearing FILE` that the fit which wrote the
    file could not determine (`formats.unidentified_constants`): the run takes its value, that
    fit's start or a guess, as written."""
    try:
        loaded = _bearing_file(args)
    except ValueError:  # not a bearing file: read_bearing_flag names what is wrong
        return
    for name, value in [] if loaded is None else loaded[1]:
        print(f"teflon-jax {args.command}: warning: --bearing {args.bearing}: {name} = {value:.6g} was not "
              "determined by the fit that wrote the file (the records did not constrain it: its standard error is "
              "null), so it is that fit's start or a guess; it is run as written (edit the file to set it).",
              file=sys.stderr)


def read_bearing_flag(args):
    """The `SlidingBearing` of `--bearing FILE`, or `None` when not given. A bearing flag that
    differs from its default as well is refused (the file says what the bearing is), except
    `--pressure` for a bearing with heating or pressure dependence: the bearings' contact
    pressure in the structure."""
    try:
        loaded = _bearing_file(args)
    except ValueError as error:
        raise ValueError(f"--bearing {error}") from None
    if loaded is None:
        return None
    bearing = loaded[0]
    allowed = ({"pressure"} if bearing.heating is not None or bearing.pressure_dependence
               is not None else set())
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
    return bearing


def save_bearing_flag(args, bearing, *, standard_errors, sources, fit) -> None:
    """Write `bearing` where `--save-bearing` says (nothing when not given)."""
    from ..formats import save_bearing

    if getattr(args, "save_bearing", None) is None:
        return
    save_bearing(args.save_bearing, bearing, standard_errors=standard_errors, sources=sources,
                 fit=fit)
