"""The documentation: the site builds without warnings, and every tutorial runs as written.

A tutorial (docs/tutorials/*.md) is run the way a reader would follow it: its ```bash blocks,
in order, in one empty folder, with `teflon-jax` and `python` of this interpreter's
environment first on PATH. A ```text block right after a ```bash block is that block's output
as the page quotes it: each of its lines must be a line the commands printed (`...` in a
quoted line stands for any text, e.g. a run time), so the numbers a page quotes cannot go
stale. Blocks in other languages (```sh, ```python) are shown, not run.

The site is built with `mkdocs build --strict` (warnings fail it): broken links, pages
missing from the navigation and API docstrings that mkdocstrings cannot render.
"""

import os
import pathlib
import re
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent
TUTORIALS = ROOT / "docs" / "tutorials"
# Pages that take more than about a minute on two cores run only with the slow tests, and
# so do the Monte Carlo page (about 80 s) and the records page (about 25 s): fit.md keeps
# this runner in the fast set; the `montecarlo` command under the page's flags runs in
# tests/test_cli.py and tests/test_montecarlo_*.py, the record formats in
# tests/test_records.py and tests/test_ground_motion.py.
SLOW = {"bearing-file.md", "design.md", "diagnose.md", "montecarlo.md", "pendulum.md",
        "records.md"}
_BLOCK = re.compile(r"^```(\w*)[^\n]*\n(.*?)^```", flags=re.DOTALL | re.MULTILINE)


def page_steps(text: str) -> list[tuple[str, list[str]]]:
    """[(bash script, quoted output lines)] of a tutorial page's text, in order."""
    steps = []
    for language, body in _BLOCK.findall(text):
        if language == "bash":
            steps.append((body, []))
        elif language == "text" and steps and not steps[-1][1]:
            steps[-1][1].extend(line.strip() for line in body.splitlines() if line.strip())
    return steps


def _pattern(quoted: str) -> re.Pattern:
    """A quoted output line as a pattern: `...` is any text, runs of spaces are any spaces."""
    parts = [r"\s+".join(map(re.escape, piece.split())) for piece in quoted.split("...")]
    return re.compile(r"^\s*" + ".*".join(parts) + r"\s*$")


def _environment(cache: pathlib.Path) -> dict:
    env = dict(os.environ, XDG_CACHE_HOME=str(cache), PYTHONPATH=str(ROOT), MPLBACKEND="Agg")
    env["PATH"] = os.pathsep.join([str(pathlib.Path(sys.executable).parent), env.get("PATH", "")])
    env.pop("XLA_FLAGS", None)
    return env


def _check_output(page: str, script: str, output: str, quoted: list[str]) -> None:
    lines = output.splitlines()
    for line in quoted:
        pattern = _pattern(line)
        assert any(pattern.match(printed) for printed in lines), (
            f"{page}: the page quotes\n  {line}\nbut the commands\n{script}\nprinted\n{output[-4000:]}"
        )


def run_tutorial(page: pathlib.Path, folder: pathlib.Path, cache: pathlib.Path) -> None:
    """Run the page's bash blocks in order in `folder` and check the output each quotes."""
    steps = page_steps(page.read_text())
    assert steps, f"{page.name} has no ```bash block to run"
    env = _environment(cache)
    for script, quoted in steps:
        done = subprocess.run(["bash", "-euo", "pipefail", "-c", script], cwd=folder, env=env,
                              capture_output=True, text=True, timeout=1200)
        output = done.stdout + done.stderr
        assert done.returncode == 0, f"{page.name}: exit {done.returncode} from\n{script}\n{output[-4000:]}"
        _check_output(page.name, script, output, quoted)


def _pages(slow: bool) -> list[str]:
    names = sorted(path.name for path in TUTORIALS.glob("*.md"))
    return [name for name in names if (name in SLOW) == slow]


@pytest.fixture(scope="module")
def compile_cache(tmp_path_factory):
    return tmp_path_factory.mktemp("cache")


@pytest.mark.parametrize("name", _pages(slow=False))
def test_tutorial_runs_as_written(name, tmp_path, compile_cache):
    run_tutorial(TUTORIALS / name, tmp_path, compile_cache)


@pytest.mark.slow
@pytest.mark.parametrize("name", _pages(slow=True))
def test_long_tutorial_runs_as_written(name, tmp_path, compile_cache):
    run_tutorial(TUTORIALS / name, tmp_path, compile_cache)


def test_every_tutorial_is_in_the_navigation():
    nav = (ROOT / "mkdocs.yml").read_text()
    for path in TUTORIALS.glob("*.md"):
        assert f"tutorials/{path.name}" in nav, f"{path.name} is not in mkdocs.yml's nav"
    assert SLOW <= {path.name for path in TUTORIALS.glob("*.md")}


def test_quoted_output_patterns():
    assert _pattern("a ... b  1.5").match("a 12.0 s b 1.5")
    assert not _pattern("f_max = 0.1193").match("f_max = 0.1194")
    steps = page_steps("```bash\necho 1\n```\n\n```text\n1\n```\n```bash\necho 2\n```\n")
    assert steps == [("echo 1\n", ["1"]), ("echo 2\n", [])]


def test_site_builds_without_warnings(tmp_path):
    pytest.importorskip("mkdocs", reason="the `docs` extra (pip install -e '.[docs]') builds the site")
    pytest.importorskip("mkdocstrings_handlers.python")
    done = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(tmp_path / "site")],
        cwd=ROOT, env=dict(os.environ, PYTHONPATH=str(ROOT), NO_MKDOCS_2_WARNING="1"),
        capture_output=True, text=True, timeout=600,
    )
    log = done.stdout + done.stderr
    assert done.returncode == 0, log[-6000:]
    assert "WARNING" not in log, log[-6000:]
    for page in ("index.html", "physics/index.html", "api/bearing/index.html", "tutorials/fit/index.html"):
        assert (tmp_path / "site" / page).is_file(), page
    # mkdocstrings rendered the re-exported names, not only the package headings
    assert "SlidingBearing" in (tmp_path / "site" / "api" / "bearing" / "index.html").read_text()


def test_user_documents_do_not_tell_how_the_project_was_developed():
    words = re.compile(r"\bthis round\b|\bprevious round|\bround that\b|\blent\b|\bissue #?\d+",
                       flags=re.IGNORECASE)
    pages = [ROOT / "README.md", ROOT / "benchmarks" / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
    for page in pages:
        for number, line in enumerate(page.read_text().splitlines(), start=1):
            assert not words.search(line), f"{page.relative_to(ROOT)}:{number}: {line}"


def test_readme_python_example_runs_in_an_empty_folder(tmp_path, compile_cache):
    """The README's Python example (its shell commands are tests/test_tour.py's)."""
    blocks = _BLOCK.findall((ROOT / "README.md").read_text())
    code = [body for language, body in blocks if language == "python"]
    assert len(code) == 1, "the README has one Python example"
    done = subprocess.run([sys.executable, "-c", code[0]], cwd=tmp_path, env=_environment(compile_cache),
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-4000:]
