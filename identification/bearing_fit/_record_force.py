"""The 1990 model's force along a measured displacement history, as the fitter sees it."""

from collections.abc import Mapping
from typing import Any

from teflon_jax.bearing import BoucWen, FrictionParameters, SlidingBearing
from teflon_jax.systems import force_along_path


def simulate_record_force(values: Mapping[str, Any], time, ux, load, *, z0=0.0, z_peak0=0.0,
                          use_breakaway: bool = True, n_interfaces: int = 1):
    """Force [N] of the model at the samples of a record (jit/vmap/grad-safe).

    The core's `teflon_jax.force_along_path` (a `lax.scan` of the exact Z update, the same
    computation as `simulate_bearing_test` with `RiccatiNewmark`) for a parameter dict;
    `tests/test_fit.py` checks it against `simulate_bearing_test`.

    **Arguments:** `values` with `f_max`, `delta_f`, `rate_a` [s/m], `yield_disp` [m],
    `breakaway_ratio`; `time` [s], `ux` [m], `load` [N] arrays of the samples.

    **Returns:** the force history [N] (same length as `time`).
    """
    bearing = SlidingBearing(
        friction=FrictionParameters(values["f_max"], values["delta_f"], values["rate_a"]),
        hysteresis=BoucWen(yield_disp=values["yield_disp"]),
        breakaway_ratio=values["breakaway_ratio"] if use_breakaway else None,
        n_interfaces=n_interfaces,
    )
    return force_along_path(bearing, time, ux, load, z0=z0, z_peak0=z_peak0)[0]

