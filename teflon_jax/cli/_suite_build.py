"""The structure of one record pair of `run --suite` (and of each bounding case)."""


def suite_build(args, build_structure, ax0, ay0, dt):
    """(build(ground_x, ground_y) -> the structure of one pair, its degrees of freedom, the
    base's coordinates in x and y, the slab's plan or None) of `run`'s flags (`build_structure`
    of `teflon-jax run`, or the triple or double pendulums of `--isolator-file`, under a
    slab's groups too), with `args.friction_factor` where a bounding case sets it. The
    structure is built once; only the ground motion changes."""
    import equinox as eqx

    from ..excitation import uniform_signal
    from ._triple import SERIES_ISOLATORS, series_suite_build

    if args.isolator in SERIES_ISOLATORS and args.structure == "slab":  # `SlabOnSeries`
        from ._run_slab_series import series_slab_suite_build

        build, plan = series_slab_suite_build(args, ax0, ay0, dt)
        return build, 3, (0, 1), plan
    if args.isolator in SERIES_ISOLATORS:  # the peaks read the pendulums' own histories
        build = series_suite_build(args)
        first = build(uniform_signal(ax0, dt), uniform_signal(ay0, dt))
        return build, first.mass.shape[-1], (0, 1), None
    template, plan = build_structure(args, ax0, ay0, dt)
    half = template.mass.shape[0] // 2

    def build(gx, gy):
        return eqx.tree_at(lambda s: (s.ground_x, s.ground_y), template, (gx, gy))

    slab = args.structure == "slab"
    return build, template.mass.shape[-1], (0, 1) if slab else (0, half), plan if slab else None
