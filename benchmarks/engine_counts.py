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
- the response types of `systems/` (classes whose name ends in `Response` or `Result`).
Nothing is run: the counts are read from the files.
"""

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
        "variant modules": ", ".join(f"{p.parent.name}/{p.name}" for p in variant),
    }


def main(argv=None) -> int:
    roots = [pathlib.Path(a) for a in (argv if argv is not None else sys.argv[1:])] or [pathlib.Path(".")]
    table = {str(root): counts(root) for root in roots}
    keys = list(next(iter(table.values())))
    for key in keys[:-1]:
        print(f"{key:48s}" + "".join(f"{row[key]:>14}" for row in table.values()))
    for root, row in table.items():
        print(f"\n{root}: {row['variant modules']}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
