"""Low-level text helpers shared by the record readers: lines and numbers with positions."""

import math
import pathlib

_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+)?"


def _read_lines(path) -> tuple[pathlib.Path, list[str]]:
    path = pathlib.Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such ground-motion file.")
    text = path.read_text(encoding="utf-8", errors="replace")
    lines = text.splitlines()
    if not any(line.strip() for line in lines):
        raise ValueError(
            f"{path}, line 1: the file is empty; expected a ground-motion record."
        )
    return path, lines


def _to_float(token: str, path, line_no: int, what: str) -> float:
    try:
        value = float(token.replace("D", "E").replace("d", "e"))
    except ValueError:
        raise ValueError(
            f"{path}, line {line_no}: cannot read {what} '{token}' as a number."
        ) from None
    if not math.isfinite(value):
        raise ValueError(
            f"{path}, line {line_no}: {what} is '{token}'; every value must be a finite number "
            "(gaps are not filled in, repair or cut the record)."
        )
    return value


def read_json_document(path, what: str):
    """The JSON object of the file `path`; `ValueError` naming the file (and for bad JSON the
    line and column) when it is missing, a folder, not UTF-8 text or not JSON. `what` names
    the kind of file."""
    import json

    path = pathlib.Path(path)
    if path.is_dir():
        raise ValueError(f"{path}: is a folder, not the {what}; give the path of the file.")
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ValueError(f"{path}: no such {what}.") from None
    except UnicodeDecodeError as error:
        raise ValueError(f"{path}: not a text (UTF-8) JSON file (byte {error.start} cannot be read); "
                         f"give a {what}.") from None
    except json.JSONDecodeError as error:
        raise ValueError(f"{path}: not valid JSON (line {error.lineno}, column {error.colno}: "
                         f"{error.msg}).") from None
