"""Digitised loops: (u, F) points read off a published figure, plus the imposed protocol.

A digitised loop has no time. The model is simulated along the protocol of the record
(`metadata["protocol"]`, e.g. `sine amplitude=1 in frequency=0.16 Hz cycles=3`) on a fine time
grid (the protocol's `teflon_jax.excitation` motion, velocity by `sample_velocity` as for
every record), and each digitised point is compared with the model force at the same displacement on the
same branch of the last full cycle. The branch of a point (moving towards +x or -x) follows from
the order of the points along the loop, as they are read off the figure.

Loops do not contain the first excursion from rest, so `breakaway_ratio` is not identifiable
from them; and a few dozen points per branch rarely resolve the elastic branch, so
`yield_disp` is fitted only when at least three points lie within 2 Y of a reversal.

Points read off a figure have errors in both coordinates. Near a reversal the force changes
steeply with displacement (elastic branch, and the steep rise of Eq. 1 at low velocity), so a
small displacement reading error makes a large force residual. Each point is therefore weighted
by the effective variance (Orear, Am. J. Phys. 50, 1982)

    sigma_i^2 = sigma_F^2 + (dF/du)_i^2 sigma_u^2,

with dF/du the slope of the model branch at the point (held constant within each solver step)
and the reading errors `sigma_u` = 0.1 % of the amplitude and `sigma_F` = 0.5 % of the largest
force unless the record states `reading_error_u [m]` / `reading_error_f [N]` in its metadata.
"""

import jax
import jax.numpy as jnp
import numpy as np

from teflon_jax.formats import Protocol
from teflon_jax.systems import sample_velocity

from ._record_force import simulate_record_force

GRID_SAMPLES_PER_CYCLE = 2000
"""Time samples per cycle of the protocol on which the model is simulated."""


def _protocol_grid(protocol: Protocol, name: str):
    if protocol.pattern not in ("sine", "triangle"):
        raise ValueError(
            f"{name}: the fitter takes digitised loops of uniaxial protocols ('sine' or "
            f"'triangle'), got '{protocol.pattern}'.")
    cycles = protocol.cycles if protocol.cycles is not None else 3.0
    n = int(round(cycles * GRID_SAMPLES_PER_CYCLE))
    time = np.linspace(0.0, cycles / protocol.frequency, n + 1)
    ux, _ = protocol.displacement(time)
    return time, np.asarray(ux, dtype=float), cycles


def _last_branches(ux):
    """Indices of the last complete increasing and decreasing runs of `ux`, sorted by u."""
    from ._loop_features import _reversals

    reversals = _reversals(ux)
    runs = list(zip(reversals[:-1], reversals[1:]))
    increasing = [r for r in runs if ux[r[1]] > ux[r[0]]]
    decreasing = [r for r in runs if ux[r[1]] < ux[r[0]]]
    if not increasing or not decreasing:
        raise ValueError("protocol: fewer than one full cycle; give cycles >= 1.5.")
    a, b = increasing[-1]
    inc = np.arange(a, b + 1)
    a, b = decreasing[-1]
    dec = np.arange(b, a - 1, -1)  # ascending u
    return inc, dec


def point_branches(ux) -> np.ndarray:
    """+1 / -1 for points digitised along the loop while moving towards +x / -x.

    The direction is the sign of the displacement change between neighbouring points in the
    order given (central where possible); points at a reversal take the direction of the
    branch they are closer to in the order.
    """
    ux = np.asarray(ux, dtype=float)
    forward = np.sign(np.diff(ux))
    branch = np.zeros(ux.size)
    branch[:-1] = forward
    branch[-1] = forward[-1]
    for i in range(1, ux.size):
        if branch[i] == 0:
            branch[i] = branch[i - 1]
    for i in range(ux.size - 2, -1, -1):
        if branch[i] == 0:
            branch[i] = branch[i + 1]
    return branch


