"""A run's response, whatever its structure and isolator: every structure is stepped by its
engine (`systems.simulate_history`), each step's balance judged, and the run is cut at the first
step that did not balance (`_run_stop`: the slab tipped, or the isolators' balance did not
converge) or whose loads passed Table 1's pressure law. The peaks and histories are one set of
reducers over the response, whatever the system (`_run_peaks`); the uplift of a vertical
component is read from the response (`_normal_load`), a slab on series pendulums adds its
sliders, and every heated isolator its surfaces' temperature rise."""

import typing

import numpy as np

from ._normal_load import normal_load_summary, response_uplift, uplift_line
from ._run_peaks import (
    run_peaks,
    slider_peaks,
    surface_temperature_summary,
    temperature_lines,
)
from ._run_stop import balance_stop, law_stop


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


def _stepped(system, duration, plan) -> Run:
    """Every step of `system` (`simulate_history`), cut before the first that did not balance."""
    import jax

    from ..systems import simulate_history

    response = jax.jit(simulate_history, static_argnums=1, static_argnames="throw")(system, duration, throw=False)
    response, end, problem = balance_stop(system, response, plan)
    return Run(response, end, problem, float(end[0][end[1] - 1]) if problem else duration)


def _on_series_groups(system) -> bool:
    from ..bearing import SeriesPendulum
    from ..systems import StructureOnSliders

    return isinstance(system, StructureOnSliders) and system.planar and isinstance(system.bearing, SeriesPendulum)


def simulate_run(system, duration: float, plan=None) -> Run:
    """The `Run` of `system` over `duration` [s] from rest (`plan`: the slab's, or None). A
    bearing whose friction follows Table 1 at the momentary pressure runs on past the table's
    reach (`systems.flag_pressure_law`), and the run is cut before the first sample beyond it,
    naming when and where (`law_stop`)."""
    from ..systems import flag_pressure_law

    run = _stepped(flag_pressure_law(system), duration, plan)
    return law_stop(system, run, None if plan is None else [g["name"] for g in plan["groups"]])


def reduce_run(structure: str, system, run: Run, plan, units):
    """(peak, histories, the JSON entries after the peak, printed lines) of `run`: the peaks and
    histories in SI, the uplift of a vertical component (and its N / W history), each slab
    group's normal load (`plan`), a slab's series pendulums' sliders and every heated surface's
    temperature rise."""
    peak, histories = run_peaks(system, run.response, plan)
    entries = response_uplift(run.response)  # over the steps kept
    if entries:
        histories["load_factor"] = np.asarray(run.response.load_factor)
    lines = [uplift_line(entries)] * bool(entries)
    if plan is not None:  # each group's normal load (overturning, vertical record)
        normal, normal_lines = normal_load_summary(plan, system, run.response, units)
        entries, lines = {**entries, **normal}, lines + normal_lines
    if _on_series_groups(system):
        entries = {**entries, "slider_disp_m": slider_peaks(plan, system, run.response)}
    rises = surface_temperature_summary(plan, system, run.response, histories)
    if rises is not None:
        entries, lines = {**entries, "surface_temperature_rise_K": rises}, lines + temperature_lines(plan, rises)
    return peak, histories, entries, lines
