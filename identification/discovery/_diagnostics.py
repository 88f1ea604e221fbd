"""Diagnostics of a fit: where the residual sits and what it correlates with; plots; report.

The residual here is *measured minus model* force. Dividing it by N Z (on samples where the
model slides, |Z| > 0.5) gives the *friction residual* d_mu: the correction the friction
coefficient would need there. A missing multiplicative effect mu -> mu (1 + theta g) leaves
d_mu = mu theta g, so d_mu correlates with the effect's regressor g:

| effect | regressor |
|---|---|
| velocity_dependence, interfaces | speed |v| |
| breakaway | first mobilisation (indicator of max|Z| < 0.999, and the next sample) |
| pressure_dependence | log(N / N_ref) |
| heating | surface temperature rise dT at heat_scale = 1 (heat-flux history) |
| asymmetry | hysteretic variable Z (the sliding direction, continuous through reversals) |
| anisotropy | sliding-angle weight |theta| / (pi/2) (biaxial records) |
| wear | accumulated travel |
| backlash | closeness to a reversal, 1 - |Z| (the force residual there, not d_mu) |

Plotting and report writing live here (not in the simulation modules); they use matplotlib's
Agg backend and write files only.
"""

import numpy as np

from teflon_jax.bearing import BREAKAWAY_THRESHOLD

EFFECT_REGRESSOR = {
    "velocity_dependence": "speed",
    "interfaces": "speed",
    "breakaway": "first_mobilisation",
    "pressure_dependence": "load",
    "heating": "heat",
    "asymmetry": "direction",
    "wear": "travel",
    "anisotropy": "angle",
    "backlash": "reversal",
}
"""The regressor each effect's signature follows."""

REGRESSOR_LABELS = {
    "speed": "speed |v| [m/s]",
    "first_mobilisation": "first mobilisation [0/1]",
    "load": "log(N / N_ref) [-]",
    "heat": "temperature-rise index dT [K]",
    "direction": "hysteretic variable Z (sliding direction) [-]",
    "travel": "accumulated travel / total [-]",
    "angle": "sliding-angle weight |theta| / (pi/2) [-]",
    "reversal": "closeness to a reversal 1 - |Z| [-]",
    "time": "time [s]",
    "half_cycle": "half-cycle index",
}


def half_cycle_index(ux, *, hysteresis: float = 0.05) -> np.ndarray:
    """Index (0, 1, 2, ...) of the half-cycle, the stroke between reversals, of each sample.

    A reversal is a displacement extremum followed by a retreat of more than `hysteresis`
    times the displacement range, so measurement noise creates no reversals.
    """
    ux = np.asarray(ux, float)
    tol = hysteresis * max(float(np.ptp(ux)), 1e-300)
    reversals = []
    direction, ext_value, ext_at = 0, ux[0], 0
    for i, u in enumerate(ux):
        if direction == 0:
            if abs(u - ux[0]) > tol:
                direction = 1 if u > ux[0] else -1
                ext_value, ext_at = u, i
        elif direction * (u - ext_value) > 0:
            ext_value, ext_at = u, i
        elif direction * (ext_value - u) > tol:
            reversals.append(ext_at)
            direction, ext_value, ext_at = -direction, u, i
    index = np.zeros(ux.size, dtype=int)
    for at in reversals:
        index[at + 1 :] += 1
    return index


def regressors(data, sim, half_cycles) -> dict:
    """Regressors of the candidate effects, one array per name (see `REGRESSOR_LABELS`).

    **Arguments:** `data` (`AugmentedData`), `sim` the simulation outputs of the current model
    (`simulate_augmented`, one record), `half_cycles` from `half_cycle_index`.
    """
    z_norm = np.hypot(np.asarray(sim["z"]), np.asarray(sim["z_y"]))
    first = np.maximum.accumulate(z_norm) < BREAKAWAY_THRESHOLD
    first[1:] |= first[:-1]
    return {
        "speed": np.abs(np.asarray(data.velocity)),
        "first_mobilisation": first.astype(float),
        "load": np.asarray(data.log_load_ratio),
        "heat": np.asarray(sim["heat_index"]),
        "direction": np.asarray(sim["z"]),
        "reversal": 1.0 - np.abs(np.asarray(sim["z"])),
        "travel": np.asarray(data.travel_fraction),
        "angle": np.asarray(data.angle_weight),
        "time": np.asarray(data.time) - float(data.time[0]),
        "half_cycle": np.asarray(half_cycles, float),
    }


def friction_residual(data, sim, model_force):
    """(d_mu, sliding mask): (measured - model) / (N Z) where |Z| > 0.5, else 0."""
    z = np.asarray(sim["z"])
    sliding = np.abs(z) > 0.5
    safe = np.where(sliding, z, 1.0) * np.asarray(data.normal)
    d_mu = np.where(sliding, (np.asarray(data.force) - model_force) / safe, 0.0)
    return d_mu, sliding


