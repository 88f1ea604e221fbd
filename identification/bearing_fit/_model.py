"""The fitter's model as an equinox module: the simulated force of every record for one parameter set."""


import equinox as eqx
import jax.numpy as jnp

from ._record_force import simulate_record_force

PARAMETER_NAMES = ("f_max", "delta_f", "rate_a", "yield_disp", "breakaway_ratio")
"""Parameters the fitter can free, in the order of the reports."""

PARAMETER_UNITS = {
    "f_max": "-", "delta_f": "-", "rate_a": "s/m", "yield_disp": "m", "breakaway_ratio": "-",
}


# ---------------------------------------------------------------------------------------------
# The model and its residual




class BearingModel(eqx.Module):
    """Residual of the bearing fit (static configuration only; data come in `args`).

    `args = {"fixed": {name: value for all five}, "records": [arrays of each record]}`.
    With `ratio=True` the free `delta_f` is the parameter `delta_ratio = delta_f / f_max`.
    """

    free: tuple[str, ...] = eqx.field(static=True)
    kinds: tuple[str, ...] = eqx.field(static=True)
    n_interfaces: tuple[int, ...] = eqx.field(static=True)
    use_breakaway: bool = eqx.field(static=True)
    ratio: bool = eqx.field(static=True)

    def values(self, params, fixed):
        values = {name: params.get(name, fixed[name]) for name in PARAMETER_NAMES}
        if self.ratio and "delta_ratio" in params:
            values["delta_f"] = params["delta_ratio"] * values["f_max"]
        return values

    def _time_force(self, values, n, rec):
        return simulate_record_force(
            values, rec["time"], rec["ux"], rec["load"], z0=rec["z0"],
            z_peak0=rec["z_peak0"], use_breakaway=self.use_breakaway, n_interfaces=n)

    def forces(self, params, args):
        from ._digitised import digitised_model_force

        values = self.values(params, args["fixed"])
        return [
            self._time_force(values, n, rec) if kind == "time"
            else digitised_model_force(values, rec, use_breakaway=self.use_breakaway, n_interfaces=n)
            for kind, n, rec in zip(self.kinds, self.n_interfaces, args["records"])
        ]

    def __call__(self, params, args):
        from ._digitised import digitised_residual

        values = self.values(params, args["fixed"])
        out = []
        for kind, n, rec in zip(self.kinds, self.n_interfaces, args["records"]):
            if kind == "time":
                out.append((self._time_force(values, n, rec) - rec["fx"]) * rec["weight"])
            else:
                out.append(digitised_residual(values, rec, use_breakaway=self.use_breakaway,
                                              n_interfaces=n))
        return jnp.concatenate(out)
