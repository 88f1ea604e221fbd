"""`teflon-jax design`: gradient-based design of the isolation system. Its grid sweep runs in
this process, or with `--scheduler local:N|ADDRESS` as chunks of design points on a Dask
cluster (`teflon_jax.studies.design_sweep_distributed`); `--out FILE.nc` keeps the sweep."""

import argparse
import sys
import time

from ..units import STANDARD_GRAVITY
from ._bearing_flags import add_bearing_flag, read_bearing_flag
from ._common import (
    _positive_int,
    _write_json,
    add_cluster_flags,
    add_quantity,
    check_table1,
    integer_at_least,
    output_units,
    warn_time_step,
)
from ._design_variables import (
    ISOLATOR_DESIGNS,
    add_design_variable_flags,
    design_fields,
    design_text,
    flag_error,
    lowered_start,
    plot_units,
    resolve_design_variables,
    restrained_options,
    structure_options,
)
from ._montecarlo import (
    _add_common,
    add_components_flags,
    check_components_flags,
    ground_motion_model,
)

HELP = "gradient-based design: minimise expected base shear under a displacement limit"
"""The line of this command in `teflon-jax --help`."""


def add_design_parser(subparsers) -> argparse.ArgumentParser:
    """`teflon-jax design --motions N --structure rigid|building --disp-limit 1.25in ...
    --json OUT.json --plot OUT.png`: minimise the expected base shear over T_b and pressure
    subject to a base-displacement limit."""
    parser = subparsers.add_parser(
        "design",
        help=HELP,
        description="BFGS over the design variables of --isolator, each within the bounds of "
        "its range flag: the isolation period of flat sliders, the radius R of a single "
        "friction pendulum (and its displacement capacity with --capacity-range), with the "
        "bearing pressure or f_max of either (--pressure holds the friction); scales of the "
        "radii and capacities and f_max of the surfaces of a triple or double pendulum's "
        "--isolator-file; under motions of one horizontal component, or of two with "
        "--components 2 (the peaks then resultants); started from "
        "the best point of a grid sweep of the same objective, with a gradient check at the "
        "optimum against central differences. BFGS sees smoothed peaks, which lie below the "
        "true ones; the limit on them is lowered until the mean TRUE peak base displacement "
        "(or its 95th percentile over the motions, --limit-statistic p95) meets --disp-limit. "
        "Exits with status 1 when the reported design breaks --disp-limit, "
        "a simulation did not converge or the gradient check fails (one-sided, from each side "
        "of the kink, where a designed capacity sits at the largest peak's restrainer contact; "
        "one-sided on the optimum's own side where a kink is found inside a failed central "
        "stencil); "
        "warns when the optimum lies on a bound.",
    )
    parser.add_argument("--motions", type=_positive_int, default=16, help="motions in the set (default 16)")
    _add_common(parser)
    add_components_flags(parser)
    # defaults: `teflon_jax.studies.default_design_problem()`, a problem whose limit binds
    add_quantity(parser, "--disp-limit", "length", "1.25in", "limit on the mean (over the motions) "
                 "of the true peak base displacement, or on its 95th percentile with "
                 "--limit-statistic p95", minimum=0.0)
    parser.add_argument("--limit-statistic", default="mean", choices=("mean", "p95"),
                        help="the statistic over the motions of the peak base displacement that "
                        "--disp-limit applies to: the mean, or the 95th percentile (linear "
                        "interpolation between the motions' peaks) (default mean)")
    add_design_variable_flags(parser)
    add_quantity(parser, "--isolation-damping", "dimensionless", None, "viscous damping ratio "
                 "zeta_b of the isolation system (default 5% on flat sliders, 0 on a friction "
                 "pendulum)", minimum=0.0, strict=False, maximum=1.0)
    parser.add_argument("--penalty", type=_penalty, default=100.0,
                        help="weight rho of the displacement-limit penalty, > 0 [-] (default 100)")
    parser.add_argument("--grid", type=_grid_points, default=7,
                        help="sweep points per variable, from LOW to HIGH of each range, at least 2 (default 7)")
    add_cluster_flags(
        parser, "evaluate the grid sweep as tasks", " (default: this process)",
        out="write the grid sweep (objective, mean smooth peaks, convergence on the grid of the design "
        "variables) as NetCDF; with --scheduler it streams there. Once BFGS ends, its 'objective' is "
        "the one grid_best is the least of, at the optimiser's lowered limit (attribute "
        "smooth_disp_limit_m); 'objective_at_disp_limit' keeps the sweep's, at --disp-limit as given",
        chunk_size="design points per compiled call, a task with --scheduler (default 16 on a CPU "
        "and on a cluster; on a GPU the largest power of two up to 65536 whose points, each over all "
        "the motions, fit in half its free memory); the same N gives the same sweep bit for bit here "
        "and on a cluster")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    add_bearing_flag(parser, replaces="--ptfe's Table 1 rows; the bearing needs a heating or "
                     "pressure-dependence part, whose contact pressure --pressure-range then spans")
    parser.set_defaults(command_function=run_design)
    return parser