def prepare_digitised(record, *, name, load, parallel, series, yield_ref):
    """Prepare a digitised loop for the bearing fit (see `_bearing_fit.PreparedRecord`)."""
    from ._loop_features import _ZERO_CROSSING, PreparedRecord, _friction_law_start

    protocol = record.metadata["protocol"]
    time, grid_ux, _ = _protocol_grid(protocol, name)
    amplitude = protocol.amplitude
    u = np.asarray(record.ux, dtype=float)
    f = np.asarray(record.fx, dtype=float)
    if u.size < 8:
        raise ValueError(f"{name}: only {u.size} digitised points; give a few dozen per branch.")
    outside = np.flatnonzero(np.abs(u) > 1.02 * amplitude)
    if outside.size:
        i = outside[0]
        raise ValueError(
            f"{name}: point {i} (ux = {u[i]:.6g} m) lies outside the protocol amplitude "
            f"{amplitude:.6g} m; check the protocol line or the digitised units.")
    if 2 * amplitude < 3 * yield_ref:
        raise ValueError(
            f"{name}: the bearing never slides: the stroke 2 x {amplitude:.3g} m is below "
            f"3 Y = {3 * yield_ref:.3g} m; friction and Y cannot be told apart.")
    branch = point_branches(u)
    inc, dec = _last_branches(grid_ux)
    load_value = float(np.mean(load))
    mu = f / (load_value * parallel)
    distance = np.where(branch > 0, u + amplitude, amplitude - u)
    grid_velocity = sample_velocity(time, grid_ux)
    speed = np.where(branch > 0,
                     np.interp(u, grid_ux[inc], np.abs(grid_velocity[inc])),
                     np.interp(u, grid_ux[dec], np.abs(grid_velocity[dec]))) / series
    sliding = distance > max(0.04 * amplitude, 4.0 * yield_ref)
    if np.count_nonzero(sliding) < 6:
        raise ValueError(f"{name}: fewer than 6 digitised points while sliding.")
    f_max, delta_f, rate_a = _friction_law_start(speed[sliding], mu[sliding] * branch[sliding])

    y_estimates, counts = [], []
    for s in (1.0, -1.0):
        on = np.flatnonzero(branch == s)
        order = on[np.argsort(distance[on])]
        d, fs = distance[order], f[order] * s
        positive = np.flatnonzero(fs > 0)
        if positive.size and positive[0] > 0:
            j = positive[0]
            d0 = d[j - 1] + (d[j] - d[j - 1]) * (-fs[j - 1]) / (fs[j] - fs[j - 1])
            y_estimates.append(d0 / _ZERO_CROSSING)
    yield_disp = float(np.median(y_estimates)) if y_estimates else float(yield_ref)
    if not np.isfinite(yield_disp) or yield_disp <= 0:
        yield_disp = float(yield_ref)
    for s in (1.0, -1.0):
        counts.append(int(np.count_nonzero((branch == s) & (distance < 2.0 * yield_disp))))

    sigma_u = _reading_error(record, "reading_error_u", 1e-3 * amplitude, name)
    sigma_f = _reading_error(record, "reading_error_f", 5e-3 * float(np.abs(f).max()), name)
    arrays = dict(
        sigma_u=np.asarray(sigma_u), sigma_f=np.asarray(sigma_f),
        grid_time=time, grid_ux=grid_ux, grid_load=np.full(time.shape, load_value),
        grid_velocity=grid_velocity,
        inc=inc, dec=dec, ux=u, fx=f, branch=branch,
        weight=np.ones_like(u),
    )
    prepared = PreparedRecord(
        name=name, kind="digitised", arrays=arrays, first_motion=False,
        start=dict(f_max=f_max, delta_f=delta_f, rate_a=rate_a, yield_disp=yield_disp,
                   breakaway_ratio=1.5),
        warnings=[], elastic_samples=float(np.median(counts)),
        interfaces_in_parallel=parallel, interfaces_in_series=series,
        measured=f, ux=u, time=None,
    )
    prepared.speed_low = float(np.percentile(speed[sliding], 5))
    prepared.speed_high = float(np.percentile(speed[sliding], 95))
    return prepared


def _grid_force(values, arrays, config):
    return simulate_record_force(
        values, arrays["grid_time"], arrays["grid_ux"], arrays["grid_load"],
        velocity=arrays["grid_velocity"],
        interfaces_in_parallel=config.interfaces_in_parallel,
        interfaces_in_series=config.interfaces_in_series)


def digitised_model_force(values, arrays, *, config):
    """Model force [N] at the digitised points: the last cycle of the protocol, per branch."""
    grid = _grid_force(values, arrays, config)
    return _branch_force(arrays, grid, arrays["ux"])


def digitised_residual(values, arrays, *, config):
    """(model - digitised force) / sigma_i at each point (effective variance, module docstring)."""
    grid = _grid_force(values, arrays, config)
    u = arrays["ux"]
    force = _branch_force(arrays, grid, u)
    du = 0.25 * arrays["sigma_u"]
    slope = jax.lax.stop_gradient(
        (_branch_force(arrays, grid, u + du) - _branch_force(arrays, grid, u - du)) / (2 * du))
    sigma = jnp.sqrt(arrays["sigma_f"] ** 2 + (slope * arrays["sigma_u"]) ** 2)
    return (force - arrays["fx"]) * arrays["weight"] / sigma


def _reading_error(record, key, default, name):
    for k, v in record.metadata.items():
        if k.split(" [")[0] == key:
            try:
                value = float(v)
            except (TypeError, ValueError):
                raise ValueError(f"{name}: metadata '{k}' must be a number (SI).") from None
            if not value > 0:
                raise ValueError(f"{name}: metadata '{k}' must be positive, got {value}.")
            return value
    return float(default)


def _branch_force(arrays, grid_force, u):
    u_inc, f_inc = arrays["grid_ux"][arrays["inc"]], grid_force[arrays["inc"]]
    u_dec, f_dec = arrays["grid_ux"][arrays["dec"]], grid_force[arrays["dec"]]
    return jnp.where(arrays["branch"] > 0, jnp.interp(u, u_inc, f_inc), jnp.interp(u, u_dec, f_dec))
