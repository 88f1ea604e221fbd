"""The bearing posterior in `teflon-jax montecarlo`: `--bearing-draws` and `--bearing-seed`,
checked before any work, the run's arguments, and what the summary says of the draws.

A bearing file (or a series pendulum's isolator file) whose `posterior` section holds S draws of the fitted constants runs one draw
per motion by default (motion m takes draw k(m), a seeded permutation cycled: without
replacement while N <= S); `--bearing-draws K` runs K draws each on the same N motions and
splits each peak's variance into a motion part and a bearing part (law of total variance);
`--bearing-draws point` runs the file's point estimate alone.

Over several `--pga` levels with `--limit` the same draws run at every level: nested, each
of the K bearings runs every level's N motions, and each limit's fragility gets a band over
the bearings (`fragility_band`); one draw per motion, motion m of every level runs the same
draw k(m), and the fit is over the bearing's and the motions' uncertainty together, with no
band.
"""

import argparse
import typing

from ._common import seed_value
from ._mixture_runs import (
    MIXTURE,
    bearing_seed,
    mixture_attributes,
    mixture_report,
    read_mixture_run,
)

POINT, MOTION = "point", "motion"

BAND = (5.0, 95.0)
"""Percentiles of the K per-bearing 95th percentiles that bound the band the summary gives."""


class PosteriorRun(typing.NamedTuple):
    """How a Monte Carlo runs a bearing file's posterior: `posterior` (`BearingPosterior`,
    or an isolator file's `IsolatorPosterior`), `mode` "motion" (a draw per motion) or "nested"
    (K draws x N motions), `bearings` K (nested) or None, `seed` of the draws' order, `path` of
    the file, `point` its point estimate (the bearing or pendulum read with the draws)."""

    posterior: object
    mode: str
    bearings: int | None
    seed: int
    path: object
    point: object


def _draws_value(text: str):
    """`--bearing-draws`: "point", "motion" or a number of bearings K >= 1."""
    if text in (POINT, MOTION):
        return text
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected 'point', 'motion' or a number of bearings K "
                                         f"(e.g. 20), got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"the number of bearings K must be at least 1, got {text}")
    return value


def add_posterior_flags(parser) -> None:
    """`--bearing-draws point|motion|K` and `--bearing-seed S`."""
    parser.add_argument("--bearing-draws", type=_draws_value, default=None, metavar="point|motion|K",
                        help="with a --bearing file that holds posterior draws (fit --bayes): "
                        "'motion' gives each motion its own draw (the default for such a file), "
                        "K runs K draws each on the same --motions motions and splits the variance "
                        "of each peak into a motion part and a bearing part, 'point' runs the "
                        "file's point estimate alone")
    parser.add_argument("--bearing-seed", type=seed_value, default=None, metavar="S",
                        help="with a --bearing file's posterior draws or mixture: seed of the order in "
                        "which they are taken (default 0)")


def read_posterior_flags(args, isolator) -> PosteriorRun | None:
    """The posterior run the flags ask for (a `MixtureRun` for a file with a mixture), or `None`
    (the point bearing, as without a posterior), of the draws read with `isolator`'s bearing or
    isolator file (`read_isolator`: the file is not read again): `ValueError` naming the flag, before any work,
    for --bearing-draws without a --bearing file that holds a posterior, K above its number of
    draws, --bearing-seed where no draws are taken, and the flags whose runs do not take draws
    (--storeys and the storey limits of --limit, --pelicun-demands, --scheduler,
    --property-factors given with --bearing-draws); several --pga levels and the --limit of
    base_disp and base_shear_ratio take them."""
    run = _posterior_run(args, isolator)
    if run is None and args.bearing_seed is not None:
        isolator_file = getattr(args, "isolator_file", None)
        why = (f"--bearing {args.bearing} runs as its point estimate here" if args.bearing is not None else
               f"--isolator-file {isolator_file} runs as its point estimate here" if isolator_file is not None
               else "no --bearing FILE is given")
        raise ValueError(f"--bearing-seed {args.bearing_seed}: orders the posterior draws (or a mixture's) of "
                         f"a --bearing file or an --isolator-file, and {why}; leave --bearing-seed out.")
    return run


