"""The files `fit` and `diagnose` save what they found in (`--save-isolator`, `--save-bearing`),
checked before the first output is written: each is built and read back as its loader reads it
(`teflon_jax.formats.isolator_from_dict`, `bearing_from_dict`), so that a result the file cannot
hold (e.g. a series pendulum whose fitted friction breaks the series model's order) is refused
while nothing is written yet, and the command leaves no partial outputs."""

import json


def _read_back(build, reader, flag: str, path, what: str) -> None:
    """`ValueError` naming `flag` and `path` when `build()` (the file's object) fails or `reader`
    refuses what it builds, as written."""
    try:
        reader(json.loads(json.dumps(build(), allow_nan=False)), where=f"{flag} {path}")
    except ValueError as error:
        raise ValueError(f"{flag} {path}: the {what} found cannot be saved: {error} Nothing was "
                         "written (no JSON, report or plot either).") from None


def isolator_writer(path, bearing, flag: str = "--save-isolator"):
    """A function of no arguments that writes `bearing` (a `SeriesPendulum`) as the isolator
    file at `path` (nothing for `path` None); `ValueError` naming `flag` first when the file
    cannot hold it."""
    if path is None:
        return lambda: None
    from ..formats import isolator_from_dict, isolator_to_dict, write_isolator

    _read_back(lambda: isolator_to_dict(bearing), isolator_from_dict, flag, path, "isolator")
    return lambda: write_isolator(path, bearing)


def bearing_writer(path, bearing, flag: str = "--save-bearing", **entries):
    """A function of no arguments that writes `bearing` (a `SlidingBearing`) as the bearing file
    at `path` with `entries` (`teflon_jax.formats.save_bearing`'s standard errors, sources, fit,
    mixture); `ValueError` naming `flag` first when the file cannot hold it."""
    if path is None:
        return lambda: None
    from ..formats import bearing_from_dict, bearing_to_dict, save_bearing

    _read_back(lambda: bearing_to_dict(bearing, **entries), bearing_from_dict, flag, path, "bearing")
    return lambda: save_bearing(path, bearing, **entries)
