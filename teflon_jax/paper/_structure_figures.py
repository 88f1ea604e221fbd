"""Figs. 7-11: the rigid mass and the six-storey building under El Centro and SCT."""

import jax.numpy as jnp
import numpy as np

from ..bearing import coulomb_friction, paper_bearing
from ..excitation import Signal, fourier_amplitude
from ..structures import signal_from_motion
from ..studies import building_sweep
from ..systems import rigid_mass, simulate_history
from ..tables import friction_table
from ..units import INCH, PSI, STANDARD_GRAVITY
from . import _figures as figures
from ._constants import (
    FIG7_DURATION,
    FIG9_SMOOTHING,
    FIG10_DURATION,
    FIG10_EARLY,
    FIG10_OMEGA,
    FIG10_PEAK,
    FIG11_ELCENTRO_DURATION,
    HIGH_FREQUENCY,
    STRUCTURE_TIME_STEP,
    _columns,
    _write_csv,
)


def _fig7_9(out, results, record):
    """Figs. 7-9: rigid mass on UF/1000 psi bearings under El Centro, full model vs Coulomb."""
    motion = record["motion"]
    signal = signal_from_motion(motion)
    friction, _ = friction_table("UF", "P").at(1000 * PSI)
    f_max, f_min = float(friction.f_max), float(friction.f_min)
    models = {
        "exact": (paper_bearing(friction), "hysteretic"),
        "coulomb_min": (paper_bearing(coulomb_friction(f_min)), "coulomb"),
        "coulomb_avg": (paper_bearing(coulomb_friction(0.5 * (f_max + f_min))), "coulomb"),
        "coulomb_max": (paper_bearing(coulomb_friction(f_max)), "coulomb"),
    }
    pga, pgd = record["pga_g"] * STANDARD_GRAVITY, record["pgd_in"] * INCH
    histories, peaks, accel_peaks, high = {}, {}, {}, {}
    spectra = []
    for name, (bearing, model) in models.items():
        system = rigid_mass(weight=1.0e6, bearing=bearing, ground_acceleration=signal,
                            time_step=STRUCTURE_TIME_STEP, friction_model=model)
        r = simulate_history(system, FIG7_DURATION)
        u = np.asarray(r.displacement[:, 0])
        a = np.asarray(r.total_acceleration[:, 0])
        histories[name] = (u, a)
        peaks[name] = float(np.max(np.abs(u))) / INCH
        accel_peaks[name] = float(np.max(np.abs(a))) / pga
        frequency, amplitude = fourier_amplitude(a, STRUCTURE_TIME_STEP)
        energy = amplitude**2
        high[name] = float(energy[frequency > HIGH_FREQUENCY].sum() / energy.sum())
        spectra.append((name, frequency, amplitude / INCH))
    time = np.asarray(r.time)
    words = {
        "exact": f"full model (Eq. 1: f_max = {f_max:.3f}, f_min = {f_min:.3f})",
        "coulomb_min": f"Coulomb, mu = {f_min:.3f} (minimum)",
        "coulomb_avg": f"Coulomb, mu = {0.5 * (f_max + f_min):.3f} (average)",
        "coulomb_max": f"Coulomb, mu = {f_max:.3f} (maximum)",
    }
    stamp = (f"Record: {motion.name}, PGA {record['pga_g']:.3f} g, PGD {record['pgd_in']:.2f} in; rigid mass on "
             f"UF PTFE bearings at 1000 psi, parallel to lay (Table 1), Y = 0.005 in, no breakaway; "
             f"RiccatiNewmark, step {STRUCTURE_TIME_STEP:g} s.")
    _columns(out / "fig7_8_histories.csv", {"time_s": time, "ground_acc_g": np.asarray(r.ground[:, 0]) / STANDARD_GRAVITY,
              **{f"{n}_disp_over_pgd": h[0] / pgd for n, h in histories.items()},
              **{f"{n}_acc_over_pga": h[1] / pga for n, h in histories.items()}})
    figures.histories(out / "fig7_displacement.png", time,
                      [(words[n], h[0] / pgd) for n, h in histories.items()],
                      title="Fig. 7: sliding displacement of a rigid mass on UF/1000 psi bearings",
                      ylabel="sliding displacement / PGD [-]", stamp=stamp)
    figures.histories(out / "fig8_acceleration.png", time,
                      [(words[n], h[1] / pga) for n, h in histories.items()
                       if n in ("exact", "coulomb_min", "coulomb_max")],
                      title="Fig. 8: total acceleration of the rigid mass",
                      ylabel="total acceleration / PGA [-]", stamp=stamp)
    figures.fourier(out / "fig9_fourier.png",
                    [(words[n], f, figures.smooth(a * INCH / pga, FIG9_SMOOTHING))
                     for n, f, a in spectra if n in ("exact", "coulomb_max")],
                    title=f"Fig. 9: Fourier amplitude of the total acceleration (first {FIG7_DURATION:g} s), "
                    f"divided by the PGA, running mean over {FIG9_SMOOTHING} frequency samples",
                    stamp=stamp)
    frequency = spectra[0][1]
    _columns(out / "fig9_fourier.csv", {"frequency_hz": frequency, **{f"{n}_in_s": s for n, _, s in spectra}})
    results["fig7"] = {
        "peak_disp_in": peaks,
        "peak_acc_over_pga": accel_peaks,
        "high_frequency_energy_fraction": high,
        "high_frequency_above_hz": HIGH_FREQUENCY,
        "duration_s": FIG7_DURATION,
        "f_max": f_max,
        "f_min": f_min,
    }


