"""`check_duration` under the name of the module that held the histories of a structure on
sliders, now in `_structure_build.py` with `simulate_structure`."""

from ._structure_build import check_duration as check_duration
