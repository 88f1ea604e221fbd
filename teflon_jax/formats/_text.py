"""Low-level text helpers shared by the record readers: lines and numbers with positions."""

import math
import pathlib
import re

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
    line and column) when it is missing, a folder, not UTF-8 text or not JSON, or when an
    object repeats a key (JSON would keep only the last). `what` names the kind of file."""
    import json

    path = pathlib.Path(path)
    if path.is_dir():
        raise ValueError(f"{path}: is a folder, not the {what}; give the path of the file.")
    try:
        text = path.read_text(encoding="utf-8")
        return json.loads(text, object_pairs_hook=_refuse_repeated_keys)
    except FileNotFoundError:
        raise ValueError(f"{path}: no such {what}.") from None
    except UnicodeDecodeError as error:
        raise ValueError(f"{path}: not a text (UTF-8) JSON file (byte {error.start} cannot be read); "
                         f"give a {what}.") from None
    except json.JSONDecodeError as error:
        raise ValueError(f"{path}: not valid JSON (line {error.lineno}, column {error.colno}: "
                         f"{error.msg}).") from None
    except _RepeatedKey as repeated:
        raise ValueError(_repeated_key_message(path, text, repeated.key)) from None


class _RepeatedKey(Exception):
    def __init__(self, key):
        super().__init__(key)
        self.key = key


def _refuse_repeated_keys(pairs):
    """The object of `pairs` as a dict; `_RepeatedKey` for a key given twice."""
    document = dict(pairs)
    if len(document) != len(pairs):
        seen = set()
        for key, _ in pairs:
            if key in seen:
                raise _RepeatedKey(key)
            seen.add(key)
    return document


_JSON_TOKEN = re.compile(r'"(?:[^"\\]|\\.)*"|[{}\[\],:]')


def _member(container, name: str) -> str:
    """The path of the value that opens now inside `container` (an open object or list)."""
    if isinstance(container[0], dict):
        return f"{container[1]}.{name}" if container[1] else name
    return f"{container[1]}[{container[0]}]"


def _repeated_key_message(path, text: str, key: str) -> str:
    """The message for the first key that an object of `text` repeats: its line and column,
    the object's path in the document and the line of the first one."""
    import json

    stack = []  # per open object: [keys -> line, path, expecting a key]; per list: [index, path]
    name = ""
    for token in _JSON_TOKEN.finditer(text):
        char = token.group()[0]
        top = stack[-1] if stack else None
        if char in "{[":
            inner = "" if top is None else _member(top, name)
            stack.append([{}, inner, True] if char == "{" else [0, inner])
        elif char in "}]":
            stack.pop()
        elif char == "," and top is not None:
            if isinstance(top[0], dict):
                top[2] = True
            else:
                top[0] += 1
        elif char == '"' and top is not None and isinstance(top[0], dict) and top[2]:
            name, top[2] = json.loads(token.group()), False
            line = text.count("\n", 0, token.start()) + 1
            column = token.start() - text.rfind("\n", 0, token.start())
            if name in top[0]:
                where = f"in '{top[1]}'" if top[1] else "at the top level"
                return (f"{path}, line {line}, column {column}: the key '{name}' appears a second time "
                        f"{where} (first on line {top[0][name]}); JSON would keep only the last one, "
                        "so remove or rename one of them.")
            top[0][name] = line
    return f"{path}: the key '{key}' appears twice in one object; remove or rename one of them."
