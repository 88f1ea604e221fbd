"""The compiled programs' text, for showing that a change leaves a structure's run untouched.

`python benchmarks/program_hashes.py` lowers the planar peak driver (`peak_response`
of the rigid mass and the Table 2 building, on flat sliders and on single pendulums, 20 s of a
two-component record) and the one-component batch of a study (`expected_response` of the same
structures under 4 records of 20 s, B3's kind of run), and the same peak runs on B7's triple
pendulum (`bench_pendulum.TRIPLE`) in one and two components, and prints the SHA-256 of each lowered
program's text, its source locations removed. Run it under two versions (`PYTHONPATH=/path/to/other/checkout`): equal hashes mean XLA
compiles the same program, so the records per second and every number are the same.
"""

import hashlib
import re

import jax
import numpy as np

jax.config.update("jax_enable_x64", True)

from bench_pendulum import TRIPLE  # noqa: E402
from engine_numbers import one_surface_keywords  # noqa: E402  (the same isolator keywords under both versions)

from teflon_jax.excitation import uniform_signal  # noqa: E402
from teflon_jax.studies import bidirectional_isolated_structure, expected_response  # noqa: E402
from teflon_jax.systems import isolated_structure, peak_response  # noqa: E402
from teflon_jax.units import PSI  # noqa: E402


def program_hash(structure, record, components: int = 2) -> tuple[str, int]:
    """SHA-256 (first 16 hex digits) and length of the lowered peak run's text."""
    def run(a, b):
        ground = (uniform_signal(a, 0.01), uniform_signal(b, 0.01))
        return peak_response(structure(ground if components == 2 else ground[0]), 20.0)

    text = jax.jit(run).lower(record, record).as_text()
    text = re.sub(r"#loc\d*|loc\(.*?\)", "", text)
    return hashlib.sha256(text.encode()).hexdigest()[:16], len(text)


def main():
    record = 3.0 * np.sin(np.arange(2001) * 0.01)
    for kind in ("rigid", "building"):
        for isolator, radius in (("flat", None), ("single-fp", 1.5)):
            structure = bidirectional_isolated_structure(kind, **one_surface_keywords(isolator, radius))
            digest, size = program_hash(structure, record)
            print(f"{kind:9s} {isolator:10s} {digest} ({size} characters)")
    records = np.stack([(1 + 0.1 * i) * record for i in range(4)])
    for kind in ("rigid", "building"):
        for isolator, radius in (("flat", None), ("single-fp", 1.5)):
            structure = isolated_structure(kind, pressure=1000 * PSI, **one_surface_keywords(isolator, radius))

            def batch(r, structure=structure):
                return expected_response(structure, {"pressure": 1500 * PSI}, r, 0.01)

            text = re.sub(r"#loc\d*|loc\(.*?\)", "", jax.jit(batch).lower(records).as_text())
            print(f"{kind:9s} {isolator:10s} one component, 4 records: "
                  f"{hashlib.sha256(text.encode()).hexdigest()[:16]} ({len(text)} characters)")
    for kind in ("rigid", "building"):
        for components, build in ((1, isolated_structure), (2, bidirectional_isolated_structure)):
            digest, size = program_hash(build(kind, isolator=TRIPLE, time_step=0.005), record, components)
            print(f"{kind:9s} triple-fp  {'one component' if components == 1 else 'two components'}: "
                  f"{digest} ({size} characters)")


if __name__ == "__main__":
    main()
