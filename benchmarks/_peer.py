"""The OpenSees peer as the benchmarks call it: the paper's UF/1000 psi bearings, at the steps each benchmark gives."""

import functools
import importlib.util
import os
import pathlib

import numpy as np

from teflon_jax.structures import superstructure_matrices
from teflon_jax.tables import interface_parameters, load_table2
from teflon_jax.units import INCH, PSI, STANDARD_GRAVITY


@functools.cache
def load_peer():
    """`benchmarks/_opensees_models.py` with OpenSees imported; ImportError if it cannot be."""
    spec = importlib.util.spec_from_file_location(
        "_opensees_models", pathlib.Path(__file__).with_name("_opensees_models.py"))
    peer = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(peer)
    peer.import_opensees()
    return peer


def _bearing(record_time_step, time_step):
    friction, _ = interface_parameters("UF", 1000 * PSI, "P")
    return dict(f_max=float(friction.f_max), delta_f=float(friction.delta_f),
                rate_a=float(friction.rate_a), yield_disp=0.005 * INCH,
                n_sub=int(round(record_time_step / time_step)))


def rigid_mass(peer, acc, record_time_step, *, time_step=0.005, period=None, damping_ratio=0.0,
               weight=1.0e6):
    """Rigid mass on UF/1000 psi sliders (optionally a spring of `period` and damping)."""
    mass = weight / STANDARD_GRAVITY
    k = 0.0 if period is None else mass * (2 * np.pi / period) ** 2
    return peer.rigid_mass_on_slider(np.asarray(acc), record_time_step, weight=weight,
                                     spring_stiffness=k, damping_ratio=damping_ratio,
                                     **_bearing(record_time_step, time_step))


@functools.cache
def _table2_building():
    """Table 2 and its superstructure matrices (masses, stiffness, damping), read once."""
    data = load_table2()
    masses, stiffness, damping, _ = superstructure_matrices(data)
    return data, masses, stiffness, damping


def building(peer, acc, record_time_step, *, period, time_step=0.005, slider=True, damping_ratio=0.05):
    """The Table 2 building on UF/1000 psi sliders and rubber springs of period `period`
    (damping ratio `damping_ratio` of the rigid-body mode); `slider=False`: the linear
    isolation system of Fig. 11 (springs only; the paper gives it 10 % damping)."""
    data, masses, stiffness, damping = _table2_building()
    total_mass = data.total_weight / STANDARD_GRAVITY
    return peer.building_on_sliders(
        np.asarray(acc), record_time_step, floor_masses=masses, stiffness=stiffness,
        damping=damping, base_mass=data.base_weight / STANDARD_GRAVITY,
        rubber_stiffness=total_mass * (2 * np.pi / period) ** 2, rubber_damping_ratio=damping_ratio,
        slider=slider, **_bearing(record_time_step, time_step))


def peaks_and_wall(args):
    """One OpenSees analysis of `(kind, acc, record_time_step, time_step)` with kind "rigid"
    (spring of 2 s, 5 % damping) or "building" (T_b = 2 s), as B3 runs them (also in worker
    processes): (wall s of the analysis, peak |base displacement| m, peak |base shear| / W_s,
    failed steps, process id)."""
    kind, acc, record_time_step, time_step = args
    peer = load_peer()
    if kind == "rigid":
        r = rigid_mass(peer, acc, record_time_step, time_step=time_step, period=2.0, damping_ratio=0.05)
        disp, shear = r["displacement"], r["total_acceleration"] / STANDARD_GRAVITY
    else:
        r = building(peer, acc, record_time_step, period=2.0, time_step=time_step)
        floor_masses = _table2_building()[1]
        disp = r["base_displacement"]
        shear = r["base_shear"] / (np.sum(floor_masses) * STANDARD_GRAVITY)
    return (r["wall_s"], float(np.max(np.abs(disp))), float(np.max(np.abs(shear))), int(r["n_failed"]),
            os.getpid())


def ready(_):
    """Pool warm-up: import and load OpenSees in a worker before timing starts (double
    precision for the Table 1 lookups, as in the parent)."""
    import jax

    jax.config.update("jax_enable_x64", True)
    load_peer()
    return True