def _fig10(out, results):
    """Fig. 10: breakaway under a sinusoidal base acceleration (0.25 g, 3.14 rad/s)."""
    dt = 1e-3
    times = np.arange(0.0, FIG10_DURATION + dt / 2, dt)
    pga = FIG10_PEAK * STANDARD_GRAVITY
    signal = Signal(jnp.asarray(times), jnp.asarray(pga * np.sin(FIG10_OMEGA * times)))
    cases = {
        "UF 1000 psi": (friction_table("UF", "P").at(1000 * PSI)[0], 1),
        "UF 3000 psi": (friction_table("UF", "P").at(3000 * PSI)[0], 1),
        "25GF 6500 psi": (friction_table("25GF", "P").at(6500 * PSI)[0], 1),
        "R-FBI (24 UF interfaces, 1000 psi)": (friction_table("UF", "P").at(1000 * PSI)[0], 24),
    }
    entries, panels, columns = [], [], {"time_s": None}
    for case, (friction, n) in cases.items():
        series, base = [], None
        for b in (None, 2.0, 4.0, 6.0):
            bearing = paper_bearing(friction, breakaway_ratio=b, n_interfaces=n)
            system = rigid_mass(weight=1.0e6, bearing=bearing, ground_acceleration=signal, time_step=dt)
            r = simulate_history(system, FIG10_DURATION)
            t = np.asarray(r.time)
            a = np.asarray(r.total_acceleration[:, 0]) / pga
            early = t <= FIG10_EARLY
            peak = float(np.max(np.abs(a[early])))
            entry = {"case": case, "b": b, "peak_acc_over_pga": peak,
                     "f_max_over_f_min": float(friction.f_max / friction.f_min)}
            if b is None:
                mu = np.abs(np.asarray(r.friction_force)) / 1.0e6
                k = int(np.argmax(mu[early]))
                base = peak
                experienced = float(mu[k])
                entry.update({"max_sliding_friction": experienced, "time_of_max_s": float(t[k]),
                              "velocity_at_max_in_s": float(abs(r.velocity[k, 0]) / INCH),
                              "interface_velocity_at_max_in_s": float(abs(r.velocity[k, 0]) / INCH / n),
                              "experienced_ratio": experienced / float(friction.f_min)})
                ratio = experienced / float(friction.f_min)
            else:
                entry["experienced_ratio"] = ratio
                entry["raises_peak"] = bool(peak > 1.02 * base)
                entry["eq18_predicts_raise"] = bool(b > ratio)
            entries.append(entry)
            label = "no breakaway" if b is None else f"b = {b:g}"
            series.append(("no breakaway" if b is None else f"breakaway, b = {b:g} (static friction "
                           f"{b * float(friction.f_min):.3f})", a))
            columns["time_s"] = t
            columns[f"{case.split(' (')[0].replace(' ', '_')}_{label.replace(' ', '').replace('=', '')}"] = a
        panels.append((f"{case}: f_max = {float(friction.f_max):.3f}, f_min = {float(friction.f_min):.3f}, "
                       f"experienced ratio {ratio:.2f}", series))
    _columns(out / "fig10_acceleration.csv", columns)
    figures.breakaway_grid(out / "fig10_breakaway.png", columns["time_s"], panels,
                           title=f"Fig. 10: rigid mass on sliding bearings only, base acceleration "
                           f"{FIG10_PEAK:g} g sin({FIG10_OMEGA:g} t); breakaway ratio b against none",
                           stamp="PTFE and pressure per panel, parallel to lay (Table 1); Y = 0.005 in; "
                           "R-FBI: 24 interfaces in series (Eq. 1 at the velocity per interface); "
                           "time step 1 ms.")
    results["fig10"] = entries