def _posterior_run(args, isolator) -> PosteriorRun | None:
    given = args.bearing_draws
    isolator_file = getattr(args, "isolator_file", None)
    if args.bearing is None and isolator_file is not None:  # a series pendulum's draws, if its file has them
        flag, path, point = "--isolator-file", isolator_file, isolator.pendulum
    elif args.bearing is None:
        if given is not None:
            raise ValueError(f"--bearing-draws {given}: needs --bearing FILE, a bearing file with "
                             "posterior draws (fit --bayes DIR --save-bearing FILE), or --isolator-file FILE "
                             "with them (fit --isolator double-fp|triple-fp --bayes DIR --save-isolator FILE).")
        return None
    else:
        flag, path, point = "--bearing", args.bearing, isolator.bearing
    posterior = isolator.posterior
    if posterior is None:
        mixture = read_mixture_run(args, isolator.mixture, _refuse_other_runs) if flag == "--bearing" else None
        if mixture is None and given not in (None, POINT):
            raise ValueError(f"--bearing-draws {given}: {flag} {path} holds no posterior "
                             "draws (no 'posterior' section); write one with fit --bayes DIR "
                             f"{'--save-bearing' if flag == '--bearing' else '--save-isolator'} FILE, "
                             "or leave --bearing-draws out.")
        return mixture
    if given == POINT or (given is None and args.property_factors is not None):
        return None  # the point estimate; bounding cases take the bearing as a whole
    if getattr(args, "plan", None) is not None:
        raise ValueError(f"{flag} {path}: holds posterior draws, which vary the bearing of a structure rebuilt "
                         "for each run, and a structure on --plan is built once; give --bearing-draws point to "
                         "run the file's own constants.")
    if isinstance(given, int) and given > posterior.size:
        raise ValueError(f"--bearing-draws {given}: the posterior of {flag} {path} has "
                         f"{posterior.size} draws; ask for at most {posterior.size} bearings.")
    _refuse_other_runs(args, "--bearing-draws " + str(given or MOTION), f"{flag} {path}")
    mode = MOTION if given in (None, MOTION) else "nested"
    return PosteriorRun(posterior, mode, None if mode == MOTION else given, bearing_seed(args), path, point)


def _refuse_other_runs(args, words: str, source: str | None = None) -> None:
    from ._engineering import STOREY_LIMITS, parse_limits

    storey_limits = [lim.text for lim in parse_limits(args.limit, args.structure, args.components)
                     if lim.name in STOREY_LIMITS]
    others = (("--property-factors", args.property_factors is not None),
              ("--storeys", args.storeys), ("--pelicun-demands", args.pelicun_demands is not None),
              ("--scheduler", args.scheduler is not None),
              *((f"--limit {text}", True) for text in storey_limits))
    for flag, given in others:
        if given:
            why = " (a storey limit keeps the storey results)" if flag.startswith("--limit") else ""
            raise ValueError(f"{flag}: runs without the posterior draws of {source or '--bearing ' + str(args.bearing)}{why} "
                             f"({words}); give --bearing-draws point to run its point estimate, or "
                             f"leave {flag} out.")


def runs_of(args, run: PosteriorRun | None) -> int:
    """The number of runs: N motions, or K bearings x N motions."""
    return args.motions * (1 if run is None or run.bearings is None else run.bearings)


def posterior_arguments(run: PosteriorRun | None, n_motions: int) -> dict:
    """The keyword arguments of `monte_carlo` that run the draws of `run` with `n_motions`
    motions: the posterior's bearings stacked on the file's point bearing (the structure's own)
    and the draws each motion (`motion_draws`) or each bearing (`nested_draws`) takes."""
    from ..studies import motion_draws, nested_draws

    if run is None or run.mode == MIXTURE:  # a mixture: runner_of runs its compositions
        return {}
    stacked, size = run.posterior.bearings(run.point), run.posterior.size
    if run.mode == MOTION:
        return {"bearings": stacked, "bearing_draw": motion_draws(n_motions, size, seed=run.seed)}
    return {"bearings": stacked, "bearing_draw": nested_draws(run.bearings, size, seed=run.seed), "nested": True}


def posterior_attributes(run: PosteriorRun | None) -> dict:
    """What a results file says of the draws (beside the file's path and SHA-256)."""
    if run is None:
        return {}
    if run.mode == MIXTURE:
        return mixture_attributes(run)
    return {"bearing_draws": run.mode, "bearing_seed": run.seed, "posterior_draws": run.posterior.size,
            "posterior_constants": ",".join(run.posterior.names),
            **({} if run.bearings is None else {"bearings": run.bearings})}


