"""The isolator's surfaces in a record suite: each series-pendulum slider's peak travel and each
heated surface's peak temperature rise per pair (`SURFACE_VARIABLES`, on ("pair", "group",
surface)), their labels, the table's columns and the suite file's variables."""

import jax
import numpy as np

from ..excitation import uniform_signal
from ._montecarlo_parts import surface_attributes, surface_groups
from ._result_variables import SURFACE_VARIABLES, group_labels, surface_columns


def suite_surface_labels(build, time_step: float, grounds) -> tuple[int, dict]:
    """(G bearing groups, {"<dimension>_names": labels} (`surface_attributes`)) of the
    structure `build` makes of one pair of `grounds` (rows (P, n) each), from its shapes alone."""

    def make(*rows):
        return build(*(uniform_signal(row, time_step) for row in rows))

    probe = jax.eval_shape(make, *(jax.ShapeDtypeStruct(np.shape(g)[1:], np.asarray(g).dtype) for g in grounds))
    labels = surface_attributes(probe)
    return (surface_groups(probe) if labels else 1), labels


def split_surfaces(joined: dict, labels: dict, group_names=None) -> dict | None:
    """The surface peaks popped from a suite's `joined` peaks (name -> (P, G, S)) with their
    labels (`labels`: `surface_attributes`; "group_names": `group_labels`), or `None`."""
    surfaces = {name: joined.pop(name) for name in SURFACE_VARIABLES if name in joined}
    if not surfaces:
        return None
    groups = group_labels(next(iter(surfaces.values())).shape[1], group_names)
    return surfaces | {key: tuple(values) for key, values in labels.items()} | {"group_names": groups}


def _labels(surfaces: dict, name: str) -> tuple:
    return surfaces[f"{SURFACE_VARIABLES[name][0]}_names"]


def suite_surface_columns(surfaces: dict | None) -> dict:
    """{"<name>_<unit>_[<group>_]<surface>": (P,)} of a suite's `surfaces` (`surface_columns`);
    {} without surfaces."""
    return {} if surfaces is None else surface_columns(surfaces, surfaces, surfaces["group_names"])


def surface_dataset_parts(surfaces: dict | None) -> tuple[dict, dict]:
    """(data variables, coordinates) of the surfaces in a suite's `xarray.Dataset`."""
    if surfaces is None:
        return {}, {}
    data, coords = {}, {"group": ("group", np.array(surfaces["group_names"], dtype=str), {"long_name": "bearing group"})}
    for name, (dim, units, long_name) in SURFACE_VARIABLES.items():
        if name in surfaces:
            data[name] = (("pair", "group", dim), np.asarray(surfaces[name]), {"units": units, "long_name": long_name})
            coords[dim] = (dim, np.array(_labels(surfaces, name), dtype=str))
    return data, coords


def surfaces_from_dataset(dataset) -> dict | None:
    """The surfaces of a loaded suite Dataset (as `split_surfaces` gives them), or `None`."""
    surfaces = {name: np.asarray(dataset[name].values, dtype=float) for name in SURFACE_VARIABLES if name in dataset}
    if not surfaces:
        return None
    labels = {f"{dim}_names": tuple(str(v) for v in dataset[dim].values)
              for name, (dim, _, _) in SURFACE_VARIABLES.items() if name in surfaces}
    return surfaces | labels | {"group_names": tuple(str(g) for g in dataset["group"].values)}
