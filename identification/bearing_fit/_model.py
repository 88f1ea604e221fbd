"""The fitter's model as an equinox module: the simulated force of every record for one parameter set."""

import equinox as eqx
import jax.numpy as jnp

from teflon_jax.bearing import PARAMETER_BOUNDS

from ._loop_features import RecordConfig as RecordConfig
from ._ratio import RATIO_PAIRS, deltas_of
from ._record_force import PERPENDICULAR_NAMES

PARAMETER_NAMES = ("f_max", "delta_f", "rate_a", "yield_disp", "breakaway_ratio",
                   *PERPENDICULAR_NAMES)
"""Parameters the fitter can free, in the order of the reports. The `*_perpendicular`
constants (Eq. 1 for sliding perpendicular to the lay, along y) are those of biaxial records;
mu is interpolated linearly in the sliding angle between them and the parallel ones."""

PARAMETER_UNITS = {name: PARAMETER_BOUNDS[name].unit for name in PARAMETER_NAMES}



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
            values.update(deltas_of(params, RATIO_PAIRS, values))
        return values

    def forces(self, params, args):
        """Model force of every record: fx (n,), (fx, fy) stacked (2n,) for biaxial ones, or
        the force at the digitised points."""
        from ._digitised import digitised_model_force

        values = self.values(params, args["fixed"])
        return [
            c.time_force(values, rec) if c.kind == "time"
            else digitised_model_force(values, rec, config=c)
            for c, rec in zip(self.configs, args["records"])
        ]

    def __call__(self, params, args):
        from ._digitised import digitised_residual

        values = self.values(params, args["fixed"])
        out = []
        for c, rec in zip(self.configs, args["records"]):
            if c.kind == "time":
                out.append((c.time_force(values, rec) - rec["fx"]) * rec["weight"])
            else:
                out.append(digitised_residual(values, rec,
                                              config=c))
        return jnp.concatenate(out)