def posterior_report(result, run: PosteriorRun | None, units) -> tuple[dict, list]:
    """(the summary JSON's `bearing_posterior` entry, the lines to print) of a run with draws:
    the draw of each motion or bearing and, nested, the variance split and the 95th
    percentile's band of each peak (displacements in the output units); nested, the runs
    K N (`n_runs`; `records_per_s` counts them, `throughput`)."""
    import numpy as np

    if run is None:
        return {}, []
    if run.mode == MIXTURE:
        return mixture_report(result, run, units)
    length, factor = units.length
    entry = {**posterior_attributes(run), "bearing_draw": [int(k) for k in result.bearing_draw]}
    lines = [f"bearing posterior of {run.path}: {run.posterior.size} draws of "
             f"{', '.join(run.posterior.names)}; " + ("one per motion" if run.bearings is None else
                                                      f"{run.bearings} bearings x {result.n_motions} motions")]
    if run.bearings is None:
        return {"bearing_posterior": entry}, lines
    failed = np.argwhere(~np.asarray(result.converged, bool))
    entry["not_converged"] = [{"bearing": int(k), "motion": int(m)} for k, m in failed]
    runs = int(np.size(result.converged))
    top = {"n_runs": runs}
    for name, key, scale, unit in (("base_disp", f"base_disp_{length}", factor, f" {length}"),
                                   ("base_shear_ratio", "base_shear_ratio", 1.0, "")):
        split, band = result.variance_split(name), result.percentile_band(name, 95.0, BAND)
        entry[key] = {
            "variance": {k: (v / scale**2 if isinstance(v, float) and k != "bearing_share" else v)
                         for k, v in split.items()},
            "p95": {k: _scaled(v, scale) for k, v in band.items() if k not in ("q", "band_percentiles")},
            "p95_band_percentiles": list(BAND)}
        share = split["bearing_share"]
        lines.append(f"  {key}: bearing share of the variance {share:.3g}" if share is not None else
                     f"  {key}: no variance")
        if band["band"] is not None:
            lines[-1] += (f"; p95 of all runs {band['pooled'] / scale:.4g}{unit}, of each bearing's "
                          f"runs median {band['median'] / scale:.4g}{unit}, {BAND[0]:g}-{BAND[1]:g} % "
                          f"band {band['band'][0] / scale:.4g}-{band['band'][1] / scale:.4g}{unit}")
    entry["variance_units"] = {f"base_disp_{length}": f"{length}^2", "base_shear_ratio": "-"}
    return {**top, "bearing_posterior": entry}, lines


def _scaled(value, scale):
    if value is None:
        return None
    if isinstance(value, list):
        return [_scaled(v, scale) for v in value]
    return value / scale


MOTION_DRAWS_NO_BAND = ("each motion ran one posterior draw, motion m the same draw at every level: the fit is "
                        "over the bearing's and the motions' uncertainty together, with no band over the draws "
                        "(--bearing-draws K runs K bearings on every level's motions and gives one)")
"""What a fragility entry of a run with one draw per motion says in place of its band."""


def posterior_levels_entry(result, run: PosteriorRun | None) -> dict:
    """The summary JSON's `bearing_posterior` entry of a run over intensity levels: the
    attributes of the draws, the draw of each bearing (nested) or of motion m of every level
    (one per motion), and how the fragilities treat them."""
    if run is None:
        return {}
    draws = [int(k) for k in result.bearing_draw]
    if run.bearings is None:  # (L N,): the level's (N,) draws repeated at every level
        draws = draws[:int(result.attrs["motions_per_level"])]
        return {"bearing_posterior": {**posterior_attributes(run), "bearing_draw": draws,
                                      "bearing_draw_of": "motion m of every level", "fragility": MOTION_DRAWS_NO_BAND}}
    return {"n_runs": int(result.converged.size),
            "bearing_posterior": {**posterior_attributes(run), "bearing_draw": draws,
                                  "bearing_draw_of": "bearing k, run on every level's motions",
                                  "fragility": "the fit of all runs, and its band over the bearings (bearing_band)"}}
