"""Table 2 of the paper: the six-storey building's storey masses, stiffnesses and damping."""

import dataclasses
import functools

import numpy as np

from ..units import FOOT, KIP
from ._cited_table import read_cited_table


@dataclasses.dataclass(frozen=True)
class BuildingData:
    """Table 2: the six-storey frame (SI).

    - `frequencies` [Hz] (6,); `mode_shapes` (6 floors x 6 modes), floor 1 first;
    - `floor_weight` [N] (each of the six floors); `total_weight` [N] including the base;
    - `storey_height` [m]; `modal_damping` [-].
    """

    frequencies: np.ndarray
    mode_shapes: np.ndarray
    floor_weight: float
    total_weight: float
    storey_height: float
    modal_damping: float

    @property
    def base_weight(self) -> float:
        return self.total_weight - 6 * self.floor_weight


@functools.cache
def load_table2() -> BuildingData:
    """Table 2 (frequencies, mode shapes, weights) in SI units."""
    meta, rows = read_cited_table("table2_six_storey_building.csv")
    by_name = {row["row"]: row for row in rows}
    modes = [f"mode_{i}" for i in range(1, 7)]
    return BuildingData(
        frequencies=np.array([float(by_name["frequency [Hz]"][m]) for m in modes]),
        mode_shapes=np.array([[float(by_name[f"floor {f}"][m]) for m in modes] for f in range(1, 7)]),
        floor_weight=float(meta["floor_weight [kip]"]) * KIP,
        total_weight=float(meta["total_weight [kip]"]) * KIP,
        storey_height=float(meta["storey_height [ft]"]) * FOOT,
        modal_damping=float(meta["modal_damping"]),
    )
