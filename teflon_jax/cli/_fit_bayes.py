"""`teflon-jax fit --bayes DIR`: the posterior (NUTS) beside the least-squares fit, in DIR and,
with --save-bearing, in the bearing file; with --each, one fit and one posterior per record,
each in DIR/<record name>/, one compiled sampler serving records of the same length.

Messages go to stderr. JAX is imported inside the functions (`--help` loads none).
"""

import pathlib
import sys

from ._common import _write_json, output_units

DEFAULT_POSTERIOR_DRAWS = 1000
"""Most posterior draws a bearing file keeps (`--posterior-draws`)."""

PREFIX = "teflon-jax fit --bayes"


def add_bayes_file_flags(parser) -> None:
    """`--posterior-draws N` and `--each` (with --bayes)."""
    parser.add_argument("--posterior-draws", type=int, default=None, metavar="N",
                        help="with --bayes and --save-bearing (or --each): the most posterior "
                             "draws the bearing file keeps, every k-th of all chains' draws "
                             f"(default {DEFAULT_POSTERIOR_DRAWS}); the file also records each "
                             "constant's effective sample size of the whole run")
    parser.add_argument("--each", action="store_true",
                        help="with --bayes: fit each record alone (least squares, then its "
                             "posterior), writing fit.json, posterior.json, posterior.nc, "
                             "pairs.png and bearing.json (with the posterior) into DIR/<record "
                             "name>/ and a summary to --json; records of one length share one "
                             "compiled sampler. A record that fails is reported and the command "
                             "exits 1 (2 if one was refused as bad input) after the others")


SAMPLER_DEFAULTS = {"prior": "bounds", "draws": 1000, "chains": 4, "seed": 0}
"""The sampler's flags (--prior, --draws, --chains, --seed) where --bayes is given without them."""


def check_bayes_flags(args, *, posterior: bool = True, series: bool = False) -> None:
    """`ValueError` naming the flag, before any work, for --posterior-draws, --each and the
    sampler's flags (`SAMPLER_DEFAULTS`) given where they do not apply or with values they
    cannot take; with --bayes, the sampler's flags left out take their defaults on `args`.
    `posterior`: whether the isolator's law is one the sampler knows (the flat slider's,
    `_isolator_table.FitRow`); `series`: the posterior of a double or triple pendulum's
    surfaces (`run_series_bayes`: its own prior, its draws kept by --save-isolator)."""
    each, draws = getattr(args, "each", False), getattr(args, "posterior_draws", None)
    if args.bayes is None:
        for flag, given in (("--each", each), ("--posterior-draws", draws is not None),
                            *((f"--{name}", getattr(args, name) is not None) for name in SAMPLER_DEFAULTS)):
            if given:
                raise ValueError(f"{flag}: applies with --bayes DIR (the posterior); add --bayes "
                                 f"DIR or leave {flag} out.")
        return
    for name, default in SAMPLER_DEFAULTS.items():
        if getattr(args, name) is None:
            setattr(args, name, default)
    if draws is not None and draws < 1:
        raise ValueError(f"--posterior-draws: must be an integer >= 1, got {draws}.")
    if series and args.prior != "bounds":
        raise ValueError(f"--prior {args.prior}: Table 1's prior is that of one flat interface; a "
                         "series pendulum's surfaces take the bounded prior (--prior bounds, the default).")
    if series and draws is not None and getattr(args, "save_isolator", None) is None:
        raise ValueError("--posterior-draws: sets the draws kept in the isolator file; add "
                         "--save-isolator FILE, or leave --posterior-draws out.")
    if not series and draws is not None and args.save_bearing is None and not each:
        raise ValueError("--posterior-draws: sets the draws kept in the bearing file; add "
                         "--save-bearing FILE (or --each), or leave --posterior-draws out.")
    if not each:
        return
    if not posterior or args.effects is not None:
        raise ValueError("--each: the posterior is sampled for the flat slider's law (Eq. 1 with "
                         "Bouc-Wen); leave --each out with --isolator or --effects.")
    for flag, value, where in (("--save-bearing", args.save_bearing, "bearing.json"),
                               ("--plot", args.plot, "pairs.png")):
        if value is not None:
            raise ValueError(f"{flag}: with --each every record's {where} is written into "
                             f"{pathlib.Path(args.bayes) / '<record name>'}; leave {flag} out.")
    seen = {}
    for path in args.records:
        stem = pathlib.Path(path).stem
        if stem in seen:
            raise ValueError(f"--each: the records {seen[stem]} and {path} share the name "
                             f"'{stem}', so their results would share {pathlib.Path(args.bayes) / stem}; "
                             "rename one of them.")
        seen[stem] = path


