"""What an engineer's analysis adds to a Monte Carlo on the command line: response limits
(`--limit base_disp=2in`), storey results (`--storeys`) and pelicun demand files
(`--pelicun-demands FILE.csv`), read and checked before any run starts.

A limit names a peak and a value with its unit, read by `teflon_jax.units.parse_quantity`:
`base_disp` (the isolators' displacement, a length), `base_shear_ratio` (base shear over the
weight above the isolators), `drift` (the largest storey's interstorey drift ratio, building
only) and `floor_acceleration` (the largest total acceleration of the base slab and the
floors, building only). A run exceeds it when its peak is above the value.
"""

import dataclasses
import re

import numpy as np

from ..units import STANDARD_GRAVITY, parse_quantity
from ._bounding import add_bounding_flags

LIMITS = {
    "base_disp": ("length", "peak isolator displacement"),
    "base_shear_ratio": ("dimensionless", "peak base shear / weight above the isolators"),
    "drift": ("dimensionless", "peak interstorey drift ratio of the worst storey"),
    "floor_acceleration": ("acceleration", "peak total acceleration of the worst level (base slab, floors)"),
    "slider_capacity_ratio": ("dimensionless", "largest peak slider travel over its capacity, over the sliders of "
                              "a double or triple pendulum (1: a slider reaches its restrainer)"),
}
"""Names a `--limit` may take: name -> (dimension, what is compared)."""

STOREY_LIMITS = ("drift", "floor_acceleration")


@dataclasses.dataclass(frozen=True)
class Limit:
    """`name` (a key of `LIMITS`), `value` [SI] and `text` as the user wrote it (NAME=VALUE)."""

    name: str
    value: float
    text: str

    def peaks(self, result) -> np.ndarray:
        """The peak each motion of a `MonteCarloResult` compares with `value` (SI): (N,), or
        (K, N) for K bearing draws each run on the N motions (`result.nested`)."""
        if self.name in ("base_disp", "base_shear_ratio"):
            return np.asarray(getattr(result, self.name))
        lead = 2 if getattr(result, "nested", False) else 1
        if self.name == "slider_capacity_ratio":  # every group's every slider over its capacity
            values = np.asarray(result.slider_travel) / np.asarray(result.attrs["slider_capacities_m"])
        else:
            values = np.asarray(result.storey_drift if self.name == "drift" else result.floor_acceleration)
        return np.max(values.reshape(values.shape[:lead] + (-1,)), axis=-1)  # every storey (and direction)


def add_engineering_flags(parser) -> None:
    """`--limit NAME=VALUE` (repeatable), `--storeys`, `--pelicun-demands FILE.csv`,
    `--property-factors LOWER,UPPER|posterior`, `--posterior-quantiles LOWER,UPPER`."""
    parser.add_argument("--limit", action="append", default=[], metavar="NAME=VALUE",
                        help="a response limit for a fragility curve, repeatable: base_disp=2in, "
                        "base_shear_ratio=0.15, drift=1%%, floor_acceleration=0.5g (drift and "
                        "floor_acceleration: building only), slider_capacity_ratio=1 (the largest slider "
                        "travel over its capacity: a double or triple pendulum's sliders reaching their "
                        "restrainers); with two or more --pga levels each "
                        "gets a lognormal fragility fitted by maximum likelihood (Baker 2015) (default: none)")
    parser.add_argument("--storeys", action="store_true",
                        help="building: also keep each storey's peak drift ratio and each level's peak "
                        "total acceleration (in x and y with --components 2; on with drift or "
                        "floor_acceleration limits and --pelicun-demands)")
    parser.add_argument("--pelicun-demands", metavar="FILE.csv", default=None,
                        help="write the peaks as demand samples in pelicun's format (PFA per level, PID "
                        "per storey, the isolators' displacement as BRD, a double or triple pendulum's "
                        "slider travel as BRD_<slider>, failed runs flagged in ERROR); "
                        "with several --pga levels one file per level, FILE-level1.csv, ...")
    add_bounding_flags(parser, "bounding analysis: run the nominal bearing and its lower- and upper-bound "
                       "variants (f_max and delta_f of Eq. 1 times LOWER and UPPER, e.g. 0.85,1.3; on every "
                       "surface of a triple or double pendulum, its radii and capacities kept; 'posterior': "
                       "each constant at a quantile of the posterior draws of the --bearing file, see "
                       "--posterior-quantiles) under the same motions, and report which case governs "
                       "displacement, base shear and drift; with --scheduler the three cases are the design "
                       "axis of the distributed run (--out FILE.nc)")


def parse_limits(texts, structure: str, components: int) -> list[Limit]:
    """The `--limit` texts as `Limit`s; `ValueError` naming the text as written for an unknown
    name, a value without its unit or not > 0, a storey limit on the rigid mass and a repeated
    limit. With two `components` the storey limits take the worse direction."""
    limits = []
    for text in texts:
        name, sep, value = text.partition("=")
        name = name.strip()
        if not sep or not value.strip():
            raise ValueError(f"--limit {text}: write NAME=VALUE, e.g. base_disp=2in.")
        if name not in LIMITS:
            raise ValueError(f"--limit {text}: unknown {name!r}; accepted: {', '.join(LIMITS)}.")
        if name in STOREY_LIMITS and structure != "building":
            raise ValueError(f"--limit {text}: storey results need --structure building.")
        number = parse_quantity(value.strip(), LIMITS[name][0], where=f"--limit {name}")
        if not np.isfinite(number) or not number > 0:
            raise ValueError(f"--limit {text}: the value must be finite and > 0.")
        if any(other.name == name and other.value == number for other in limits):
            raise ValueError(f"--limit {text}: given twice.")
        limits.append(Limit(name, float(number), text.strip()))
    return limits


