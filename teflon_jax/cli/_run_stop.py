"""A `run` that stops before the end of its record: a step that does not balance (the slab
tips, or the bearings' or sliders' balance does not converge) ends what can be trusted. The
outputs then hold the steps before that step, and the JSON says so (`stop_entries`); the
command still exits 1."""

import dataclasses
import math

import numpy as np

PARTIAL_NOTE = ("the run stopped at stopped_at_s, the first step that did not balance (the slab tipped or "
                "the balance did not converge) or whose loads took the bearings beyond Table 1's pressure "
                "law (beyond_pressure_law_s): the entries named in partial_fields and the histories "
                "cover the steps from 0 s to last_kept_s only; tipped_steps and unconverged_steps count "
                "such steps over the whole record, every step of which is solved)")
WRITTEN = ('the outputs asked for hold the response before t = {:.4g} s only ("complete": false in the '
           "JSON)")


def kept_steps(balanced) -> int:
    """Saved steps before the first that did not balance (`balanced` (nt,), the first entry the
    state at rest); nt when every step balanced."""
    balanced = np.asarray(balanced, bool)
    return balanced.size if balanced.all() else max(int(np.argmin(balanced)), 1)


def cut(tree, size: int, kept: int):
    """`tree` (a response or a tuple of histories) with every array whose first axis is the
    time's (length `size`) cut to its first `kept` entries; other leaves unchanged."""
    import jax

    if kept == size:
        return tree
    return jax.tree_util.tree_map(lambda a: a[:kept] if np.ndim(a) >= 1 and np.shape(a)[0] == size else a, tree)


def stop_entries(time, kept: int, tipped, unconverged, fields, beyond_law_s=None) -> dict:
    """The JSON entries of a run's end: {"complete": True} when it kept all of `time` (nt,)
    [s]; else "complete": false, "stopped_at_s" (the first step that did not balance, or
    whose loads passed Table 1's pressure law, `beyond_law_s` [s]: "beyond_pressure_law_s"),
    "last_kept_s", the counts and first times [s] (None: none) of the `tipped` and
    `unconverged` (nt,) steps, and "partial_fields": the `fields` (JSON keys) that cover
    only the kept steps."""
    time = np.asarray(time)
    if kept == time.size:
        return {"complete": True}
    tipped, unconverged = np.asarray(tipped, bool), np.asarray(unconverged, bool)

    def first(flags):
        return float(time[flags][0]) if flags.any() else None

    return {"complete": False, "stopped_at_s": float(time[kept]), "last_kept_s": float(time[kept - 1]),
            "tipped_steps": int(tipped.sum()), "first_tipped_s": first(tipped),
            "unconverged_steps": int(unconverged.sum()), "first_unconverged_s": first(unconverged),
            "beyond_pressure_law_s": beyond_law_s, "partial_fields": list(fields), "partial_note": PARTIAL_NOTE}


def cut_response(system, response, kept: int):
    """`response` (saved at every step) cut to its first `kept` samples, its uplift times
    counting those steps only."""
    time = np.asarray(response.time)
    short = cut(response, time.size, kept)
    dt = float(system.time_step)
    changes = {}
    if short.load_factor is not None:
        changes["uplift_time"] = np.sum(np.asarray(short.load_factor)[1:] <= 0) * dt
    if short.normal_load is not None:
        changes["group_uplift_time"] = np.sum(np.asarray(short.normal_load)[1:] <= 0, axis=0) * dt
    return dataclasses.replace(short, **changes)


def law_stop(system, run, names=None):
    """`run` (`_run_response.Run`, of `system` with its Table 1 law flagged, `flag_pressure_law`)
    cut before the first sample whose loads its law gives no Eq. 1 constants at
    (`systems.pressure_law_valid`), with the time, the group (`names`: the plan's) and the
    contact pressure named; `run` itself where every sample is within the law."""
    from ..systems import LAW_REACH, pressure_law_valid
    from ..units import PSI

    valid = np.asarray(pressure_law_valid(system, run.response))
    if valid.all():
        return run
    first = int(np.argmin(valid))
    kept = max(first, 1)
    time, _, tipped, unconverged = run.end
    time = np.asarray(time)
    tipped, unconverged = (np.asarray(flags, bool).copy() for flags in (tipped, unconverged))
    tipped[kept:], unconverged[kept:] = False, False
    table, response = system.pressure_table, run.response
    overturning = response.normal_load is not None and getattr(system, "overturning", None) is not None
    if overturning:
        loads = np.asarray(response.normal_load[first]) / np.asarray(system.bearing_load)
        groups_valid = np.broadcast_to(np.asarray(table.groups_valid_at(system.bearing, loads)), loads.shape)
        group = int(np.argmin(groups_valid))  # the first group the law gives no constants at
        where = f"bearing group {names[group] if names else group}'s"
        load, pressure = loads[group], np.broadcast_to(np.asarray(table.pressure), loads.shape)[group]
    else:
        where, load = "the isolators'", float(np.asarray(response.load_factor)[first])
        pressure = float(np.max(np.asarray(table.pressure)))
    message = (f"at t = {time[first]:.4g} s {where} normal load reached {load:.4g} times its share of the weight, "
               f"a contact pressure of {load * pressure / PSI:.0f} psi, {LAW_REACH}, under "
               f"the vertical record{' and the overturning moment' if overturning else ''}; give the bearings' constants at such pressures "
               "(a bearing file with a pressure dependence) or a weaker record (on a slab, a lower "
               "height_of_centre_of_mass); "
               + WRITTEN.format(time[kept]) + ".")
    end = (time, kept, tipped, unconverged)
    return type(run)(cut_response(system, response, kept), end, message, float(time[kept - 1]),
                     beyond_law_s=float(time[first]))


