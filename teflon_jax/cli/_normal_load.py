"""The isolators' normal load on the command line: the vertical ground component, a load
composed onto any structure and isolator (`run --record-z FILE`, `montecarlo --vertical-ratio R`),
N = W max(1 + a_v / g, 0); the uplift (N <= 0) it causes, reported per run or per motion; and
each bearing group's load on a slab, with the overturning of its plan's height."""

import numpy as np

from ..units import parse_quantity
from ._common import add_quantity

MAX_VERTICAL_RATIO = 2.0
"""The largest `--vertical-ratio` [-]: twice the horizontal peak, above the vertical-to-horizontal
ratios of recorded motions (Bozorgnia & Campbell 2004: 0.5 far from the source to above 1 near
it)."""

NORMAL_LOAD_NOTE = ("N_g = W_g (1 + a_v / g) + dN_g, dN_g of a rigid slab on vertical supports of "
                    "equal (or the plan's relative) stiffness under the moment h H of the horizontal "
                    "force H at the start of each step; while N_g <= 0 the group carries no shear "
                    "and the others take its share (where at least three groups off one line stay "
                    "down; else the lever rule's loads, a negative N_g the tension a bonded "
                    "support would need)")


def add_vertical_flag(parser) -> None:
    """`--record-z FILE`: the vertical component (up positive), read and scaled as the others."""
    parser.add_argument("--record-z", default=None, help="vertical component, up positive (PEER .AT2 "
                        "or a two-column file with --record-units; scaled by --scale, windowed by "
                        "--start/--duration): the isolators' normal load becomes W (1 + a_v / g), and "
                        "their friction follows the contact pressure (Table 1 read at the momentary "
                        "pressure, or a --bearing file's pressure dependence); at N <= 0 they carry no "
                        "shear and the run reports the uplift (default: none)")


def add_vertical_flags(parser) -> None:
    """`--vertical-ratio` and `--vertical-frequency-ratio` of `montecarlo`."""
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


def with_vertical(system, az, dt, radius=None, **law):
    """`system` (any structure `run` builds) with the vertical component `az` [m/s^2] on the
    records' grid of step `dt` [s] (unchanged for `None`); `radius` [m] of a single friction
    pendulum whose W / R scales with the normal load (None for the others, and for a slab's
    groups, which hold their W_g / R_g); `law`: how the friction follows the normal load
    (`pressure_law`, `systems.with_vertical_motion`)."""
    if az is None:
        return system
    from ..excitation import uniform_signal
    from ..systems import with_vertical_motion

    return with_vertical_motion(system, uniform_signal(az, dt), radius=radius, **law)


def pressure_law(args, isolator, plan=None) -> dict:
    """How the bearings' friction follows a vertical record's normal load, as the arguments of
    `systems.with_vertical_motion`: a `--bearing` file's pressure dependence
    (`pressure_exponent`), else Table 1's rows of each bearing's PTFE read at the momentary
    contact pressure (`friction_table`, `table_pressure`: --ptfe and --pressure, or each
    group's of the --plan; across the lay too with --anisotropic); {} for series pendulums,
    whose surfaces carry their own."""
    import jax
    import jax.numpy as jnp

    from ..tables import friction_table

    if isolator.pendulum is not None:
        return {}
    bearing = isolator.bearing  # of --bearing, as read with the isolator
    if bearing is not None:
        part = bearing.pressure_dependence
        return {} if part is None else {"pressure_exponent": part.exponent}
    groups = [{}] if plan is None else plan["groups"]
    kinds = [(g.get("ptfe") or args.ptfe).upper() for g in groups]
    pressures = [parse_quantity(g.get("pressure") or args.pressure, "pressure", where="--pressure") for g in groups]

    def tables(direction):
        rows = [friction_table(kind, direction, extrapolate=True) for kind in kinds]
        return rows[0] if plan is None else jax.tree_util.tree_map(lambda *a: jnp.stack(a), *rows)

    table = (tables("P"), tables("T")) if args.anisotropic else tables("P")
    return {"friction_table": table, "table_pressure": pressures[0] if plan is None else jnp.asarray(pressures)}