def _print_block(done: int, total: int) -> None:
    """One line per block of draws (also with --no-progress)."""
    what = "warm-up done" if done == 0 else f"{done} of {total} draws per chain done"
    print(f"{PREFIX}: {what}", file=sys.stderr, flush=True)


def _unit_of(family: str):
    """name -> (unit, SI value of one unit) of `--units` for the posterior table."""
    from ..report import parameter_unit

    units = output_units(family)

    def unit_of(name):
        return units.force if name == "noise_level" else parameter_unit(name, units.length)

    return unit_of


def _posterior_files(out, result, unit_of) -> None:
    """posterior.json, posterior.nc and pairs.png (axes in the units `unit_of` gives) in `out`,
    and the table on stderr."""
    _write_json(out / "posterior.json", result.to_json_dict())
    result.to_netcdf(out / "posterior.nc")
    result.plot_pairs(out / "pairs.png", unit_of=unit_of)
    print(result.summary(unit_of=unit_of), file=sys.stderr)


def _write_posterior(out, result, unit_of) -> None:
    """posterior.json, posterior.nc, pairs.png and the table on stderr (`_posterior_files`),
    then the run's messages (why it is not converged)."""
    _posterior_files(out, result, unit_of)
    for message in result.messages:
        print(f"{PREFIX}: {message}", file=sys.stderr)


def sample(args, records, fixed, least_squares, out: pathlib.Path, fit_json):
    """NUTS warm-started from `least_squares`, its files written into `out`.

    **Returns:** (exit status: 0 converged, 1 not, 2 refused, 130 interrupted; the
    `BayesResult` or None)."""
    from identification.bayes import fit_bayes

    return _sampled(lambda: fit_bayes(
        records, free=least_squares.free, fixed=fixed, normal_load=args.normal_load, prior=args.prior,
        num_warmup=args.draws, num_samples=args.draws, num_chains=args.chains, seed=args.seed,
        least_squares=least_squares, progress_bar=not args.no_progress, on_block=_print_block),
        out, fit_json, lambda result: _write_posterior(out, result, _unit_of(args.units)))


def _sampled(run, out: pathlib.Path, fit_json, write):
    """`run()` (a sampler taking `on_block`) with `out` made first and its result written by
    `write(result)`; a Ctrl-C (`SamplingInterrupted`) writes the draws finished so far, as not
    converged. **Returns:** (exit status: 0 converged, 1 not, 2 refused, 130 interrupted; the
    `BayesResult` or None)."""
    from identification.bayes import SamplingInterrupted

    try:
        out.mkdir(parents=True, exist_ok=True)
        result = run()
    except (ValueError, OSError) as error:
        print(f"{PREFIX}: error: {error}", file=sys.stderr)
        return 2, None
    except SamplingInterrupted as stop:
        if stop.result is None:
            _write_json(out / "posterior.json", {
                "converged": False, "status": "interrupted in the warm-up: no draws",
                "least_squares": str(fit_json)})
        else:
            write(stop.result)
        why = stop.result.interrupted if stop.result else "interrupted in the warm-up"
        print(f"{PREFIX}: {why}; {out / 'posterior.json'} says so (not converged); the "
              f"least-squares fit is in {fit_json}.", file=sys.stderr)
        return 130, stop.result
    write(result)
    return (0 if result.converged else 1), result


