"""A bearing file's `mixture` (`diagnose --mixture bic --save-bearing FILE`) in `teflon-jax
montecarlo --bearing FILE`: each composition of effects runs a share of the N motions in
proportion to its weight, and each of its motions one draw of its constants.

The compositions differ in their parts (breakaway in one, heating in another), so each is a
program of its own: composition c runs the motions `first_c .. first_c + n_c - 1` of the seed
(`monte_carlo(first_motion=...)`, the same motions as a run of one bearing), on the structure
with its point bearing put in (`with_bearing`) and one draw of its posterior per motion
(`motion_draws`, seeded by `--bearing-seed`); the results are joined along the motions. The
shares n_c come from `BearingMixture.motion_counts` (systematic sampling, unbiased, each
floor(N w_c) or ceil(N w_c)). The summary says which composition and which draw each motion
ran, and each composition's statistics.
"""

import dataclasses
import typing

MIXTURE = "mixture"
"""The `--bearing-draws` mode of a mixture file (one composition's draw per motion)."""


class MixtureRun(typing.NamedTuple):
    """How a Monte Carlo runs a bearing file's mixture: `mixture` (`BearingMixture`), `mode`
    "mixture", `bearings` None (one run per motion), `seed` of the shares and the draws, `path`
    of the file, `counts` (C,) the motions of each composition."""

    mixture: object
    mode: str
    bearings: None
    seed: int
    path: object
    counts: object


def read_mixture_run(args, mixture, refuse_other_runs) -> MixtureRun | None:
    """The mixture run of `mixture`, the `BearingMixture` read with `--bearing FILE` (None where
    the file has none), or None (no mixture in the file, or `--bearing-draws
    point`: the file's point estimate, the composition the search chose). `ValueError` naming
    the flag, before any work, for `--bearing-draws K`, several `--pga` levels or `--limit`,
    the runs `refuse_other_runs(args, words)` refuses, and a composition the structures cannot
    run (e.g. a test rig's backlash)."""
    from ..systems import check_structure_bearing

    given = args.bearing_draws
    if mixture is None or given == "point" or (given is None and args.property_factors is not None):
        return None
    if given not in (None, MIXTURE, "motion"):
        raise ValueError(f"--bearing-draws {given}: --bearing {args.bearing} holds a mixture of "
                         f"{mixture.size} compositions (diagnose --mixture), which runs one "
                         "composition's draw per motion; give --bearing-draws motion (the default) "
                         "or point (the composition the search chose).")
    refuse_other_runs(args, "a mixture of compositions, one draw per motion")
    levels = [("--pga " + args.pga_text, len(args.pga_levels) > 1),
              *((f"--limit {text}", True) for text in args.limit or ())]
    for flag, given_flag in levels:
        if given_flag:
            raise ValueError(f"{flag}: runs one --pga level without --limit over the mixture of "
                             f"--bearing {args.bearing}; give --bearing-draws point to run the "
                             "composition the search chose, or one level.")
    for c in mixture.compositions:
        try:
            check_structure_bearing(c.bearing, args.pressure)
        except ValueError as error:
            raise ValueError(f"--bearing {args.bearing}: mixture composition {c.label} (weight "
                             f"{c.weight:.3g}): {error}") from None
    seed = bearing_seed(args)
    counts = mixture.motion_counts(args.motions, seed=seed)
    return MixtureRun(mixture, MIXTURE, None, seed, args.bearing, counts)


def bearing_seed(args) -> int:
    """`--bearing-seed`, 0 where it is not given."""
    return 0 if args.bearing_seed is None else args.bearing_seed


def runner_of(run, monte_carlo):
    """`monte_carlo`, or for a `MixtureRun` the function that runs its compositions with the
    same arguments (`structure, motions, n_motions, *, key, chunk_size, progress`)."""
    if not isinstance(run, MixtureRun):
        return monte_carlo

    def run_mixture(structure, motions, n_motions, *, key, chunk_size, progress=None):
        from ..studies import motion_draws, with_bearing

        results, first = [], 0
        for composition, count in zip(run.mixture.compositions, run.counts):
            if count == 0:
                continue
            posterior, point = composition.posterior, composition.bearing

            def shifted(done, total, first=first):
                if progress is not None:
                    progress(first + done, n_motions)

            results.append(monte_carlo(
                with_bearing(structure, point), motions, int(count), key=key, chunk_size=chunk_size,
                progress=shifted, first_motion=first, bearings=posterior.bearings(point),
                bearing_draw=motion_draws(int(count), posterior.size, seed=run.seed)))
            first += int(count)
        return joined(results)

    return run_mixture


