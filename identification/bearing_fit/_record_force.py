"""The fitter's force model: a parameter dict as the one bearing model, driven along a record.

The force at the samples is `teflon_jax.imposed_path_test` (its velocity convention: the
velocity at the sample by second-order central differences, `sample_velocity`; Z exact between
samples, Park's Eqs. 8-9 along the Hermite path in the plane). This module only maps the
fitter's parameter names onto a `SlidingBearing` and multiplies by the interfaces recorded in
parallel.

Reference: Constantinou, Mokha & Reinhorn (1990), Eqs. 1, 3, 8-9, 17; FORMATS.md.
"""

from collections.abc import Mapping
from typing import Any

import jax.numpy as jnp

from teflon_jax.bearing import BoucWen, FrictionParameters, SlidingBearing
from teflon_jax.systems import imposed_path_test, sampled_path

PERPENDICULAR_NAMES = ("f_max_perpendicular", "delta_f_perpendicular", "rate_a_perpendicular")
"""Eq. 1 constants for sliding perpendicular to the lay (along y) in biaxial fits."""


def bearing_of(values: Mapping[str, Any], *, interfaces_in_series: int = 1) -> SlidingBearing:
    """The `SlidingBearing` of a parameter dict (`PARAMETER_NAMES`, and for anisotropic
    biaxial fits `PERPENDICULAR_NAMES`): no breakaway (Eq. 1 throughout) where
    `breakaway_ratio` is `None` or missing, a structural choice fixed at trace time."""
    perpendicular = None
    if all(values.get(name) is not None for name in PERPENDICULAR_NAMES):
        perpendicular = FrictionParameters(*(values[n] for n in PERPENDICULAR_NAMES))
    return SlidingBearing(
        friction=FrictionParameters(values["f_max"], values["delta_f"], values["rate_a"]),
        hysteresis=BoucWen(yield_disp=values["yield_disp"]),
        breakaway_ratio=values.get("breakaway_ratio"),
        friction_perpendicular=perpendicular,
        n_interfaces=interfaces_in_series,
    )


def simulate_record_force(values: Mapping[str, Any], time, ux, load, *, velocity=None, uy=None,
                          velocity_y=None, z0=0.0, z_peak0=0.0, interfaces_in_parallel: int = 1, interfaces_in_series: int = 1,
                          park_elements: int = 16):
    """Force [N] of the model at the samples of a record (jit/vmap/grad-safe in `values`).

        F = m mu(v / n, theta, max|Z|) N Z      (Eqs. 1, 17; m in parallel, n in series)

    **Arguments:** `values` with `f_max`, `delta_f`, `rate_a` [s/m], `yield_disp` [m],
    `breakaway_ratio` (`None` or missing: no breakaway) (and `PERPENDICULAR_NAMES` for an anisotropic biaxial model); `time` [s],
    `ux` [m], `load` [N] of the samples; `velocity` [m/s] at the samples (default
    `sample_velocity(time, ux)`); biaxial records add `uy` [m] and `velocity_y`; `z0`,
    `z_peak0` the state at the first sample (uniaxial); `park_elements` elements per sample
    interval of a biaxial path (see `teflon_jax.solver.park_substeps`).

    **Returns:** fx [N] (n,) for a uniaxial record, `(fx, fy)` [N] each (n,) for a biaxial one.
    """
    bearing = bearing_of(values, interfaces_in_series=interfaces_in_series)
    path = sampled_path(time, ux, load, uy=uy, velocity=velocity, velocity_y=velocity_y,
                        park_elements=park_elements)
    planar = uy is not None
    response = imposed_path_test(bearing, path, z0=None if planar else jnp.asarray(z0),
                                  z_peak0=0.0 if planar else z_peak0)
    if not planar:
        return interfaces_in_parallel * response.fx
    return interfaces_in_parallel * response.fx, interfaces_in_parallel * response.fy
