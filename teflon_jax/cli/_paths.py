"""The paths a command is given: each output can be written, is not one of the command's
inputs and ends in the suffix of what is written there; each input file is given once. All
checked before any work (`check_outputs`, `check_distinct_files`)."""

import os
import pathlib

_IMAGE_SUFFIXES = (".png", ".pdf", ".svg", ".jpg", ".jpeg", ".eps", ".ps", ".tif", ".tiff", ".webp")

OUTPUT_FLAGS = {
    "simulate-test": (("out", "--out", "file", "test_record.csv"), ("plot", "--plot", "image", "loop.png")),
    "fit": (("json", "--json", "file", "fit.json"), ("plot", "--plot", "image", "fit.png"),
            ("bayes", "--bayes", "folder", "")),
    "diagnose": (("json_path", "--json", "file", "diagnose.json"), ("report", "--report", "folder", "")),
    "montecarlo": (("json", "--json", "file", "mc.json"), ("plot", "--plot", "image", "mc.png"),
                   ("out", "--out", "file", "mc.nc")),
    "design": (("json", "--json", "file", "design.json"), ("plot", "--plot", "image", "design.png"),
               ("out", "--out", "file", "sweep.nc")),
    "run": (("json", "--json", "file", "run.json"), ("plot", "--plot", "image", "run.png"),
            ("histories", "--histories", "file", "histories.nc"), ("out", "--out", "file", "suite.nc")),
    "reproduce": (("out", "--out", "folder", ""),),
}
"""Each sub-command's output paths: (attribute, flag, "file" | "image" | "folder", an example name)."""


OTHER_OUTPUTS = (("save_bearing", "--save-bearing", "file", "bearing.json"),
                 ("save_isolator", "--save-isolator", "file", "isolator.json"),
                 ("pelicun_demands", "--pelicun-demands", "file", "demands.csv"))
"""Output files that some commands write beside those of `OUTPUT_FLAGS`, in its form."""

_FILE_SUFFIXES = {(None, "--json"): (".json",), (None, "--save-bearing"): (".json",),
                  (None, "--save-isolator"): (".json",), ("simulate-test", "--out"): (".csv",)}
"""The suffixes an output file of a flag (of one command, or of every command: None) must end in,
where its format is fixed: the first is the one written."""

_INPUT_NAMES = {"records": "the record", "record": "the record"}
"""Positional inputs, named in messages as the user knows them."""


def output_flags(command: str) -> tuple:
    """`OUTPUT_FLAGS` of `command` and `OTHER_OUTPUTS`."""
    return (*OUTPUT_FLAGS.get(command, ()), *OTHER_OUTPUTS)


def _outputs(args, command: str) -> list[tuple[str, str, str]]:
    """(flag, path as typed, kind) of every output path given to `command`."""
    given = [(flag, getattr(args, dest, None), kind) for dest, flag, kind, _ in output_flags(command)]
    return [(flag, str(text), kind) for flag, text, kind in given if text is not None and str(text).strip()]


def _inputs(args, outputs) -> list[tuple[str, pathlib.Path]]:
    """(name, path) of every existing file among the other values of `args`: the command's
    inputs (records, suite, plan, bearing and isolator files, ...)."""
    taken = {flag.lstrip("-").replace("-", "_") for flag, _, _ in outputs} | {"json_path"}
    found = []
    for dest, value in vars(args).items():
        if dest in taken or dest.startswith("_") or dest.endswith("_text"):
            continue
        for item in value if isinstance(value, (list, tuple)) else (value,):
            if isinstance(item, (str, pathlib.PurePath)) and str(item).strip() and pathlib.Path(item).is_file():
                found.append((_INPUT_NAMES.get(dest, "--" + dest.replace("_", "-")), pathlib.Path(item)))
    return found