def pressure_note(law: dict, az) -> str | None:
    """The note of a run whose bearings read Table 1 at the momentary contact pressure s p
    under the vertical component `az` [m/s^2]: the pressures it reaches, and where they lie
    beyond the table's rows (its end segments extended); None otherwise."""
    if az is None or "friction_table" not in law:
        return None
    from ..systems import normal_load_factor
    from ..units import PSI

    s = np.asarray(normal_load_factor(np.asarray(az)))
    s = s[s > 0] if np.any(s > 0) else np.zeros(1)
    pressure = np.asarray(law["table_pressure"], float)
    table = law["friction_table"][0] if isinstance(law["friction_table"], tuple) else law["friction_table"]
    rows = np.asarray(table.pressures)
    low, high = s.min() * pressure.min(), s.max() * pressure.max()
    text = (f"the bearings' friction follows the contact pressure under the vertical component: Table 1 "
            f"read from {low / PSI:.0f} to {high / PSI:.0f} psi")
    if low < rows.min() or high > rows.max():
        text += f", beyond its rows ({rows.min() / PSI:.0f}-{rows.max() / PSI:.0f} psi) on their end segments extended"
    return text


def check_vertical_pressures(system, rows, dt) -> None:
    """`ValueError` before any run where a vertical component would take the contact pressure of
    `system`'s bearings (Table 1 read at the momentary pressure, `TablePressure`) to where Eq. 1
    cannot take their constants: `rows` [(what the user gave, a_v (n,) [m/s^2] at step `dt`
    [s])], each read at the structure's steps as the run reads it (`load_factors`) and checked
    at the least and largest load factor s > 0 there and at the table's rows between (the
    constants are linear in s between them); nothing for a system without the table."""
    import equinox as eqx
    import jax.numpy as jnp

    from ..excitation import uniform_signal
    from ..units import PSI

    table = getattr(system, "pressure_table", None)
    if table is None:
        return
    breaks = table.constant_breaks()
    for where, az in rows:
        record = eqx.tree_at(lambda s: s.vertical_acceleration, system, uniform_signal(az, dt))
        s = load_factors(record, (np.size(az) - 1) * dt)
        loaded = s[s > 0]
        if loaded.size == 0:
            continue
        low, high = loaded.min(), loaded.max()
        points = [high, low, *breaks[(breaks > low) & (breaks < high)]]
        for point in points:
            if not bool(table.valid_at(system.bearing, jnp.asarray(point))):
                pressure = point * float(np.max(np.asarray(table.pressure)))
                raise ValueError(
                    f"{where}: the vertical component takes the bearings' contact pressure to {pressure / PSI:.0f} psi "
                    f"(N / W = {point:.3g}), where Table 1's extended end segments give no Eq. 1 constants for them "
                    "(f_max > delta_f >= 0, rate_a >= 0, breakaway ratio >= 1); give the bearing's constants at "
                    "such pressures (--bearing, a file with a pressure dependence) or a lighter vertical record.")


def response_uplift(response) -> dict:
    """The JSON entries of the uplift of a run's response (its `uplift_time` [s] and
    `load_factor` history): whether N <= 0 at any step and for how long [s]; {} without a
    vertical component."""
    if response.uplift_time is None:
        return {}
    time = float(response.uplift_time)
    loads = np.asarray(response.load_factor)
    return {"uplift": {"occurred": time > 0, "time_s": time, "min_load_factor": float(loads.min()),
                       "max_load_factor": float(loads.max()),
                       "note": "N = W max(1 + a_v / g, 0); while N <= 0 the isolators carry no "
                               "shear (friction and pendulum force zero)"}}


