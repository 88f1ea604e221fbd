"""`storey_rows` under the name of the module that held the storey results of a building, now
in `_structure_build.py` (one component) and `_bidirectional_models.py` (two)."""

from ._structure_build import storey_rows as storey_rows
