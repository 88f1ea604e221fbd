"""A run's response, whatever its structure and isolator. The library steps flat sliders and
single pendulums (rigid mass, building, slab) as a `BidirectionalStructure`, and series
pendulums as a `StructureOnSliders` on them (one or two components) or a slab on them (a
`BidirectionalStructure` whose `bearing` is a `SeriesPendulum`); one table keyed by that type
says how to simulate the system, cut it at the first step that did not balance (`_run_stop`)
and read its uplift (`_normal_load`). The peaks and histories are one set of reducers over the
response, whatever the system (`_run_peaks`)."""

import typing

import numpy as np

from ._normal_load import (
    load_factors,
    normal_load_summary,
    response_uplift,
    series_uplift,
    uplift_line,
)
from ._run_peaks import run_peaks, slider_peaks, surface_temperature_summary
from ._run_stop import (
    bidirectional_stop,
    law_stop,
    series_slab_stop,
    series_stop,
    unbalanced_message,
)


class Run(typing.NamedTuple):
    """A simulated run: its `response` (cut to the steps that balanced), its `end` (time (nt,)
    [s], kept steps, tipped (nt,), unconverged (nt,): `stop_entries`), `problem` (why it
    stopped, '' when complete), the `duration` [s] it kept and `beyond_law_s`, the time [s] of
    the first sample beyond Table 1's pressure law where the run stopped there (`law_stop`)."""

    response: object
    end: tuple
    problem: str
    duration: float
    beyond_law_s: float | None = None


class _Engine(typing.NamedTuple):
    """What a run needs of one system type (module docstring)."""

    simulate: typing.Callable  # (system, duration [s], plan) -> Run
    uplift: typing.Callable  # (system, response, duration [s]) -> (JSON entries, N / W history or None)
    extras: typing.Callable = lambda plan, system, response, histories: ({}, [])  # more JSON entries, lines


def _bidirectional(system, duration, plan) -> Run:
    from ..systems import simulate_history

    response = simulate_history(system, duration, throw=False)
    if bool(response.succeeded):
        return Run(response, (response.time, np.size(response.time), (), ()), "", duration)
    return Run(*bidirectional_stop(system, response), duration)


def _series(system, duration, plan) -> Run:
    from ..systems import simulate_history

    response = simulate_history(system, duration, throw=False)
    return _series_run(response, response.time, response.converged, duration)


def _series_run(response, time, converged, duration) -> Run:
    response, end, problem = series_stop(response, time, converged)
    return Run(response, end, problem, float(end[0][end[1] - 1]) if problem else duration)


def _slab_series(system, duration, plan) -> Run:
    import jax

    from ..systems import response_layout, simulate_history

    response = jax.jit(simulate_history, static_argnums=1, static_argnames="throw")(system, duration, throw=False)
    problem = unbalanced_message(response, plan["height_of_centre_of_mass"], building=response_layout(system).building)
    end, response = series_slab_stop(system, response)  # the steps before the first unbalanced one
    return Run(response, end, problem, float(end[0][end[1] - 1]) if problem else duration)


def _response_uplift(system, response, duration):
    entries = response_uplift(response)
    return entries, np.asarray(response.load_factor) if entries else None


def _series_uplift(system, duration):
    entries = series_uplift(system, duration)
    return entries, load_factors(system, duration) if entries else None


def _slab_series_extras(plan, system, response, histories):
    """The sliders' peaks of every group and the heated surfaces' temperature rise."""
    rises = surface_temperature_summary(plan, system, response, histories)
    lines = [f"surface temperature rise {name}: " + ", ".join(f"{e} {v:.4g} K" for e, v in row.items())
             for name, row in (rises or {}).items()]
    return {"slider_disp_m": slider_peaks(plan, system, response), "surface_temperature_rise_K": rises}, lines


def _engines() -> dict:
    from ..bearing import SeriesPendulum
    from ..systems import BidirectionalStructure, StructureOnSliders

    return {
        BidirectionalStructure: _Engine(_bidirectional, _response_uplift),
        StructureOnSliders: _Engine(_series, lambda s, r, d: _series_uplift(s, d)),
        SeriesPendulum: _Engine(_slab_series, lambda s, r, d: _series_uplift(s, d), _slab_series_extras),
    }


def _engine(system) -> _Engine:
    from ..bearing import SeriesPendulum
    from ..systems import BidirectionalStructure

    slab = isinstance(system, BidirectionalStructure) and isinstance(system.bearing, SeriesPendulum)
    return _engines()[SeriesPendulum if slab else type(system)]


def simulate_run(system, duration: float, plan=None) -> Run:
    """The `Run` of `system` over `duration` [s] from rest (`plan`: the slab's, or None). A
    bearing whose friction follows Table 1 at the momentary pressure runs on past the table's
    reach (`systems.flag_pressure_law`), and the run is cut before the first sample beyond it,
    naming when and where (`law_stop`)."""
    from ..systems import flag_pressure_law

    run = _engine(system).simulate(flag_pressure_law(system), duration, plan)
    return law_stop(system, run, None if plan is None else [g["name"] for g in plan["groups"]])


def reduce_run(structure: str, system, run: Run, plan, units):
    """(peak, histories, the JSON entries after the peak, printed lines) of `run`: the peaks and
    histories in SI, the uplift of a vertical component (and its N / W history), each slab
    group's normal load (`plan`) and what the system adds (a slab on series pendulums: its
    sliders and heated surfaces)."""
    engine = _engine(system)
    peak, histories = run_peaks(system, run.response, plan)
    entries, load_factor = engine.uplift(system, run.response, run.duration)
    if load_factor is not None:
        histories["load_factor"] = load_factor
    lines = [uplift_line(entries)] * bool(entries)
    if plan is not None:  # each group's normal load (overturning, vertical record)
        normal, normal_lines = normal_load_summary(plan, system, run.response, units)
        entries, lines = {**entries, **normal}, lines + normal_lines
    more, more_lines = engine.extras(plan, system, run.response, histories)
    return peak, histories, {**entries, **more}, lines + more_lines