def uplift_line(summary: dict) -> str | None:
    """The printed line of `response_uplift` (None without a vertical component)."""
    if not summary:
        return None
    u = summary["uplift"]
    if not u["occurred"]:
        return (f"uplift: none (N / W between {u['min_load_factor']:.3g} and "
                f"{u['max_load_factor']:.3g})")
    return f"uplift: N <= 0 during {u['time_s']:.4g} s (isolators carried no shear then)"


def load_factors(system, duration):
    """N / W (nt,) of a structure's vertical record at the ends of the whole steps the drivers
    run over `duration` [s] (`systems.step_load_factors`)."""
    from ..systems import step_count, step_load_factors

    return np.asarray(step_load_factors(system, step_count(system.time_step, duration)))


def uplift_of(times, rows=None) -> dict:
    """The uplifted motions of `rows` (default all) of a result's `uplift_time` (N,) [s]:
    {"n_uplifted", "uplifted_motions" (their indices in the result), "uplift_time_s"}."""
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


def group_normal_loads(system, response):
    """(N_g history (nt, G) [N], uplift time per group (G,) [s]): the state's loads with
    overturning, else W_g times the vertical record's factor (or W_g throughout)."""
    weights = np.asarray(system.bearing_load)
    if response.normal_load is not None:
        return np.asarray(response.normal_load), np.asarray(response.group_uplift_time)
    if response.load_factor is None:
        return np.broadcast_to(weights, (np.size(response.time), weights.size)), np.zeros(weights.size)
    loads = np.asarray(response.load_factor)[:, None] * weights
    return loads, np.full(weights.size, float(response.uplift_time))


def normal_load_summary(plan, system, response, units) -> tuple[dict, list]:
    """(JSON entry "normal_load", printed lines): each group's peak and least normal load [N]
    (negative: the tension a bonded support would need), its uplift time [s], its radius [m]
    (single pendulums) or its isolator file (series pendulums)."""
    loads, uplift = group_normal_loads(system, response)
    name, factor = units.force
    groups, lines = {}, []
    radii = plan.get("radii") or [None] * len(plan["groups"])
    files = plan.get("isolator_files")
    for j, (g, history, time, radius) in enumerate(zip(plan["groups"], loads.T, uplift, radii)):
        groups[g["name"]] = {"static_N": g["load"], "peak_N": float(history.max()),
                             "min_N": float(history.min()), "uplift_time_s": float(time),
                             "radius_m": radius} | ({} if files is None else {"isolator_file": files[j]})
        lines.append(f"normal load {g['name']}: peak {history.max() / factor:.4g} {name}, least "
                     f"{history.min() / factor:.4g} {name}, uplift {float(time):.4g} s")
    entry = {"height_of_centre_of_mass_m": plan["height_of_centre_of_mass"], "groups": groups,
             "note": NORMAL_LOAD_NOTE}
    return {"normal_load": entry}, lines


def suite_normal_load(plan, groups, pair) -> dict:
    """The "normal_load" entry of `normal_load_summary` (its group keys, without the note) of
    pair index `pair` of a suite's `SuiteResult.groups` ((P, G) peak and least N_g [N], uplift
    time [s]) on the slab `plan` (`slab_isolators`: each group's radius or isolator file)."""
    radii = plan.get("radii") or [None] * len(plan["groups"])
    files = plan.get("isolator_files")
    entry = {g["name"]: {"static_N": g["load"], "peak_N": float(groups["peak_N"][pair, j]),
                         "min_N": float(groups["min_N"][pair, j]),
                         "uplift_time_s": float(groups["uplift_time_s"][pair, j]), "radius_m": radius}
             | ({} if files is None else {"isolator_file": files[j]})
             for j, (g, radius) in enumerate(zip(plan["groups"], radii))}
    return {"normal_load": {"height_of_centre_of_mass_m": plan["height_of_centre_of_mass"], "groups": entry}}
