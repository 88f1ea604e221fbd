"""`teflon-jax diagnose`: one flow for every isolator, its parser built without JAX."""

import subprocess
import sys

from identification.discovery import BASELINES, EFFECT_NAMES
from teflon_jax.cli import _diagnose
from teflon_jax.cli._isolator_flags import ISOLATORS

HEAVY = ("jax", "diffrax", "optimistix", "equinox", "numpyro", "matplotlib", "identification")


def test_the_help_answers_without_jax():
    code = ("import sys\nfrom teflon_jax.cli import main\ntry:\n    main(['diagnose', '--help'])\n"
            "except SystemExit as stop:\n    assert stop.code == 0, stop.code\n"
            f"print(sorted(m for m in {HEAVY!r} if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert "usage: teflon-jax diagnose" in done.stdout
    assert done.stdout.strip().splitlines()[-1] == "[]"


def test_the_help_lists_the_effects_and_baselines_of_the_search():
    assert _diagnose.EFFECT_NAMES == EFFECT_NAMES
    assert _diagnose.BASELINES == tuple(BASELINES)


def test_every_isolator_has_one_row_and_the_series_pendulums_share_theirs():
    assert set(_diagnose.DIAGNOSES) == set(ISOLATORS)
    rows = _diagnose.DIAGNOSES
    assert rows["triple-fp"] is rows["double-fp"] and rows["triple-fp"].isolator_file
    assert rows["single-fp"].restoring_force and not rows["flat"].restoring_force
    assert rows["flat"].search is rows["single-fp"].search
    refused = {flag for flag, _, _ in rows["flat"].refused}
    assert {"--radius", "--isolator-file", "--save-isolator"} <= refused