def check_no_clash(args, command: str) -> None:
    """`ValueError` naming both flags when an output path of `command` is one of its input
    files (writing it would replace the input) or another output's path."""
    outputs = _outputs(args, command)
    inputs = _inputs(args, outputs)
    seen = {}
    for flag, text, _ in outputs:
        path = pathlib.Path(text)
        key = os.path.realpath(path)
        if key in seen:
            raise ValueError(f"{flag} {text}: is also the path of {seen[key]}; give each output its own name.")
        seen[key] = flag
        for name, source in inputs:
            if path.exists() and os.path.samefile(path, source):
                raise ValueError(f"{flag} {text}: is the input file of {name}; writing the results there "
                                 "would replace it. Give another name for the output.")


def check_distinct_files(named, why: str) -> None:
    """`ValueError` naming both where two of `named` ((flag or name, path as typed), None paths
    skipped) are one file, however spelled (`./x.csv`, a link); `why` says why each must be
    its own."""
    seen = []
    for name, text in named:
        if text is None or not pathlib.Path(text).is_file():
            continue
        for other, other_text in seen:
            if os.path.samefile(text, other_text):
                raise ValueError(f"{name} {text}: is the file of {other} {other_text}; {why}.")
        seen.append((name, text))


def check_outputs(args, command: str) -> list[pathlib.Path]:
    """Before any work: every output path of `command` on `args` can be written and is none
    of its inputs (`check_no_clash`). A file (or image) must not be a folder, a folder not a
    file; the nearest existing folder above must be writable, and the missing folders are
    created here, the same for every command; an image needs a suffix matplotlib writes. A
    `ValueError` names the flag and echoes the path as typed otherwise. **Returns:** the
    folders created, deepest first (`remove_empty_folders` takes them back where the command
    then refuses its input)."""
    check_no_clash(args, command)
    created = []
    for dest, flag, kind, example in output_flags(command):
        text = getattr(args, dest, None)
        if text is None:
            continue
        if not str(text).strip():
            raise ValueError(f"{flag}: empty path; give a {'folder' if kind == 'folder' else 'file name'}.")
        path = pathlib.Path(text)
        if kind != "folder" and (path.is_dir() or str(text).endswith(("/", os.sep))):
            raise ValueError(f"{flag} {text}: is a folder; give a file name, e.g. {path / example}.")
        if kind == "folder" and path.exists() and not path.is_dir():
            raise ValueError(f"{flag} {text}: is a file; give a folder (it is created if missing).")
        suffixes = _FILE_SUFFIXES.get((command, flag), _FILE_SUFFIXES.get((None, flag)))
        if suffixes is not None and path.suffix.lower() not in suffixes:
            raise ValueError(f"{flag} {text}: writes a {suffixes[0][1:].upper()} file; end the name in "
                             f"{' or '.join(suffixes)}, e.g. {path.with_suffix(suffixes[0]).name}.")
        if kind == "image" and path.suffix.lower() not in _IMAGE_SUFFIXES:
            raise ValueError(f"{flag} {text}: unknown image format {path.suffix or '(no suffix)'!r}; "
                             f"end the name in {', '.join(_IMAGE_SUFFIXES[:3])}.")
        above = path.parent if kind != "folder" else path
        while not above.exists() and above != above.parent:
            above = above.parent
        if not above.is_dir():
            raise ValueError(f"{flag} {text}: cannot write results there, {above} is a file, not a folder.")
        if not os.access(above, os.W_OK | os.X_OK) or (path.exists() and not os.access(path, os.W_OK)):
            raise ValueError(f"{flag} {text}: cannot write results there (permission denied).")
        folder = path if kind == "folder" else path.parent
        missing = [folder, *folder.parents][:len(folder.parents) + 1]
        created += [f for f in missing if not f.exists()]
        folder.mkdir(parents=True, exist_ok=True)
    return sorted(set(created), key=lambda f: len(f.parts), reverse=True)


def remove_empty_folders(folders) -> None:
    """Remove those of `folders` (deepest first) that are still empty: the output folders a
    command created before it refused its input, so that a refused command leaves nothing."""
    for folder in folders:
        try:
            folder.rmdir()
        except OSError:  # not empty (the command wrote there), or gone
            pass
