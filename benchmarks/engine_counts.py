"""Counts of the engine structure of a checkout: how many times the model space above the
bearing law is written out.

`python benchmarks/engine_counts.py [ROOT ...]` prints, for each checkout (default: this one),
- the modules of `teflon_jax/systems/`;
- the modules of `systems/` and `cli/` named after one isolator, structure, load or number of
  components (`triple`, `double`, `pendulum`, `series`, `slab`, `vertical`, `bidirectional`,
  `biaxial` in the file name);
- the lines that branch on an isolator's name (`isolator ==` or `!=`);
- the places that spell an isolator's name as a string literal ("triple-fp", "double-fp");
- the hand-written implicit derivatives (`custom_jvp`);
- the response types of `systems/` (classes whose name ends in `Response` or `Result`);
- the stepped systems of `systems/` (classes with a `step`, `newmark_update` or `propagated_step`
  method: system types and the step strategies they take), and the stepped system types (classes
  that derive from `AbstractSteppedSystem`: the structures and the bearing test's actuator);
- the equilibrium iterations of `systems/`, `elements/` and `solver/` (`while_loop` call sites);
- the history drivers (functions of `systems/` that `scan` and are named `simulate_*`,
  `*_history` or `*_histories`) and the peak drivers (functions of `systems/` and `studies/` that `scan` and are
  named after peaks or uplift);
- the structure history functions, the imposed-path test functions and the structure builders
  `teflon_jax.systems` exports (functions that return a `StructureResponse`, a
  `BearingTestResult`, or a stepped structure, by their annotation or their docstring's
  **Returns:**);
- the tables keyed by isolator name (dict literals with "flat", "single-fp", "triple-fp" or
  "double-fp" as a key), and the modules whose code (docstrings aside) spells an isolator's name
  as a string of its own: the places the isolators are listed.
Nothing is run: the counts are read from the files.
"""

import ast
import pathlib
import re
import sys

VARIANT_WORDS = ("triple", "double", "pendulum", "series", "slab", "vertical", "bidirectional",
                 "biaxial")
BRANCH = re.compile(r"isolator\s*[!=]=")
NAME_LITERAL = re.compile(r"[\"'](?:triple|double)-fp[\"']")
CUSTOM_JVP = re.compile(r"^@.*custom_jvp", re.MULTILINE)
RESPONSE_CLASS = re.compile(r"^class\s+\w*(?:Response|Result)\b", re.MULTILINE)


def _modules(folder: pathlib.Path) -> list[pathlib.Path]:
    return sorted(p for p in folder.glob("_*.py") if p.name != "__init__.py")


STEP_METHODS = {"step", "newmark_update", "propagated_step"}


def _stepped_systems(text: str, types_only: bool = False) -> int:
    classes = [n for n in ast.walk(ast.parse(text)) if isinstance(n, ast.ClassDef)]
    typed = [any(ast.unparse(b).endswith("AbstractSteppedSystem") for b in c.bases) for c in classes]
    stepping = [bool(STEP_METHODS & {f.name for f in c.body if isinstance(f, ast.FunctionDef)}) for c in classes]
    return sum(typed if types_only else stepping)


def _scanning(text: str, named) -> int:
    functions = [n for n in ast.walk(ast.parse(text)) if isinstance(n, ast.FunctionDef)]
    return sum(1 for f in functions if named(f.name) and "scan(" in ast.unparse(f))


def _is_history(name: str) -> bool:
    return name.startswith("simulate_") or name.endswith(("_histories", "_history"))


def _is_peaks(name: str) -> bool:
    return "peak" in name or "uplift" in name


ISOLATOR_NAMES = {"flat", "single-fp", "triple-fp", "double-fp"}


def _name_tables(text: str) -> int:
    """Dict literals with an isolator's name as a key."""
    return sum(1 for n in ast.walk(ast.parse(text)) if isinstance(n, ast.Dict) and any(
        isinstance(k, ast.Constant) and k.value in ISOLATOR_NAMES for k in n.keys))


