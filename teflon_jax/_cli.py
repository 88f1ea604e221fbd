"""The `teflon-jax` command: simulate-test, reproduce, fit, diagnose, montecarlo, design."""

import argparse
import sys


def _parser() -> argparse.ArgumentParser:
    from ._cli_simulate import add_simulate_parser

    parser = argparse.ArgumentParser(
        prog="teflon-jax",
        description="Differentiable simulation of PTFE sliding bearings (Constantinou, Mokha & "
        "Reinhorn 1990) on JAX.",
    )
    parser.add_argument("--float32", action="store_true", help="compute in single precision "
                        "(default: double precision)")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    add_simulate_parser(sub)
    for module, adders in (
        ("teflon_jax._cli_reproduce", ("add_reproduce_parser",)),
        ("identification._cli_fit", ("add_fit_parser",)),
        ("identification._cli_diagnose", ("add_diagnose_parser",)),
        ("teflon_jax._cli_scale", ("add_montecarlo_parser", "add_design_parser")),
    ):
        imported = __import__(module, fromlist=list(adders))
        for adder in adders:
            getattr(imported, adder)(sub)
    return parser


_RUNNERS = {
    "simulate-test": ("teflon_jax._cli_simulate", "run_simulate"),
    "reproduce": ("teflon_jax._cli_reproduce", "run_reproduce"),
    "fit": ("identification._cli_fit", "run_fit"),
    "diagnose": ("identification._cli_diagnose", "run_diagnose"),
    "montecarlo": ("teflon_jax._cli_scale", "run_montecarlo"),
    "design": ("teflon_jax._cli_scale", "run_design"),
}


def main(argv=None) -> int:
    args = _parser().parse_args(argv)
    import jax

    jax.config.update("jax_enable_x64", not args.float32)
    module, name = _RUNNERS[args.command]
    runner = getattr(__import__(module, fromlist=[name]), name)
    try:
        return runner(args)
    except (ValueError, FileNotFoundError) as error:
        print(f"teflon-jax {args.command}: error: {error}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
