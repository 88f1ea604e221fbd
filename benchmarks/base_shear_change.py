"""The one-component building's Monte Carlo base shear ratio, before and after it became the
whole base shear: `PYTHONPATH=<tree> python benchmarks/base_shear_change.py` prints, for flat
sliders and a triple pendulum (benchmarks/triple_isolator.json), each motion's `base_shear_ratio`
of `monte_carlo` and, where the tree has them, the reducers over the saved history of the same
system and motion (`response_peaks`: the whole base shear and the first-storey shear)."""

import json
from pathlib import Path

import jax

jax.config.update("jax_enable_x64", True)

from teflon_jax.excitation import StochasticGroundMotion, uniform_signal  # noqa: E402
from teflon_jax.formats import load_isolator  # noqa: E402
from teflon_jax.studies import monte_carlo, monte_carlo_motion  # noqa: E402
from teflon_jax.systems import isolated_structure, simulate_history  # noqa: E402

MOTIONS, DT = 3, 0.01
MODEL = StochasticGroundMotion(peak_ground_acceleration=2.94, duration=8.0, time_step=DT,
                               strong_motion_duration=4.0)
KEY = jax.random.key(5)
out = {}
for name, options in (("flat", {}), ("triple-fp", {"isolator": load_isolator(Path(__file__).with_name(
        "triple_isolator.json"))})):
    structure = isolated_structure("building", **options)
    result = monte_carlo(structure, MODEL, MOTIONS, key=KEY)
    row = {"montecarlo": result.base_shear_ratio.tolist()}
    try:
        from teflon_jax.studies import response_layout, response_peaks
    except ImportError:
        response_peaks = None
    if response_peaks is not None:
        reduced = []
        for i in range(MOTIONS):
            system = structure(uniform_signal(monte_carlo_motion(MODEL, KEY, i), DT))
            peaks = response_peaks(response_layout(system), simulate_history(system, (MODEL.duration)))
            reduced.append({k: float(peaks[k]) for k in ("base_shear_ratio_resultant",
                                                         "first_storey_shear_ratio_resultant")})
        row["reducers"] = reduced
    out[name] = row
print(json.dumps(out, indent=1))