def fig11_panels(sweep, records) -> list:
    """Fig. 11's panels of a `building_sweep` result: per record, the peak base displacement
    over the record's PGD and the first-storey shear over the superstructure's weight, both
    dimensionless ([-]), as (panel title, axis label, [(system, values over the periods)])."""
    panels = []
    for i, record in enumerate(sweep.records):
        pgd = records[record]["pgd_in"] * INCH
        name = records[record]["name"]
        panels.append((f"{name}: base displacement", "peak base displacement / PGD [-]",
                       [(_system_words(s), sweep.peaks["base_disp"][i, j] / pgd) for j, s in enumerate(sweep.systems)]))
        panels.append((f"{name}: base shear", "peak first-storey shear / superstructure weight [-]",
                       [(_system_words(s), sweep.peaks["base_shear_ratio"][i, j]) for j, s in enumerate(sweep.systems)]))
    return panels


def _fig11(out, results, records, periods):
    """Fig. 11: the Table 2 building on sliding and linear isolation systems."""
    motions = {k: records[k]["motion"] for k in ("elcentro", "sct") if k in records}
    if "elcentro" in motions and motions["elcentro"].duration > FIG11_ELCENTRO_DURATION:
        m = motions["elcentro"]
        motions["elcentro"] = m.window(m.start_time, m.start_time + FIG11_ELCENTRO_DURATION)
    sweep = building_sweep(records=motions, periods=periods, time_step=STRUCTURE_TIME_STEP)
    rows, entries = [], []
    for i, record in enumerate(sweep.records):
        pgd = records[record]["pgd_in"] * INCH
        for j, system in enumerate(sweep.systems):
            for k, period in enumerate(sweep.periods):
                disp = float(sweep.peaks["base_disp"][i, j, k])
                entry = {"record": record, "system": system, "Tb_s": float(period),
                         "base_disp_in": disp / INCH, "base_disp_over_pgd": disp / pgd,
                         "base_shear_ratio": float(sweep.peaks["base_shear_ratio"][i, j, k]),
                         "max_drift_in": float(sweep.peaks["max_drift"][i, j, k]) / INCH,
                         "succeeded": bool(sweep.succeeded[i, j, k])}
                entries.append(entry)
                rows.append([entry[c] for c in entry])
    _write_csv(out / "fig11_spectra.csv", list(entries[0]), rows)
    panels = fig11_panels(sweep, records)
    names = ", ".join(f"{records[k]['name']} (PGA {records[k]['pga_g']:.2f} g, PGD {records[k]['pgd_in']:.2f} in)"
                      for k in sweep.records)
    figures.spectra_panels(out / "fig11_spectra.png", sweep.periods, panels,
                           title="Fig. 11: six-storey building (Table 2) on sliding and linear isolation "
                           "systems, against the isolation period Tb",
                           stamp=f"Records: {names}. Sliding: UF PTFE parallel to lay, breakaway b = 4, rubber "
                           "springs of period Tb, 5 % damping; linear: period Tb, 10 % damping; step "
                           f"{STRUCTURE_TIME_STEP:g} s.")
    results["fig11"] = entries
    results["_sweep"] = sweep


def _system_words(name: str) -> str:
    """'sliding_1000psi' -> 'sliding, UF at 1000 psi (b = 4)'; 'linear' -> 'linear, 10 % damping'."""
    if name.startswith("sliding_"):
        return f"sliding, UF at {name.removeprefix('sliding_').removesuffix('psi')} psi (b = 4)"
    if name == "linear":
        return "linear, 10 % damping"
    return name.replace("_", " ")