def _penalty(text: str) -> float:
    """`--penalty`: a finite number > 0 (0 would drop the displacement limit, a negative one reward
    breaking it)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number > 0, got {text!r}") from None
    if not 0 < value < float("inf"):
        raise argparse.ArgumentTypeError(f"expected a finite number > 0 (the weight of the displacement "
                                         f"limit), got {text}")
    return value


def _grid_points(text: str) -> int:
    return integer_at_least(text, 2, "an integer >= 2 (the sweep runs from LOW to HIGH of each range)")


def run_design(args) -> int:
    """Run `teflon-jax design`; returns the exit status (0 ok; 1 when a simulation did not
    converge or the gradient at the optimum disagrees with central differences)."""
    import jax
    import numpy as np
    from tqdm import tqdm

    from ..excitation import sample, sample_two_components
    from ..studies import (
        check_netcdf_output,
        design_bounds,
        design_sweep,
        design_sweep_distributed,
        optimise_design,
        sweep_dataset,
        write_design_objective,
    )
    units = output_units(args.units)
    if args.scheduler is not None and args.out is None:
        raise ValueError("--scheduler: a distributed sweep streams its results to a file; add --out FILE.nc.")
    if args.out is not None:
        check_netcdf_output(args.out, "--out")  # before anything is computed
    check_components_flags(args)
    variables, structure = _variables_and_structure(args)
    if args.time_step is not None:
        warn_time_step("design", args.time_step, args.time_step_text, args.record_step, args.record_step_text)
    tic = time.perf_counter()
    stages = {}
    bar = tqdm(total=2, unit="stage", desc="design", disable=args.no_progress)
    draw = sample_two_components if args.components == 2 else sample
    records = draw(ground_motion_model(args), jax.random.key(args.seed), args.motions)
    dt = args.record_step
    grid = {name: np.linspace(*bounds, args.grid) for name, bounds in variables.items()}
    bar.set_postfix_str(f"grid sweep, {args.grid}x{args.grid} designs x {args.motions} motions")
    design = ISOLATOR_DESIGNS[args.isolator]
    attrs = {"structure": args.structure, "components": args.components, "isolator": args.isolator,
             "seed": args.seed, "pga_m_s2": args.pga,
             **({"isolator_file": str(args.isolator_file)} if design.uses_file else
                {"ptfe": args.ptfe} if args.bearing is None else {"bearing": str(args.bearing)}),
             "motion_duration_s": args.duration, "isolation_damping": args.isolation_damping,
             "limit_statistic": args.limit_statistic}
    if args.scheduler is None:
        from ..studies import device_chunk_size

        n_dof = (7 if structure.kind == "building" else 1) * args.components  # Table 2's storeys and the base
        batch = args.chunk_size or device_chunk_size(records.size, n_dof, cpu=16)
        sweep = design_sweep(structure, records, dt, grid=grid, disp_limit=args.disp_limit,
                             penalty=args.penalty, batch_size=batch, limit_statistic=args.limit_statistic)
        if args.out is not None:
            sweep_dataset(sweep, attrs={**attrs, "disp_limit_m": args.disp_limit,
                                        "penalty": args.penalty}).to_netcdf(args.out)
    else:
        from ._main import compile_cache_dir

        sweep = design_sweep_distributed(
            structure, records, dt, grid=grid, disp_limit=args.disp_limit, penalty=args.penalty,
            out=args.out, scheduler=args.scheduler, chunk_size=args.chunk_size or 16, attrs=attrs,
            limit_statistic=args.limit_statistic,
            compilation_cache=None if args.no_compile_cache else str(compile_cache_dir()))
    stages["grid"] = time.perf_counter() - tic
    bar.update(1)
    bar.set_postfix_str("BFGS from the best grid point")
    bounds = design_bounds(structure, variables)
    start = lowered_start(sweep, bounds, structure, records, dt, args.disp_limit, args.penalty,
                          args.limit_statistic)
    result = optimise_design(structure, records, dt, variables=variables, disp_limit=args.disp_limit,
                             penalty=args.penalty, start=start, limit_statistic=args.limit_statistic)
    if args.out is not None:  # the file's objective: the one grid_best is chosen by
        write_design_objective(args.out, sweep, result.smooth_disp_limit, args.penalty)
    bar.update(1)
    bar.close()
    stages.update(result.stages_s)
    payload = _payload(args, result, sweep, units, time.perf_counter() - tic)
    if design.percentile_check:
        payload.update(_percentile_check(args, structure, result, records))
        args.p95_rel_error = payload["p95_disp_gradient_rel_error"]
    if args.plot is not None:
        first = time.perf_counter()
        _plot(args, sweep, result, units)
        stages["plot"] = time.perf_counter() - first
    payload.update(wall_s=time.perf_counter() - tic, stages_s=stages)
    _write_json(args.json, payload)
    other = "95th percentile" if args.limit_statistic == "mean" else "mean"
    print(f"optimum: {design_text(result.optimum, units)}; {_STATISTIC[args.limit_statistic]} peak base "
          f"displacement {units.show(result.limited_disp, 'length')} against the limit {args.disp_limit_text} "
          f"({'met' if result.limit_met else 'BROKEN'}), {other} "
          f"{units.show(result.p95_peak_disp if other != 'mean' else result.peak_disp, 'length')}; "
          f"mean peak base shear / weight {result.peak_shear:.4g} (smoothed, as BFGS sees them: "
          f"{units.show(result.limited_smooth_disp, 'length')} against the lowered limit "
          f"{units.show(result.smooth_disp_limit, 'length')}, "
          f"{result.mean_shear:.4g}); {result.steps} BFGS steps; gradient check "
          f"{_CHECK_WORDS.get(result.gradient_check, '')}"
          f"{result.gradient_rel_error:.2g} relative; {payload['wall_s']:.1f} s")
    return _verdict(result, args)


def _plot(args, sweep, result, units) -> None:
    """`design.png` of `--plot`: the grid's objective with the optimum, and the trade-off."""
    from ..report import plot_design
    from ..studies import sweep_objective

    design = ISOLATOR_DESIGNS[args.isolator]
    isolator = design.words.format(file=args.isolator_file)
    friction = ("" if design.uses_file else f"{args.ptfe} PTFE, " if args.bearing is None
                else f"bearing {args.bearing}, ")
    stamp = (f"{args.structure} on {isolator}, {friction}zeta_b = {args.isolation_damping_text}, "
             f"{args.motions} {'two-component ' if args.components == 2 else ''}Clough-Penzien motions "
             f"(PGA {args.pga_text}, {args.duration_text}, "
             f"seed {args.seed}), limit {args.disp_limit_text} on the {_STATISTIC[args.limit_statistic]} "
             "peak displacement")
    # the grid's objective for the limit on the smoothed statistic that BFGS ended on
    final = {**sweep, "objective": sweep_objective(sweep, result.smooth_disp_limit, args.penalty)}
    plot_design(final, result, args.plot, title=stamp, units=plot_units(units))


