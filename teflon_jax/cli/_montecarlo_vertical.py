"""`teflon-jax montecarlo --vertical-ratio R`: every stochastic motion with a vertical
component (`VerticalGroundMotion`) on the isolators' normal load, and the uplift it causes
reported per motion and counted in the summary; at one level or several (`--pga L1,L2,...`:
the vertical peak R times each level's, the uplift per level), with `--limit`, `--storeys`,
`--pelicun-demands` and `--property-factors` run on the same structure and motions."""

from ._common import add_quantity

MAX_VERTICAL_RATIO = 2.0
"""The largest `--vertical-ratio` [-]: twice the horizontal peak, above the vertical-to-horizontal
ratios of recorded motions (Bozorgnia & Campbell 2004: 0.5 far from the source to above 1 near
it)."""


def add_vertical_flags(parser) -> None:
    """`--vertical-ratio` and `--vertical-frequency-ratio`."""
    add_quantity(parser, "--vertical-ratio", "dimensionless", None, "add a vertical component whose "
                 "expected peak is this ratio times the horizontal --pga (Newmark, Blume & Kapur 1973: "
                 "2/3; Bozorgnia & Campbell 2004: V/H of 0.5 far from the source to above 1 near it); the "
                 "isolators' normal load becomes W (1 + a_v / g), uplift (N <= 0) is reported per motion "
                 "(0: a vertical record of zeros, the horizontal-only peaks; at most 2) (default: none, "
                 "horizontal only)", minimum=0.0, strict=False, maximum=MAX_VERTICAL_RATIO,
                 why="recorded motions have a vertical peak of 0.5 times the horizontal far "
                 "from the source to above 1 near it")
    add_quantity(parser, "--vertical-frequency-ratio", "dimensionless", None, "with --vertical-ratio: "
                 "the vertical component's Kanai-Tajimi (and high-pass) frequency over the horizontal "
                 "one's; vertical motions are richer in short periods (default 2)", minimum=0.0)


def check_vertical_flags(args) -> None:
    """`ValueError` naming the flag: `--vertical-frequency-ratio` without `--vertical-ratio`."""
    if args.vertical_ratio is None and args.vertical_frequency_ratio is not None:
        raise ValueError("--vertical-frequency-ratio: shapes the vertical component; add --vertical-ratio.")


def vertical_model(args, model):
    """`model` with its vertical component (`VerticalGroundMotion`), or `model` without the flag."""
    if args.vertical_ratio is None:
        return model
    from ..excitation import VERTICAL_FREQUENCY_RATIO, VerticalGroundMotion

    ratio = args.vertical_frequency_ratio
    return VerticalGroundMotion(model, vertical_ratio=args.vertical_ratio,
                                frequency_ratio=VERTICAL_FREQUENCY_RATIO if ratio is None else ratio)


def vertical_structure(args, structure):
    """`structure` taking (horizontal, vertical) motions with the flag, else itself (flat
    sliders, single pendulum, triple or double pendulum; one or two horizontal components)."""
    if args.vertical_ratio is None:
        return structure
    from ..systems import with_vertical_component

    return with_vertical_component(structure)


def uplift_of(times, rows=None) -> dict:
    """The uplifted motions of `rows` (default all) of a result's `uplift_time` (N,) [s]:
    {"n_uplifted", "uplifted_motions" (their indices in the result), "uplift_time_s"}."""
    import numpy as np

    times = np.asarray(times).reshape(-1)
    rows = np.arange(times.size) if rows is None else np.asarray(rows)
    uplifted = rows[times[rows] > 0]
    return {"n_uplifted": int(uplifted.size), "uplifted_motions": uplifted.tolist(),
            "uplift_time_s": times[uplifted].tolist()}


def uplift_payload(result, model) -> dict:
    """The summary JSON's "vertical" entry: the component's ratios and the uplifted motions
    (index and time with N <= 0), which stay in the statistics. With design variants (the
    bounding cases) the first one's: the uplift is the vertical record's, the same in each."""
    if result.uplift_time is None:
        return {}
    times = result.uplift_time if result.uplift_time.ndim == 1 else result.uplift_time[0]
    return {"vertical": {
        "vertical_ratio": float(model.vertical_ratio), "frequency_ratio": float(model.frequency_ratio),
        "normal_load": "N = W max(1 + a_v / g, 0) on friction and pendulum force; no shear while N <= 0",
        **uplift_of(times),
        "statistics": "uplifted motions are kept: their peaks include the uplift, which the model "
                      "represents (rigid superstructure, no vertical impact)"}}


def uplift_message(payload: dict) -> str | None:
    """The printed line of the summary's "vertical" entry (`uplift_payload`; None without one)."""
    v = payload.get("vertical")
    if v is None:
        return None
    shown = ", ".join(str(i) for i in v["uplifted_motions"][:20]) + (" ..." if v["n_uplifted"] > 20 else "")
    return (f"  uplift (N <= 0): {v['n_uplifted']} motion(s)" + (f" ({shown}), kept in the statistics"
                                                                  if v["n_uplifted"] else ""))