def wants_storeys(args, limits) -> bool:
    """Whether the run keeps storey results; `ValueError` naming the flag where it cannot."""
    wanted = args.storeys or args.pelicun_demands is not None or any(lim.name in STOREY_LIMITS for lim in limits)
    if args.storeys and args.structure != "building":
        raise ValueError("--storeys: storey results need --structure building.")
    return wanted and args.structure == "building"


def intensity_unit(text: str) -> tuple[str, float]:
    """(unit as written, its SI factor) of the first level of a `--pga` text ('0.1g,0.2g' -> g)."""
    first = str(text).split(",")[0]
    unit = re.sub(r"^\s*[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?\s*", "", first).strip() or "m/s^2"
    return unit, parse_quantity("1" + unit, "acceleration", where="--pga")


def level_paths(path, n_levels: int) -> list:
    """The pelicun file of each level: `path` itself for one, `<stem>-level<j><suffix>` for more."""
    import pathlib

    path = pathlib.Path(path)
    if n_levels == 1:
        return [path]
    return [path.with_name(f"{path.stem}-level{j + 1}{path.suffix}") for j in range(n_levels)]


def pelicun_peaks(result, rows, components: int = 1) -> dict:
    """The keyword arguments of `write_pelicun_demands` for the motions `rows` of a result:
    the building's level accelerations and storey drifts (per direction with two
    `components`), or for a rigid mass under one its total acceleration |V| / m =
    base_shear_ratio g as level 0; with two components the base displacement and ground
    acceleration are resultants, so the first goes in as non-directional and the second not;
    a series pendulum's sliders' travel (`slider_demands`) where the result keeps it."""
    one = components == 1
    peaks = {"base_disp": result.base_disp[rows], "failed": ~np.asarray(result.converged, bool)[rows],
             "pga": result.pga[rows] if one else None, "base_direction": 1 if one else 0}
    if result.slider_travel is not None:
        peaks.update(slider_demands(np.asarray(result.slider_travel)[rows], result.attrs.get("slider_names")))
    if result.storey_drift is not None:
        peaks["level_acceleration"] = result.floor_acceleration[rows]
        peaks["storey_drift"] = result.storey_drift[rows]
    elif one:
        peaks["level_acceleration"] = (result.base_shear_ratio[rows] * STANDARD_GRAVITY)[:, None]
    return peaks


def slider_demands(travel, names) -> dict:
    """`slider_travel` (R, S) [m] and `slider_names` of `write_pelicun_demands` from a series
    pendulum's peak travel per run, bearing group and slider (R, G, S): each slider's largest
    over the groups (their isolators alike, the worst group's slider nearest its restrainer)."""
    return {"slider_travel": np.max(np.asarray(travel, float), axis=1), "slider_names": names}


def add_suite_pelicun_flag(parser) -> None:
    """`--pelicun-demands FILE.csv` on `teflon-jax run --suite`."""
    parser.add_argument("--pelicun-demands", metavar="FILE.csv", default=None,
                        help="with --suite: write each pair's peaks as a demand sample in pelicun's format "
                        "(PFA per level and PID per storey in x and y for the building, the ground's PFA, "
                        "the isolators' resultant displacement as BRD-1-0, a double or triple pendulum's sliders' "
                        "travel as BRD_<slider>-1-0, failed runs flagged in ERROR); the "
                        "building's storey results then go into the suite's NetCDF file too")


def suite_pelicun_peaks(result, ax, ay) -> dict:
    """The keyword arguments of `write_pelicun_demands` for a `SuiteResult` of record pairs
    (ax, ay) (P, n) [m/s^2]: the ground's peak per direction, the building's storey results in
    x and y when the suite kept them, the resultant base displacement as non-directional, and
    so a series pendulum's sliders' travel (`slider_demands`)."""
    peaks = {"base_disp": result.peaks["base_disp_resultant_m"], "failed": ~np.asarray(result.converged, bool),
             "pga": np.stack([np.abs(ax).max(axis=1), np.abs(ay).max(axis=1)], axis=1), "base_direction": 0}
    if result.surfaces is not None and "slider_travel" in result.surfaces:
        peaks.update(slider_demands(result.surfaces["slider_travel"], result.surfaces.get("slider_names")))
    if result.storeys is not None:
        peaks["level_acceleration"] = result.storeys["level_acceleration"]
        peaks["storey_drift"] = result.storeys["storey_drift"]
    return peaks


def check_bounding_flags(args, isolator):
    """`--property-factors` and `--posterior-quantiles` of `montecarlo` on `isolator`
    (`read_isolator`) checked before any work: their `Bounds`, or None without them
    (`read_property_factors`: `ValueError` naming the flag)."""
    from ._bounding import read_property_factors

    if args.property_factors is not None or args.posterior_quantiles is not None:
        return read_property_factors(args, isolator)
    return None