_STATISTIC = {"mean": "mean", "p95": "95th-percentile"}
"""The words of each `--limit-statistic`."""

_CHECK_WORDS = {"one-sided": "(one-sided at the restrainer contact) ",
                "piecewise": "(one-sided on the optimum's side of a kink) "}
"""The printed words of each `gradient_check` but the central one."""


def _variables_and_structure(args):
    """({design variable: (low, high)} [SI], the structure they change) of the flags, each
    checked (`ValueError` naming the flag): the variables of `--isolator`'s design space
    (`resolve_design_variables`), the structure at the low end of their bounds, and the box
    of bounds checked by the design space (`teflon_jax.bearing.design_space`)."""
    from ..bearing import design_space

    variables = resolve_design_variables(args)
    build = _pendulum_structure if ISOLATOR_DESIGNS[args.isolator].uses_file else _slider_structure
    structure = build(args, variables)
    try:
        design_space(args.isolator).check(structure, variables)
    except ValueError as error:
        raise flag_error(error) from None
    return variables, structure


def _slider_structure(args, variables):
    """The `IsolatedStructure` of flat sliders or a single pendulum at the low ends of the
    bounds (Table 1's rows checked against the pressure flags, by name), for --components."""
    from ..studies import bidirectional_isolated_structure
    from ..systems import isolated_structure

    bearing = _design_bearing(args)
    if bearing is None and "pressure" in variables:
        for pressure, text in zip(args.pressure_range, args.pressure_range_text):
            check_table1(args.ptfe, pressure, text, "--pressure-range")
    if bearing is None and args.pressure_text is not None:
        check_table1(args.ptfe, args.pressure, args.pressure_text)
    options = dict(ptfe=args.ptfe, **structure_options(args, variables, bearing),
                   time_step=0.0025 if args.time_step is None else args.time_step, newton_tolerance=0.0)
    # Design differentiates the peaks: the turning-point split of the Monte Carlo default
    # switches branch when a design change moves a velocity reversal across a step, and the
    # gradient check at the optimum then fails; the plain update at 2.5 ms with Newmark's
    # rule passes it, with the isolator's equilibrium solved to rounding (no trace of where
    # Newton's loop stopped in the check's central differences; see `default_design_problem`).
    # Two components take Park's Z along each step's increment with Newmark's rule already.
    one_component = {"split_at_turn": False, "linear_rule": "newmark"}
    structure = isolated_structure(args.structure, **options, **one_component)
    if "capacity" in variables:  # the surface with its restrainer, scaled by the weight carried
        options = restrained_options(args, variables, structure, options)
        structure = isolated_structure(args.structure, **options, **one_component)
    return bidirectional_isolated_structure(args.structure, **options) if args.components == 2 else structure