def residual_correlation(model_force, regress, effect, data, sim) -> float:
    """Pearson correlation of the friction residual with the effect's regressor (sliding samples).

    Positive: friction is under-predicted where the regressor is large. `nan`-free: 0 when the
    regressor is constant or the effect has no regressor.
    """
    key = EFFECT_REGRESSOR.get(effect)
    if key is None:
        return 0.0
    d_mu, sliding = friction_residual(data, sim, model_force)
    if key == "first_mobilisation":
        sliding = sliding | (regress[key] > 0)
        z = np.asarray(sim["z"])
        d_mu = np.where(
            sliding,
            (np.asarray(data.force) - model_force)
            / (np.asarray(data.normal) * np.where(np.abs(z) > 1e-3, z, 1e-3)),
            0.0,
        )
    if key == "reversal":
        # Backlash: near reversals the measured force is smaller in magnitude than the
        # model's; correlate (measured - model) with -model where |Z| < 0.95.
        near = np.abs(np.asarray(sim["z"])) < 0.95
        g, y = -model_force[near], (np.asarray(data.force) - model_force)[near]
        if g.size < 3 or np.std(g) == 0 or np.std(y) == 0:
            return 0.0
        return float(np.corrcoef(g, y)[0, 1])
    g = regress[key][sliding]
    y = d_mu[sliding]
    if g.size < 3 or np.std(g) == 0 or np.std(y) == 0:
        return 0.0
    return float(np.corrcoef(g, y)[0, 1])


def locate_residual(data, sim, model_force, half_cycles) -> dict:
    """Where the residual energy sits, by region of the test.

    Regions: first excursion (half-cycle 0), near reversals (model |Z| < 0.95: sticking and
    re-mobilisation), high and low speed (|v| above / below the median sliding speed), early
    and late thirds of the record, sliding in +x and in -x.

    **Returns:** region -> {"share_of_samples", "share_of_residual", "concentration"}, where
    concentration = share_of_residual / share_of_samples (> 1: the residual gathers there).
    """
    r2 = (np.asarray(data.force) - model_force) ** 2
    total = max(float(r2.sum()), 1e-300)
    speed = np.abs(np.asarray(data.velocity))
    z = np.abs(np.asarray(sim["z"]))
    sliding = z >= 0.95
    v_med = float(np.median(speed[sliding])) if sliding.any() else float(np.median(speed))
    t = np.asarray(data.time)
    third = (t[-1] - t[0]) / 3
    v = np.asarray(data.velocity)
    regions = {
        "first excursion": half_cycles == 0,
        "near reversals": ~sliding,
        "high speed": sliding & (speed > v_med),
        "low speed": sliding & (speed <= v_med),
        "early cycles (first third)": t < t[0] + third,
        "late cycles (last third)": t > t[-1] - third,
        "sliding +x": v > 0,
        "sliding -x": v < 0,
    }
    out = {}
    n = r2.size
    for name, mask in regions.items():
        share_n = float(mask.sum()) / n
        share_r = float(r2[mask].sum()) / total
        out[name] = {
            "share_of_samples": share_n,
            "share_of_residual": share_r,
            "concentration": share_r / share_n if share_n > 0 else 0.0,
        }
    return out


def noise_estimate(residual) -> float:
    """RMS of the sample-to-sample scatter of a residual, std(diff(r)) / sqrt(2).

    For white measurement noise on top of a smooth misfit this estimates the noise alone.
    """
    r = np.asarray(residual, float)
    return float(np.std(np.diff(r)) / np.sqrt(2.0))


def _lag1(r) -> float:
    r = np.asarray(r, float) - np.mean(r)
    denominator = float(r @ r)
    if denominator <= 0:
        return 0.0
    return float(np.clip((r[1:] @ r[:-1]) / denominator, 0.0, 0.999))


def effective_samples(residual) -> float:
    """n_eff = n (1 - rho) / (1 + rho) with rho the lag-1 autocorrelation (>= 0) of `residual`."""
    rho = _lag1(residual)
    return max(float(len(residual)) * (1.0 - rho) / (1.0 + rho), 2.0)


WHITENESS_LEVEL = 0.01
"""Significance level of the Ljung-Box test below which a residual is called structured."""


def ljung_box(residual, lags: int | None = None) -> dict:
    """Ljung-Box portmanteau test of whiteness of a residual series (time order).

        Q = n (n + 2) sum_{k=1}^{h} rho_k^2 / (n - k),   Q ~ chi^2(h) for white noise

    (Ljung & Box, "On a measure of lack of fit in time series models", Biometrika 65, 1978),
    with rho_k the lag-k sample autocorrelation and h = min(20, n // 5) lags by default.

    **Returns:** dict(q, lags, p_value, white) with `white = p_value >= WHITENESS_LEVEL`.
    """
    from jax.scipy.special import gammaincc

    r = np.asarray(residual, dtype=float)
    r = r - r.mean()
    n = r.size
    h = int(lags) if lags is not None else max(1, min(20, n // 5))
    if n < 3 * h or h < 1:
        raise ValueError(f"residual: {n} samples are too few for a Ljung-Box test with {h} lags.")
    denom = float(r @ r)
    if denom == 0.0:
        return dict(q=0.0, lags=h, p_value=1.0, white=True)
    rho = np.array([float(r[k:] @ r[:-k]) / denom for k in range(1, h + 1)])
    q = float(n * (n + 2) * np.sum(rho**2 / (n - np.arange(1, h + 1))))
    p = float(gammaincc(h / 2.0, q / 2.0))
    return dict(q=q, lags=h, p_value=p, white=p >= WHITENESS_LEVEL)
