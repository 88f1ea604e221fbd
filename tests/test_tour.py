"""The README's tour runs as written, in order, in an empty folder, and writes the pictures it
names (`teflon-jax` is `python -m teflon_jax.cli` here). The set-up block stays two commands.

The whole tour (Monte Carlo of 1,000 motions, a design, a diagnosis) takes minutes: it is
marked slow. The fast test runs the tour's first command (the figure-eight test whose record the
fit reads) and checks that its compiled programs went to the cache folder.
"""

import os
import pathlib
import re
import shlex
import subprocess
import sys

import pytest

README = pathlib.Path(__file__).resolve().parent.parent / "README.md"


def _blocks(heading: str) -> list[str]:
    """The ```bash blocks of the README section `heading`."""
    text = README.read_text()
    start = text.index(f"## {heading}")
    end = text.find("\n## ", start + 1)
    section = text[start:end if end > 0 else None]
    return re.findall(r"```bash\n(.*?)```", section, flags=re.DOTALL)


def tour_commands() -> list[list[str]]:
    """Each command of the tour as an argv (continuation lines joined, comments dropped)."""
    commands = []
    for block in _blocks("A short tour"):
        for line in block.replace("\\\n", " ").splitlines():
            words = shlex.split(line, comments=True)
            if words:
                commands.append(words)
    return commands


def _run(words, folder, cache):
    assert words[0] == "teflon-jax", words
    env = dict(os.environ, XDG_CACHE_HOME=str(cache), PYTHONPATH=str(README.parent))
    env.pop("XLA_FLAGS", None)
    done = subprocess.run([sys.executable, "-m", "teflon_jax.cli", *words[1:]], cwd=folder, env=env,
                          capture_output=True, text=True, timeout=1800)
    assert done.returncode == 0, f"{shlex.join(words)} exited {done.returncode}:\n{done.stderr[-3000:]}"
    for word in words:
        if word.endswith(".png"):
            assert (folder / word).stat().st_size > 10_000, f"{shlex.join(words)} did not write {word}"
    return done


def test_readme_has_two_setup_commands_and_a_tour():
    setup = [line for block in _blocks("Start here") for line in block.splitlines()
             if line.strip() and not line.lstrip().startswith("#")]
    assert len(setup) == 2, setup
    assert "pip install -e ." in setup[0] and "teflon-jax reproduce" in setup[0]
    assert '".[test]"' in setup[1] and "pytest" in setup[1]
    names = [c[1] for c in tour_commands()]
    assert {"simulate-test", "fit", "diagnose", "montecarlo", "design"} <= set(names)
    # every file a later step reads is written by an earlier step
    written = set()
    for words in tour_commands():
        for i, word in enumerate(words):
            if (word.endswith(".csv") and words[i - 1] != "--out") or words[i - 1] == "--bearing":
                assert word in written, f"{word} is read before a step writes it"
            if i and words[i - 1] in ("--out", "--json", "--plot", "--save-bearing"):
                written.add(word)


def test_tour_first_step_runs_and_writes_its_picture(tmp_path):
    first = tour_commands()[0]
    assert first[1] == "simulate-test" and "eight.png" in first
    _run(first, tmp_path, tmp_path / "cache")
    assert (tmp_path / "eight.csv").stat().st_size > 0
    assert any((tmp_path / "cache" / "teflon-jax" / "jax").iterdir()), "no compiled program was cached"


@pytest.mark.slow
def test_whole_tour_runs_in_order_in_an_empty_folder(tmp_path):
    folder = tmp_path / "tour"
    folder.mkdir()
    for words in tour_commands():
        _run(words, folder, tmp_path / "cache")