def _pendulum_structure(args, variables):
    """The `IsolatedStructure` on the pendulum of `--isolator-file` (`ValueError` naming
    the flag for a file of another isolator), for --components: its sliders balanced to
    rounding (so that central differences see no trace of where Newton's loop stopped)."""
    import jax
    import jax.numpy as jnp

    from ..studies import bidirectional_isolated_structure
    from ..systems import isolated_structure
    from ._isolator_flags import load_isolator_file as _load

    pendulum = jax.tree_util.tree_map(lambda x: jnp.asarray(x, float), _load(args.isolator_file, args.isolator))
    build = bidirectional_isolated_structure if args.components == 2 else isolated_structure
    return build(args.structure, isolator=pendulum, time_step=0.005 if args.time_step is None else args.time_step,
                 newton_tolerance=0.0)


def _design_bearing(args):
    """The bearing of `--bearing FILE` (or None): design varies the isolation period and the
    contact pressure, which changes a given bearing only through its heating or pressure
    dependence."""
    read = read_bearing_flag(args)
    bearing = None if read is None else read.bearing
    pressure_matters = bearing is not None and (bearing.heating is not None or bearing.pressure_dependence is not None)
    if bearing is not None and args.f_max_range_text is not None:
        if pressure_matters:
            raise ValueError(f"--f-max-range: the friction of --bearing {args.bearing} changes with the "
                             "contact pressure (heating or pressure dependence); design it over "
                             "--pressure-range instead.")
        return bearing
    if bearing is not None and not pressure_matters:
        raise ValueError(
            f"--bearing {args.bearing}: design varies the isolation period and the contact "
            "pressure, and the contact pressure changes this bearing nowhere (it has neither "
            "heating nor pressure dependence); run montecarlo --bearing over the periods you "
            "consider, design its f_max (--f-max-range) or design with Table 1 (--ptfe).")
    return bearing