def non_finite(value, where="") -> list:
    """The JSON paths of the numbers in `value` (nested dicts and lists) that are not finite."""
    if isinstance(value, dict):
        return [p for k, v in value.items() for p in non_finite(v, f"{where}.{k}" if where else str(k))]
    if isinstance(value, (list, tuple)):
        return [p for i, v in enumerate(value) for p in non_finite(v, f"{where}[{i}]")]
    if isinstance(value, float) and not math.isfinite(value):
        return [where]
    return []


def balance_stop(system, response, plan=None):
    """(response cut to the steps before the first that did not balance (`kept_steps`), its
    uplift times counting those steps only; its end (time (nt,) [s], kept, tipped (nt,),
    unconverged (nt,)) for `stop_entries`; why it cannot be trusted past there, '' when every
    step balanced) of a run's `StructureResponse` (every step saved, each with its
    `converged` and, on bearing groups with overturning loads, `tipped`; `plan`: the slab's)."""
    time, converged = np.asarray(response.time), np.asarray(response.converged)
    tipped = np.zeros(time.size, bool) if response.tipped is None else np.asarray(response.tipped)
    kept = kept_steps(converged)
    end = (time, kept, tipped, ~converged & ~tipped)
    if kept == time.size:
        return response, end, ""
    return cut_response(system, response, kept), end, _unbalanced_message(system, response, tipped, plan)


TIPPING = "what its weight holds back about the leaning groups (they take no tension)"
"""What the overturning moment of a slab (or a building's base) on a plan's groups exceeds when
it tips: the words of every message that names a tipped run."""

TIPPING_REMEDY = "spread the groups, lower height_of_centre_of_mass in the plan"
"""What mends a tipped slab (a smaller time step does not)."""

BUILDING_TIPS = ("the overturning moment of the inertia forces of its base and floors at their heights exceeds "
                 f"{TIPPING}, which a rigid base slab without rocking cannot balance; spread the groups or give a "
                 "weaker record")
"""Why the building on a plan tips: its levels stand at Table 2's heights, so there is no plan
height to lower."""


def _unbalanced_message(system, response, tipped, plan) -> str:
    """Why the run cannot be trusted: the steps on which the slab tipped (the building on a
    plan: its levels set the moment) and those whose balance did not converge, each with its
    count and first time [s]."""
    from ..systems import response_layout

    time, converged = np.asarray(response.time), np.asarray(response.converged)
    newton = ~converged & ~tipped
    parts = []
    if tipped.any() and response_layout(system).building:
        parts.append(f"the building tips on {int(tipped.sum())} steps (first at t = {time[tipped][0]:.4g} s): "
                     + BUILDING_TIPS)
    elif tipped.any():
        parts.append(f"the slab tips on {int(tipped.sum())} steps (first at t = {time[tipped][0]:.4g} s): "
                     f"the overturning moment of its horizontal force at the centre of mass "
                     f"{plan['height_of_centre_of_mass']:g} m above the sliding surface exceeds {TIPPING}, "
                     f"which a rigid slab without rocking cannot balance; {TIPPING_REMEDY} or give a weaker record")
    if newton.any():
        parts.append(f"the isolators' balance did not converge on {int(newton.sum())} steps (first at "
                     f"t = {time[newton][0]:.4g} s); try a smaller --time-step")
    return "; ".join(parts) + f"; {WRITTEN.format(time[~converged][0])}."


def failed_pairs(result) -> str:
    """Which of a suite's pairs cannot be trusted and why ('' when all converged): those beyond
    Table 1's pressure law (`result.beyond_pressure_law`), those whose first unbalanced step
    tipped the slab (`result.tipped`) and those whose balance missed its tolerance, each named,
    with what to do (`result`: a `studies.SuiteResult`)."""
    from ..systems import LAW_REACH

    names, count = result.names, len(result.names)
    beyond, tipped = (np.zeros(count, bool) if flags is None else np.asarray(flags, bool)
                      for flags in (result.beyond_pressure_law, result.tipped))
    unbalanced = ~np.asarray(result.converged, bool) & ~beyond
    parts = []
    law = [n for n, b in zip(names, beyond) if b]
    if law:
        parts.append(f"{len(law)} of {count} pairs took a bearing group's contact pressure {LAW_REACH}, under "
                     f"the vertical component and the groups' overturning loads ({', '.join(law)}): run such a pair "
                     "alone to "
                     "see where and when, and give the bearings' constants at such pressures (a bearing file with "
                     "a pressure dependence) or a lower height_of_centre_of_mass")
    tips = [n for n, f in zip(names, unbalanced & tipped) if f]
    if tips:
        parts.append(f"{len(tips)} of {count} pairs tipped the slab (or the building's base), its overturning moment "
                     f"beyond {TIPPING} ({', '.join(tips)}): {TIPPING_REMEDY} or run such a pair alone to see when; "
                     "a smaller --time-step does not mend it")
    newton = [n for n, f in zip(names, unbalanced & ~tipped) if f]
    if newton:
        parts.append(f"{len(newton)} of {count} pairs could not be balanced in every step "
                     f"({', '.join(newton)}): run such a pair alone to see when, or try a smaller --time-step")
    return "; ".join(parts)


def pair_flags(result, i: int) -> dict:
    """A suite pair's JSON flags beside "converged" (`studies.RUN_FLAGS`: `beyond_pressure_law`,
    `tipped`) where the `SuiteResult` keeps them."""
    from ..studies import RUN_FLAGS

    return {name: bool(getattr(result, name)[i]) for name in RUN_FLAGS if getattr(result, name) is not None}