def joined(results):
    """`MonteCarloResult`s of consecutive motions joined into one along the motions: arrays over
    the motions concatenated, the times added, the largest memory estimate. A surface result
    that only some compositions have (`surface_temperature_rise`: only a heated composition's
    surfaces warm) is 0 for the motions of the others, whose model keeps the surfaces at their
    start temperature."""
    import numpy as np

    first = results[0]
    fields = {}
    for field in dataclasses.fields(first):
        values = [getattr(r, field.name) for r in results]
        arrays = [(r, v) for r, v in zip(results, values) if isinstance(v, np.ndarray)]
        if not arrays or arrays[0][1].shape[:1] != (arrays[0][0].n_motions,):
            continue
        if len(arrays) < len(results) and field.name != "surface_temperature_rise":
            raise ValueError(f"the mixture's compositions give {field.name} for only some of their motions; "
                             "run the compositions apart (--bearing-draws point).")
        tail = arrays[0][1].shape[1:]
        fields[field.name] = np.concatenate([v if isinstance(v, np.ndarray) else np.zeros((r.n_motions, *tail))
                                             for r, v in zip(results, values)])
    return dataclasses.replace(first, **fields, wall_s=sum(r.wall_s for r in results),
                               compile_s=sum(r.compile_s for r in results),
                               memory_estimate_bytes=max(r.memory_estimate_bytes for r in results))


def mixture_attributes(run: MixtureRun) -> dict:
    """What a results file says of the mixture (beside the file's path and SHA-256)."""
    compositions = run.mixture.compositions
    return {"bearing_draws": MIXTURE, "bearing_seed": run.seed,
            "mixture_criterion": run.mixture.criterion,
            "mixture_compositions": ";".join(c.label for c in compositions),
            "mixture_weights": [c.weight for c in compositions],
            "mixture_motions": [int(n) for n in run.counts]}


def mixture_report(result, run: MixtureRun, units) -> tuple[dict, list]:
    """(the summary JSON's `bearing_mixture` entry, the lines to print): each composition's
    weight, motions, draws and statistics, and the composition and draw of every motion."""
    import numpy as np

    length, factor = units.length
    draws = np.asarray(result.bearing_draw)
    converged = np.asarray(result.converged, bool)
    peaks = {f"base_disp_{length}": np.asarray(result.base_disp) / factor,
             "base_shear_ratio": np.asarray(result.base_shear_ratio)}
    entry = {**mixture_attributes(run), "file": str(run.path), "compositions": [],
             "left_out": list(run.mixture.left_out), "min_weight": run.mixture.min_weight,
             "motion_allocation": "systematic sampling of the weights (each composition floor or ceil "
                                  "of N w), composition c on the motions after those of 0..c-1"}
    lines = [f"bearing mixture of {run.path} ({run.mixture.criterion}): " + ", ".join(
        f"{c.label} (w {c.weight:.3g}) {int(n)} motions"
        for c, n in zip(run.mixture.compositions, run.counts))]
    first = 0
    for c, n in zip(run.mixture.compositions, (int(n) for n in run.counts)):
        ok = converged[first:first + n]
        stats = {key: {q: (float(np.percentile(x[first:first + n][ok], g)) if ok.any() else None)
                       for q, g in (("p50", 50), ("p95", 95))} for key, x in peaks.items()}
        entry["compositions"].append({
            "effects": list(c.effects), "weight": c.weight, "delta_bic": c.delta_bic, "motions": n,
            "first_motion": first, "posterior_draws": c.posterior.size,
            "constants": list(c.posterior.names), "n_converged": int(ok.sum()), **stats})
        first += n
    entry["composition"] = np.repeat(np.arange(run.mixture.size), run.counts).tolist()
    entry["bearing_draw"] = [int(k) for k in draws]
    return {"bearing_mixture": entry}, lines