def _payload(args, result, sweep, units, wall_s: float) -> dict:
    """The summary JSON of `teflon-jax design` (lengths and pressures in `units`, keys
    naming them); `grid_best` is the grid's best point on the optimum's objective (the limit
    on the smoothed peaks lowered as the optimiser's, `smooth_disp_limit`)."""
    import jax
    import numpy as np

    from ..studies import sweep_objective

    length = units.length
    # the grid on the optimiser's own objective: its limit lowered for smoothed peaks
    at_limit = np.asarray(sweep_objective(sweep, result.smooth_disp_limit, args.penalty)).reshape(-1)
    best = int(np.nanargmin(at_limit)) if np.isfinite(at_limit).any() else None  # None: no grid point converged
    payload = {
        "n_motions": args.motions,
        "structure": args.structure,
        "components": args.components,
        "isolator": args.isolator,
        "devices": len(jax.devices()),
        "wall_s": wall_s,
        "optimum": {
            **design_fields(result.optimum, units),
            "objective": result.objective,
            "mean_smooth_base_shear_ratio": result.mean_shear,
            f"mean_smooth_base_disp_{length[0]}": result.mean_disp / length[1],
            "mean_peak_base_shear_ratio": result.peak_shear,
            f"mean_peak_base_disp_{length[0]}": result.peak_disp / length[1],
            f"p95_smooth_base_disp_{length[0]}": result.p95_disp / length[1],
            f"p95_peak_base_disp_{length[0]}": result.p95_peak_disp / length[1],
            "disp_limit_met": result.limit_met,
            f"smooth_disp_limit_{length[0]}": result.smooth_disp_limit / length[1],
            "bfgs_steps": result.steps,
            "optimiser_converged": result.optimiser_converged,
            "simulation_converged": result.simulation_converged,
            "n_failed_motions": result.n_failed_motions,
            "at_bounds": list(result.at_bounds),
            "converged": result.converged,
        },
        f"disp_limit_{length[0]}": args.disp_limit / length[1],
        "limit_statistic": args.limit_statistic,
        "restrainer_ratio": args.restrainer_ratio if "capacity" in result.optimum else None,
        "gradient_rel_error": result.gradient_rel_error,
        "gradient_check": result.gradient_check,
        "kink_checks": list(result.kink_checks),
        "restrainer_contact": _contact_fields(result.restrainer_contact, result.central_rel_error, units),
        "gradient_tolerance": _tolerance(),
        "messages": list(result.messages),
        "grid_best": None if best is None else {
            **design_fields({n: float(v.reshape(-1)[best]) for n, v in sweep["grid"].items()}, units),
            "objective": float(at_limit[best]),
        },
        "optimum_beats_grid": None if best is None else bool(result.objective <= at_limit[best] * (1 + 1e-9)),
        "bfgs_start": design_fields(result.start, units),
        "motions": {"pga_g": [args.pga / STANDARD_GRAVITY], "duration_s": args.duration, "seed": args.seed},
        "sweep_file": None if args.out is None else str(args.out),
    }
    return payload