def _spells_a_name(text: str) -> bool:
    """Whether the code (docstrings aside) spells an isolator's name as a string of its own."""
    tree = ast.parse(text)
    docs = {id(node.body[0].value) for node in ast.walk(tree)
            if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef)) and node.body
            and isinstance(node.body[0], ast.Expr) and isinstance(node.body[0].value, ast.Constant)}
    docs |= {id(b.value) for node in ast.walk(tree) if hasattr(node, "body") and isinstance(node.body, list)
             for a, b in zip(node.body, node.body[1:]) if isinstance(a, (ast.Assign, ast.AnnAssign))
             and isinstance(b, ast.Expr) and isinstance(b.value, ast.Constant)}  # attribute docstrings
    return any(isinstance(n, ast.Constant) and n.value in ISOLATOR_NAMES and id(n) not in docs
               for n in ast.walk(tree))


STRUCTURE_TYPES = ("StructureOnSliders", "BidirectionalStructure")  # the second on older trees
"""The stepped structures' types, whose builders `counts` counts."""


def _exported_returning(package: pathlib.Path, texts: dict, returns=("StructureResponse",)) -> int:
    """Functions exported by `systems/__init__.py` that return one of the types `returns` (by
    their annotation, or by their docstring's **Returns:** where it names one)."""
    exported = set(re.findall(r"import (\w+) as \1", texts[package / "systems" / "__init__.py"]))
    found = set()
    for path in _modules(package / "systems"):
        for f in ast.walk(ast.parse(texts[path])):
            if not (isinstance(f, ast.FunctionDef) and f.name in exported):
                continue
            annotation = "" if f.returns is None else ast.unparse(f.returns)
            returned = (ast.get_docstring(f) or "").partition("**Returns:**")[2]
            annotated = any(name in annotation for name in returns)
            documented = any(name in returned for name in returns)
            if annotated or documented:
                found.add(f.name)
    return len(found)


def counts(root: pathlib.Path) -> dict:
    package = root / "teflon_jax"
    sources = sorted(package.rglob("*.py"))
    texts = {path: path.read_text() for path in sources}
    systems = _modules(package / "systems")
    variant = [p for folder in ("systems", "cli") for p in _modules(package / folder)
               if any(word in p.stem for word in VARIANT_WORDS)]
    return {
        "modules in systems/": len(systems),
        "lines in systems/": sum(len(texts[p].splitlines()) for p in systems),
        "systems/ and cli/ modules named per variant": len(variant),
        "lines branching on the isolator's name": sum(len(BRANCH.findall(t)) for t in texts.values()),
        "isolator names as string literals": sum(len(NAME_LITERAL.findall(t)) for t in texts.values()),
        "custom_jvp": sum(len(CUSTOM_JVP.findall(t)) for t in texts.values()),
        "response types in systems/": sum(len(RESPONSE_CLASS.findall(texts[p])) for p in systems),
        "stepped systems (classes with a step) in systems/": sum(_stepped_systems(texts[p]) for p in systems),
        "stepped system types in systems/": sum(_stepped_systems(texts[p], True) for p in systems),
        "while_loop iterations in systems/, elements/, solver/": sum(
            texts[p].count("while_loop(") for p in _modules(package / "systems") + _modules(package / "elements")
            + _modules(package / "solver")),
        "history drivers in systems/": sum(_scanning(texts[p], _is_history) for p in systems),
        "peak drivers in systems/, studies/": sum(
            _scanning(texts[p], _is_peaks) for p in systems + _modules(package / "studies")),
        "structure history functions exported by systems": _exported_returning(package, texts),
        "imposed-path test functions exported by systems": _exported_returning(package, texts,
                                                                              ("BearingTestResult",)),
        "structure builders exported by systems": _exported_returning(package, texts, STRUCTURE_TYPES),
        "tables keyed by isolator name": sum(_name_tables(t) for t in texts.values()),
        "modules that list an isolator by its name": sum(_spells_a_name(t) for t in texts.values()),
        "variant modules": ", ".join(f"{p.parent.name}/{p.name}" for p in variant),
    }


def main(argv=None) -> int:
    roots = [pathlib.Path(a) for a in (argv if argv is not None else sys.argv[1:])] or [pathlib.Path(".")]
    table = {str(root): counts(root) for root in roots}
    keys = list(next(iter(table.values())))
    for key in keys[:-1]:
        print(f"{key:58s}" + "".join(f"{row[key]:>14}" for row in table.values()))
    for root, row in table.items():
        print(f"\n{root}: {row['variant modules']}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
