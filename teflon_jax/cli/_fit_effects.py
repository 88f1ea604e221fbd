"""`teflon-jax fit RECORD --effects NAME,...`: fit a chosen composition of the bearing model.

The model is Eq. 1 with Bouc-Wen plus the named optional parts (the effect names of
`diagnose`), fitted to one record from several starts by the solver discovery uses; the JSON
has the parameters with standard errors (SI), the nrmse and the convergence of the fit.
"""

import sys

from ._bearing_flags import check_output_file, save_bearing_flag
from ._common import _write_json, parse_name_values, read_bearing_record, read_quantities
from ._diagnose import known_dimensions, with_normal_load
from ._isolator_flags import check_normal_load_used


def _effect_names(text: str) -> list[str]:
    from identification.discovery import EFFECT_NAMES

    names = [name.strip() for name in text.split(",") if name.strip()]
    if text.strip() == "list" or not names:
        raise ValueError("--effects: give one or more of " + ", ".join(EFFECT_NAMES) + ".")
    unknown = [name for name in names if name not in EFFECT_NAMES]
    if unknown:
        raise ValueError(f"--effects: unknown effect(s) {', '.join(unknown)}; the known "
                         f"effects are {', '.join(EFFECT_NAMES)}.")
    return names


def run_fit_effects(args) -> int:
    """Run `fit --effects`; 0 converged, 1 not converged, 2 bad input."""
    from identification.discovery import discover_effects

    try:
        read_quantities(args, "fit")
        check_output_file(args.save_bearing, "--save-bearing")
        check_output_file(args.json, "--json")
        effects = _effect_names(args.effects)
        if len(args.records) != 1:
            raise ValueError(f"--effects: fits one record; got {len(args.records)} "
                             f"({', '.join(args.records)}).")
        for flag, value in (("--free", args.free), ("--bayes", args.bayes),
                            ("--plot", args.plot)):
            if value is not None:
                raise ValueError(f"{flag}: not available with --effects (every constant of the "
                                 "named parts is fitted; hold some with --fixed).")
        known = parse_name_values(args.fixed, known_dimensions(), "--fixed")
        record = read_bearing_record(args.records[0])
        check_normal_load_used(args, [record], args.records)
        record = with_normal_load(record, args.records[0], args.normal_load)
        composition = ["velocity_dependence", *[e for e in effects if e != "velocity_dependence"]]
        result = discover_effects(record, baseline=tuple(composition), max_effects=0,
                                  known=known)
    except (ValueError, FileNotFoundError) as error:
        print(f"teflon-jax fit: error: {error}", file=sys.stderr)
        return 2
    converged = bool(result.fit_convergence.get("final_converged", False))
    document = {"effects": result.effects, "parameters": result.parameters,
                "std_errors": result.std_errors, "nrmse": result.nrmse_final,
                "converged": converged, "fit_convergence": dict(result.fit_convergence),
                "units": "SI", "record": str(args.records[0])}
    _write_json(args.json, document)
    save_bearing_flag(args, result.bearing(), standard_errors=result.bearing_errors(),
                      sources=args.records,
                      fit={"command": "fit --effects", "effects": result.effects,
                           "nrmse": result.nrmse_final, "converged": converged})
    shown = ", ".join(f"{k} = {v:.5g}" for k, v in result.parameters.items())
    status = _status(result.fit_convergence, converged)
    print(f"{', '.join(result.effects)}: {shown}; nrmse = {result.nrmse_final:.4f} [-] (SI); "
          f"{status}", file=sys.stderr)
    return 0 if converged else 1


def _status(log: dict, converged: bool) -> str:
    """The fit's status in words: converged (a minimum of the misfit, however large, within
    the step budget), with how many of the other solves (starts) ran out of steps; or NOT
    CONVERGED (exit status 1)."""
    limit = log.get("iteration_limit")
    if not converged:
        return (f"NOT CONVERGED: the least-squares solve reached its limit of {limit} steps before a "
                "minimum; the constants are no result (exit status 1)")
    others = log.get("unconverged", 0)
    return "converged" + (f" ({others} of its {log.get('fits')} solves stopped at the limit of {limit} "
                          "steps)" if others else "")