def _percentile_check(args, structure, result, records) -> dict:
    """The 95th percentile over the motions of the smooth peak base displacement at the
    optimum, its derivative in each design variable and central differences
    (`percentile_disp_gradient_check`), as JSON entries."""
    from ..studies import percentile_disp_gradient_check

    check = percentile_disp_gradient_check(structure, result.optimum, records, args.record_step)
    return {"p95_smooth_base_disp_m": check["value"], "p95_disp_gradient": check["gradient"],
            "p95_disp_finite_differences": check["finite_differences"],
            "p95_disp_gradient_rel_error": check["rel_error"]}


def _contact_fields(contact, central: float, units) -> dict | None:
    """JSON entries of `restrainer_contact_check`'s report (lengths in `units`): None without
    a designed capacity."""
    if contact is None:
        return None
    unit, scale = units.length
    fields = {"at_contact": contact["at_contact"], f"capacity_{unit}": contact["capacity"] / scale,
              f"largest_peak_{unit}": contact["largest_peak"] / scale,
              f"free_largest_peak_{unit}": contact["free_largest_peak"] / scale,
              "relative_gap": contact["gap"], "tolerance": contact["tolerance"]}
    if contact["at_contact"]:
        fields.update(central_rel_error=central, one_sided_rel_error=contact["rel_error"],
                      one_sided_checks=contact["checks"])
    return fields


def _tolerance() -> float:
    """Largest relative error of the gradient at the optimum (against finite differences)
    that lets the optimum be trusted (`teflon_jax.studies.GRADIENT_TOLERANCE`)."""
    from ..studies import GRADIENT_TOLERANCE

    return GRADIENT_TOLERANCE


def _range_flags(args) -> str:
    """The flags of the design variables' bounds, e.g. '--radius-range or --pressure-range'."""
    return " or ".join(getattr(args, "design_flags", ("--period-range", "--pressure-range")))


def _verdict(result, args) -> int:
    """Warnings and the exit status: 1 when the optimum cannot be trusted (a simulation did
    not converge, the gradient check failed, or BFGS did not converge)."""
    tolerance = _tolerance()
    for message in result.messages:
        print(f"teflon-jax design: {message}", file=sys.stderr)
    if result.at_bounds:
        print(f"teflon-jax design: warning: the optimum lies on a bound of {', '.join(result.at_bounds)}; "
              f"the best design may lie outside the box: widen {_range_flags(args)}, "
              "or check --disp-limit.", file=sys.stderr)
    failed = []
    if not result.limit_met:
        units = output_units(args.units)
        failed.append(f"the reported design breaks --disp-limit {args.disp_limit_text}: its "
                      f"{_STATISTIC[args.limit_statistic]} peak base displacement is "
                      f"{units.show(result.limited_disp, 'length')}; widen "
                      f"{_range_flags(args)}, or raise --disp-limit")
    if not result.simulation_converged:
        failed.append(f"{result.n_failed_motions} motion(s) of the set did not converge at the optimum "
                      "(a Newton step failed); try a smaller --time-step")
    if not result.gradient_rel_error <= tolerance:
        failed.append(f"the gradient at the reported optimum differs from finite differences by "
                      f"{result.gradient_rel_error:.2g} (relative), more than {tolerance:g}: "
                      "the optimum cannot be trusted")
    if not result.optimiser_converged:
        failed.append(f"BFGS did not converge in {result.steps} steps")
    p95 = getattr(args, "p95_rel_error", None)
    if p95 is not None and not p95 <= tolerance:
        failed.append(f"the derivative of the 95th-percentile displacement differs from central "
                      f"differences by {p95:.2g} (relative), more than {tolerance:g}")
    for reason in failed:
        print(f"teflon-jax design: error: {reason}.", file=sys.stderr)
    return 1 if failed else 0