def save_posterior(args, least_squares, records, result, save_fitted, path, sources) -> bool:
    """The bearing file `path` again, with the posterior's draws (thinned to
    --posterior-draws) beside the least-squares bearing; only for a converged run (else the
    file keeps the least-squares bearing, and the message says why). True when written."""
    if not result.converged:
        print(f"{PREFIX}: {path} holds the least-squares bearing only: a posterior whose chains "
              "did not converge is not added to it.", file=sys.stderr)
        return False
    limit = args.posterior_draws or DEFAULT_POSTERIOR_DRAWS
    try:
        posterior = result.bearing_posterior(limit)
    except ValueError as error:
        print(f"{PREFIX}: {path} holds the least-squares bearing only: {error}", file=sys.stderr)
        return False
    save_fitted(args, least_squares, records, posterior=posterior, path=path, sources=sources,
                bayes={"prior": result.prior, "converged": bool(result.converged),
                       "divergences": int(result.divergences), "chains": result.num_chains,
                       "draws_per_chain": result.num_samples})
    print(f"{PREFIX}: {path}: the bearing with {posterior.size} posterior draws (every "
          f"{posterior.thinning}-th of {posterior.draws_before_thinning}).", file=sys.stderr)
    return True


def run_bayes(args, records, fixed, least_squares, save_fitted) -> int:
    """`fit --bayes DIR` after the joint least-squares fit: 1 unless converged, 130 when
    interrupted (Ctrl-C), with the draws finished so far written as not converged."""
    print(f"{PREFIX}: NUTS, {args.chains} chains x ({args.draws} warm-up steps + "
          f"{args.draws} draws), each step a simulation of the records per leapfrog step: minutes "
          "to hours; the bar shows the time left (Ctrl-C stops, keeping the draws so far, "
          "reported as not converged).", file=sys.stderr)
    status, result = sample(args, records, fixed, least_squares, pathlib.Path(args.bayes),
                            args.json)
    if status == 0 and args.save_bearing is not None:
        if not save_posterior(args, least_squares, records, result, save_fitted,
                              args.save_bearing, args.records):
            return 1
    elif status in (1, 130) and args.save_bearing is not None:
        print(f"{PREFIX}: {args.save_bearing} holds the least-squares bearing only (no "
              "converged posterior).", file=sys.stderr)
    return status


def run_fit_each(args, free, fixed, records, save_fitted) -> int:
    """`fit --bayes DIR --each`: each record fitted alone into DIR/<record name>/; the summary
    to --json. Exit status: 0 when every record converged, 130 on Ctrl-C, else 2 when a record
    was refused as bad input and 1 when one did not converge."""
    from identification.bearing_fit import fit_bearing_test

    root, rows, worst = pathlib.Path(args.bayes), [], 0
    print(f"teflon-jax fit --each: {len(records)} record(s), each fitted alone (least squares, "
          f"then NUTS, {args.chains} chains x ({args.draws} + {args.draws})); the sampler is "
          "compiled once for records of one length.", file=sys.stderr)
    try:
        for i, (name, record) in enumerate(zip(args.records, records)):
            out = root / pathlib.Path(name).stem
            print(f"teflon-jax fit --each: record {i + 1} of {len(records)}: {name} -> {out}",
                  file=sys.stderr, flush=True)
            status, row = _fit_one(args, free, fixed, name, record, out, save_fitted,
                                   fit_bearing_test)
            rows.append(row)
            if status == 130:
                worst = 130
                break
            worst = max(worst, status)
    except KeyboardInterrupt:
        worst = 130
        rows.append({"record": str(args.records[len(rows)]), "status": "interrupted"})
    _write_json(args.json, {"each": rows, "folder": str(root)})
    failed = [r for r in rows if r["status"] != "converged"]
    print(f"teflon-jax fit --each: {len(rows) - len(failed)} of {len(records)} record(s) "
          "converged" + ("; " + "; ".join(f"{r['record']}: {r['status']}" for r in failed)
                         if failed else "") + f"; summary in {args.json}.", file=sys.stderr)
    return worst


