"""`simulate-test --isolator single-fp --radius R`: the test of a single friction pendulum.

The slider on a spherical surface of radius R resists with the liner's friction and the
restoring force of the surface (small rotations, Zayas, Low & Mahin 1990):

    F = N u / R + mu(v) N Z,

with the friction part mu N Z that of the flat slider of the same liner (Eq. 1, Bouc-Wen /
Park's Z; Constantinou, Mokha & Reinhorn 1990); in two directions N u / R acts along each
displacement component. `fit --isolator single-fp` recovers R and the friction constants from
such a record.
"""

import numpy as np

from ..units import STANDARD_GRAVITY
from ._common import ISOLATORS, add_quantity
from ._triple import SERIES_ISOLATORS, _load


def add_pendulum_test_flags(parser) -> None:
    """`--isolator flat|single-fp|triple-fp|double-fp` and `--radius R` of `simulate-test`."""
    parser.add_argument("--isolator", default="flat", choices=ISOLATORS,
                        help="a flat slider, or a single friction pendulum: the slider on a "
                        "concave surface of --radius, force N u / R + friction (default flat)")
    add_quantity(parser, "--radius", "length", None, "with --isolator single-fp: radius of "
                 "curvature R of the concave surface, e.g. 88in", minimum=0.0)


def check_pendulum_test_flags(args) -> float | None:
    """The radius R [m] of `--isolator single-fp` (None for a flat slider), with the flags
    checked before any work: `ValueError` naming the flag."""
    if args.isolator == "flat":
        if args.radius is not None:
            raise ValueError("--radius: applies to --isolator single-fp only (a flat slider has no "
                             "radius); add --isolator single-fp or leave --radius out.")
        return None
    if args.isolator in SERIES_ISOLATORS:
        if args.isolator_file is None:
            raise ValueError(f"--isolator-file: --isolator {args.isolator} needs the isolator file of its "
                             "surfaces (radius, capacity and friction of each; docs/formats.md), e.g. "
                             f"--isolator-file {'tfp' if args.isolator == 'triple-fp' else 'dfp'}.json.")
        _load(args.isolator_file, args.isolator)  # a file of the other pendulum is refused by name
        return None
    if args.isolator_file is not None:
        raise ValueError(f"--isolator: the isolator comes from --isolator-file {args.isolator_file} "
                         "(a triple or double pendulum, as the file says); leave --isolator single-fp out.")
    if args.radius is None:
        raise ValueError("--radius: --isolator single-fp needs the radius of its concave surface, "
                         "e.g. --radius 88in.")
    return float(args.radius)


def pendulum_result(result, radius: float | None):
    """`result` (a `BearingTestResult`) with the surface's N u / R added to fx and fy
    (unchanged for a flat slider, `radius` None)."""
    import equinox as eqx

    if radius is None:
        return result
    load = result.normal_load
    return eqx.tree_at(lambda r: (r.fx, r.fy), result,
                       (result.fx + load * result.ux / radius, result.fy + load * result.uy / radius))


def pendulum_metadata(metadata: dict, radius: float | None, radius_text) -> dict:
    """The record's metadata of a pendulum test: its specimen and source say so."""
    if radius is None:
        return metadata
    period = 2 * np.pi * np.sqrt(radius / STANDARD_GRAVITY)
    return {**metadata,
            "specimen": f"single friction pendulum, R = {radius_text} (T = {period:.4g} s), "
                        + metadata["specimen"].replace("flat slider", "liner"),
            "source": metadata["source"] + "; restoring force N u / R (Zayas, Low & Mahin 1990)"}
