"""The fitter's model as an equinox module: the simulated force of every record for one parameter set."""

import equinox as eqx
import jax.numpy as jnp

from teflon_jax.bearing import PARAMETER_BOUNDS

from ._loop_features import RecordConfig as RecordConfig
from ._record_force import PERPENDICULAR_NAMES, simulate_record_force

PARAMETER_NAMES = ("f_max", "delta_f", "rate_a", "yield_disp", "breakaway_ratio",
                   *PERPENDICULAR_NAMES)
"""Parameters the fitter can free, in the order of the reports. The `*_perpendicular`
constants (Eq. 1 for sliding perpendicular to the lay, along y) are those of biaxial records;
mu is interpolated linearly in the sliding angle between them and the parallel ones."""

PARAMETER_UNITS = {name: PARAMETER_BOUNDS[name].unit for name in PARAMETER_NAMES}

RATIO_PAIRS = (("delta_f", "f_max", "delta_ratio"),
               ("delta_f_perpendicular", "f_max_perpendicular", "delta_ratio_perpendicular"))
"""(delta_f, f_max, internal name): inside the optimiser delta_f = ratio x f_max, 0 < ratio < 1."""


class BearingModel(eqx.Module):
    """Residual of the bearing fit (static configuration only; data come in `args`).

    `args = {"fixed": {name: value for all parameters}, "records": [arrays of each record]}`.
    With `ratio=True` a free `delta_f` is the parameter `delta_ratio = delta_f / f_max` (and
    likewise for the perpendicular constants). `anisotropic`: the model has its own
    perpendicular constants (else sliding along y follows the parallel ones). Breakaway
    (Eq. 17) is in the model where `breakaway_ratio` is free or fixed to a number, not `None`.
    """

    free: tuple[str, ...] = eqx.field(static=True)
    configs: tuple[RecordConfig, ...] = eqx.field(static=True)
    ratio: bool = eqx.field(static=True)
    anisotropic: bool = eqx.field(static=True, default=False)

    def values(self, params, fixed):
        names = PARAMETER_NAMES if self.anisotropic else PARAMETER_NAMES[:5]
        values = {name: params.get(name, fixed[name]) for name in names}
        if self.ratio:
            for delta, f_max, internal in RATIO_PAIRS:
                if internal in params:
                    values[delta] = params[internal] * values[f_max]
        return values

    def _time_force(self, values, c, rec):
        if c.biaxial:
            fx, fy = simulate_record_force(
                values, rec["time"], rec["ux"], rec["load"], velocity=rec["velocity"],
                uy=rec["uy"], velocity_y=rec["velocity_y"],
                interfaces_in_parallel=c.interfaces_in_parallel,
                interfaces_in_series=c.interfaces_in_series, park_elements=c.park_elements)
            return jnp.concatenate([fx, fy])
        return simulate_record_force(
            values, rec["time"], rec["ux"], rec["load"], velocity=rec["velocity"],
            z0=rec["z0"], z_peak0=rec["z_peak0"],
            interfaces_in_parallel=c.interfaces_in_parallel,
            interfaces_in_series=c.interfaces_in_series)

    def forces(self, params, args):
        """Model force of every record: fx (n,), (fx, fy) stacked (2n,) for biaxial ones, or
        the force at the digitised points."""
        from ._digitised import digitised_model_force

        values = self.values(params, args["fixed"])
        return [
            self._time_force(values, c, rec) if c.kind == "time"
            else digitised_model_force(values, rec, config=c)
            for c, rec in zip(self.configs, args["records"])
        ]

    def __call__(self, params, args):
        from ._digitised import digitised_residual

        values = self.values(params, args["fixed"])
        out = []
        for c, rec in zip(self.configs, args["records"]):
            if c.kind == "time":
                out.append((self._time_force(values, c, rec) - rec["fx"]) * rec["weight"])
            else:
                out.append(digitised_residual(values, rec,
                                              config=c))
        return jnp.concatenate(out)
