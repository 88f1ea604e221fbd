"""Settings of the paper's figures: time steps, period grids, durations, specimen load."""

import csv

import numpy as np

from ..units import INCH, PSI

STRUCTURE_TIME_STEP = 0.005
"""RiccatiNewmark step [s] for the structural figures (4 substeps of the 0.02 s records)."""

FULL_PERIODS = np.round(np.arange(0.2, 4.0 + 1e-9, 0.1), 10)


QUICK_PERIODS = np.array([0.5, 1.0, 1.5, 2.0, 3.0, 4.0])


FIG7_DURATION = 10.0  # [s], the part of El Centro the paper plots


FIG11_ELCENTRO_DURATION = 40.0  # [s], the part of El Centro used for Fig. 11


FIG10_DURATION = 2.0  # [s]


FIG10_EARLY = 1.5  # [s], window of the "early" peak acceleration


FIG10_OMEGA = 3.14  # [rad/s]


FIG10_PEAK = 0.25  # [g]


FIG9_SMOOTHING = 9  # frequency samples in the running mean of the Fig. 9 spectra (0.9 Hz at 10 s)


HIGH_FREQUENCY = 5.0  # [Hz], split for the high-frequency content of Fig. 9


SPECIMEN_LOAD = 1000 * PSI * np.pi * (5 * INCH) ** 2  # 10 in diameter at 1000 psi [N]


def _write_csv(path, header, rows):
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(header)
        for row in rows:
            writer.writerow([f"{x:.8g}" if isinstance(x, float) else x for x in row])


def _columns(path, columns: dict):
    names = list(columns)
    arrays = [np.asarray(columns[n], dtype=float) for n in names]
    _write_csv(path, names, zip(*[a.tolist() for a in arrays]))