def _fit_one(args, free, fixed, name, record, out, save_fitted, fit_bearing_test):
    """One record of --each: (exit status, its summary row)."""
    row = {"record": str(name), "folder": str(out)}
    try:
        fit = fit_bearing_test([record], free=free, fixed=fixed, normal_load=args.normal_load,
                               n_starts=args.starts, reduce=not args.full_model)
    except ValueError as error:
        print(f"teflon-jax fit --each: {name}: error: {error}", file=sys.stderr)
        return 2, {**row, "status": f"refused: {error}"}
    out.mkdir(parents=True, exist_ok=True)
    _write_json(out / "fit.json", fit.to_json_dict())
    row["least_squares"] = {"converged": bool(fit.converged), "nrmse": fit.nrmse,
                            "parameters": dict(fit.parameters)}
    if not fit.converged:
        print(f"teflon-jax fit --each: {name}: the least-squares fit did not converge "
              f"({fit.message}); no posterior.", file=sys.stderr)
        return 1, {**row, "status": "least squares not converged"}
    status, result = sample(args, [record], fixed, fit, out, out / "fit.json")
    if status == 0 and not save_posterior(args, fit, [record], result, save_fitted,
                                          out / "bearing.json", [name]):
        status = 1
    if status != 0:
        save_fitted(args, fit, [record], path=out / "bearing.json", sources=[name])
    words = {0: "converged", 1: "not converged", 2: "refused", 130: "interrupted"}
    return status, {**row, "status": words[status],
                    "bearing": str(out / "bearing.json")}


def _series_unit_of(family: str):
    """name -> (unit, SI value of one unit) of `--units` for a series pendulum's constants
    (`<surface>_<constant>`: the unit of the constant)."""
    unit_of = _unit_of(family)
    return lambda name: unit_of(name if name == "noise_level" else name.split("_", 1)[1])


def run_series_bayes(args, fit, records) -> int:
    """`fit --isolator double-fp|triple-fp --bayes DIR` after its least-squares fit: the
    posterior of its surfaces' Eq. 1 constants (`identification.bayes.fit_series_bayes`) in
    DIR; with --save-isolator, a converged run's draws in the isolator file. Exit status 0
    when converged, 1 when not, 130 when interrupted (Ctrl-C), with the draws finished so far
    written as not converged."""
    from identification.bayes import fit_series_bayes

    out = pathlib.Path(args.bayes)
    print(f"{PREFIX}: NUTS on the {fit.bearing.description[:-1]}'s surface friction (radii and "
          f"capacities held at the least-squares values), {args.chains} chains x ({args.draws} warm-up "
          f"steps + {args.draws} draws), each step a simulation of the series model along the record: "
          "minutes to hours (Ctrl-C stops, keeping the draws so far, reported as not converged).",
          file=sys.stderr)
    status, result = _sampled(lambda: fit_series_bayes(
        records[0], fit, normal_load=args.normal_load, num_warmup=args.draws, num_samples=args.draws,
        num_chains=args.chains, seed=args.seed, progress_bar=not args.no_progress, on_block=_print_block),
        out, args.json, lambda result: _write_posterior(out, result, _series_unit_of(args.units)))
    if status == 0 and args.save_isolator is not None:
        if not _save_isolator_posterior(args, fit, result):
            return 1
    elif status in (1, 130) and args.save_isolator is not None:
        print(f"{PREFIX}: {args.save_isolator} holds the least-squares isolator only (no converged "
              "posterior).", file=sys.stderr)
    return status


def _save_isolator_posterior(args, fit, result) -> bool:
    """--save-isolator again, with a converged run's draws (thinned to --posterior-draws)
    beside the least-squares constants; True when written."""
    from ..formats import write_isolator

    path = args.save_isolator
    if not result.converged:
        print(f"{PREFIX}: {path} holds the least-squares isolator only: a posterior whose chains did "
              "not converge is not added to it.", file=sys.stderr)
        return False
    try:
        posterior = result.isolator_posterior(args.posterior_draws or DEFAULT_POSTERIOR_DRAWS)
    except ValueError as error:
        print(f"{PREFIX}: {path} holds the least-squares isolator only: {error}", file=sys.stderr)
        return False
    write_isolator(path, fit.bearing, posterior=posterior)
    print(f"{PREFIX}: {path}: the isolator with {posterior.size} posterior draws (every "
          f"{posterior.thinning}-th of {posterior.draws_before_thinning}).", file=sys.stderr)
    return True
