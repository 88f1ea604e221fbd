"""Loaders for the paper's published tables (shipped in `data/`), returned in SI units.

Table 1: constants of Eq. 1 (and b of Eq. 17) for 16 PTFE / polished stainless-steel interfaces.
Table 2: modal data of the six-storey frame of Fig. 11.
Reference: Constantinou, Mokha & Reinhorn (1990), J. Struct. Eng. 116(2), 455-474.
"""

import dataclasses
import functools

import equinox as eqx
import jax.numpy as jnp

from ..bearing import FrictionParameters
from ..units import INCH, PSI
from ..validation import concrete
from ._cited_table import read_cited_table

PTFE_TYPES = ("UF", "15GF", "25GF")


DIRECTIONS = ("P", "T")


@dataclasses.dataclass(frozen=True)
class Interface:
    """One row of Table 1, in SI units.

    - `ptfe`: "UF", "15GF" or "25GF"; `direction`: "P" (parallel to lay) or "T" (perpendicular).
    - `pressure` [Pa]; `f_max`, `delta_f` [-]; `rate_a` [s/m]; `breakaway_ratio` b [-].
    """

    ptfe: str
    pressure: float
    direction: str
    f_max: float
    delta_f: float
    rate_a: float
    breakaway_ratio: float

    @property
    def label(self) -> str:
        return f"{self.ptfe} {self.pressure / PSI:.0f}psi {self.direction}"


@functools.cache
def load_table1() -> tuple[Interface, ...]:
    """The 16 interfaces of Table 1 in SI units (see `Interface`)."""
    _, rows = read_cited_table("table1_ptfe_interfaces.csv")
    return tuple(
        Interface(
            ptfe=row["ptfe"],
            pressure=float(row["pressure [psi]"]) * PSI,
            direction=row["direction"],
            f_max=float(row["f_max [%]"]) / 100.0,
            delta_f=float(row["delta_f [%]"]) / 100.0,
            rate_a=float(row["rate_a [s/in]"]) / INCH,
            breakaway_ratio=float(row["breakaway_ratio"]),
        )
        for row in rows
    )


def table1_parameters() -> tuple[FrictionParameters, jnp.ndarray, tuple[str, ...]]:
    """Table 1 as one batched `FrictionParameters` (leading axis 16), the b values and labels."""
    rows = load_table1()
    params = FrictionParameters(
        f_max=jnp.array([r.f_max for r in rows]),
        delta_f=jnp.array([r.delta_f for r in rows]),
        rate_a=jnp.array([r.rate_a for r in rows]),
    )
    return params, jnp.array([r.breakaway_ratio for r in rows]), tuple(r.label for r in rows)


def _rows_for(ptfe: str, direction: str) -> list[Interface]:
    if ptfe not in PTFE_TYPES:
        raise ValueError(f"ptfe: unknown PTFE type {ptfe!r}; accepted values: {', '.join(PTFE_TYPES)}.")
    if direction not in DIRECTIONS:
        raise ValueError(
            f"direction: unknown direction {direction!r}; accepted values: P (parallel to lay), "
            "T (perpendicular to lay)."
        )
    rows = [r for r in load_table1() if r.ptfe == ptfe and r.direction == direction]
    if not rows:
        available = sorted({(r.ptfe, r.direction) for r in load_table1()})
        raise ValueError(
            f"direction: Table 1 has no {direction} rows for {ptfe}; available combinations: "
            + ", ".join(f"{p}/{d}" for p, d in available)
            + "."
        )
    return sorted(rows, key=lambda r: r.pressure)


class FrictionTable(eqx.Module):
    """Rows of Table 1 for one PTFE type and direction, interpolated linearly in contact pressure.

    Eq. 1 constants at a pressure between two tabulated ones are taken on the straight line
    between them (the paper tabulates 1000, 2000, 3000 and 6500 psi). Outside that range the
    nearest segment is extended only when `extrapolate=True`.
    """

    pressures: jnp.ndarray  # [Pa]
    f_max: jnp.ndarray
    delta_f: jnp.ndarray
    rate_a: jnp.ndarray  # [s/m]
    breakaway_ratio: jnp.ndarray
    extrapolate: bool = eqx.field(static=True, default=False)

    def at(self, pressure) -> tuple[FrictionParameters, jnp.ndarray]:
        """Eq. 1 constants and b at `pressure` [Pa]; differentiable in `pressure`.

        Under `jit` a pressure outside the table is an `equinox` runtime error.
        """
        pressure = jnp.asarray(pressure, dtype=self.pressures.dtype)
        lo, hi = self.pressures[0], self.pressures[-1]
        if not self.extrapolate:
            known = concrete(self.pressures)
            span = "" if known is None else f" {known[0] / PSI:.0f}-{known[-1] / PSI:.0f} psi"
            message = (
                f"pressure outside Table 1's range{span}; pass extrapolate=True to extend the "
                "nearest segment"
            )
            pressure = eqx.error_if(pressure, (pressure < lo * (1 - 1e-9)) | (pressure > hi * (1 + 1e-9)), message)

        def interp(values):
            index = jnp.clip(jnp.searchsorted(self.pressures, pressure) - 1, 0, len(self.pressures) - 2)
            p0, p1 = self.pressures[index], self.pressures[index + 1]
            v0, v1 = values[index], values[index + 1]
            return v0 + (v1 - v0) * (pressure - p0) / (p1 - p0)

        params = FrictionParameters(
            f_max=interp(self.f_max), delta_f=interp(self.delta_f), rate_a=interp(self.rate_a)
        )
        return params, interp(self.breakaway_ratio)


def friction_table(ptfe: str, direction: str = "P", *, extrapolate: bool = False) -> FrictionTable:
    """The Table 1 rows of `ptfe` ("UF", "15GF", "25GF") and `direction` ("P", "T") as a `FrictionTable`."""
    rows = _rows_for(ptfe, direction)
    return FrictionTable(
        pressures=jnp.array([r.pressure for r in rows]),
        f_max=jnp.array([r.f_max for r in rows]),
        delta_f=jnp.array([r.delta_f for r in rows]),
        rate_a=jnp.array([r.rate_a for r in rows]),
        breakaway_ratio=jnp.array([r.breakaway_ratio for r in rows]),
        extrapolate=extrapolate,
    )


def interface_parameters(
    ptfe: str, pressure: float, direction: str = "P", *, extrapolate: bool = False
) -> tuple[FrictionParameters, float]:
    """Eq. 1 constants and b for `ptfe` at `pressure` [Pa] and `direction`, from Table 1.

    A pressure at or below zero, or outside the tabulated 1000-6500 psi without
    `extrapolate=True`, is a `ValueError` naming the parameter and the range.
    """
    table = friction_table(ptfe, direction, extrapolate=extrapolate)
    pressure = float(pressure)
    lo, hi = float(table.pressures[0]), float(table.pressures[-1])
    if not pressure > 0:
        raise ValueError(f"pressure: must be > 0, got {pressure} Pa.")
    if not extrapolate and not (lo * (1 - 1e-9) <= pressure <= hi * (1 + 1e-9)):
        raise ValueError(
            f"pressure: {pressure / PSI:.0f} psi is outside Table 1's range for {ptfe}/{direction} "
            f"({lo / PSI:.0f}-{hi / PSI:.0f} psi); choose a pressure in that range or ask for "
            "extrapolation (extrapolate=True, --extrapolate)."
        )
    params, b = table.at(pressure)
    return params, float(b)
