"""Coverage of the fitter's 95 % intervals on noisy synthetic records (slow).

The records are the simulator's test No. 62 (UF, 1000 psi, P; 1 in at 0.16 Hz), with independent
Gaussian noise of 2 % of the RMS force added to each; every record is fitted on its own (one
vmapped batch). If the standard errors are right, estimate +- 1.96 SE contains the truth in about
95 % of the fits; a covariance off by a factor 2 gives about 68 % or 99.99 %.
"""

import numpy as np
import pytest

import teflon_jax as tj
from identification.bearing_fit import fit_bearing_tests_batch
from teflon_jax.units import INCH, PSI

Y_PAPER = 0.005 * INCH
FREE = ("f_max", "delta_f", "rate_a", "yield_disp")
N_RECORDS = 120


@pytest.mark.slow
def test_95_percent_intervals_cover_the_truth():
    friction, _ = tj.interface_parameters("UF", 1000 * PSI, "P")
    truth = dict(f_max=float(friction.f_max), delta_f=float(friction.delta_f),
                 rate_a=float(friction.rate_a), yield_disp=Y_PAPER)
    load = 1000 * PSI * np.pi * (5 * INCH) ** 2
    bearing = tj.paper_bearing(friction, yield_disp=Y_PAPER)
    result = tj.imposed_path_test(bearing, tj.SineMotion(1 * INCH, 0.16, cycles=2), load,
                                      samples_per_cycle=300)
    t, u, f = (np.asarray(x) for x in (result.time, result.ux, result.fx))
    sigma = 0.02 * np.sqrt(np.mean(f**2))
    rng = np.random.default_rng(12)
    records = [tj.test_record_from_arrays(u, f + sigma * rng.standard_normal(f.size), time=t,
                                          normal_load=load) for _ in range(N_RECORDS)]
    fits = fit_bearing_tests_batch(records, free=FREE, n_starts=1)
    assert all(fit.converged for fit in fits)
    inside = np.array([[abs(fit.parameters[n] - truth[n]) <= 1.96 * fit.std_errors[n]
                        for n in FREE] for fit in fits])
    coverage = inside.mean()
    assert 0.90 <= coverage <= 0.99, (coverage, inside.mean(axis=0))
    # Each parameter on its own, with room for the binomial scatter of 120 fits (sd 2 %).
    assert np.all((inside.mean(axis=0) >= 0.87) & (inside.mean(axis=0) <= 1.0))
