"""The `teflon-jax` command: simulate-test, reproduce, fit, diagnose, montecarlo, design."""

import argparse
import importlib
import math
import os
import pathlib
import re
import sys
import time

from ._common import (
    check_scheduler,
    project_version,
    read_quantities,
    set_command_line,
)
from ._paths import check_outputs, output_flags, remove_empty_folders
from ._provenance import clear_arguments, set_arguments, stamp_outputs

_COMMANDS = {
    # command: (module, adds its parser, runs it, its line in `teflon-jax --help`)
    "simulate-test": ("_simulate", "add_simulate_parser", "run_simulate", "HELP"),
    "reproduce": ("_reproduce", "add_reproduce_parser", "run_reproduce", "HELP"),
    "fit": ("_fit", "add_fit_parser", "run_fit", "FIT_HELP"),
    "diagnose": ("_diagnose", "add_diagnose_parser", "run_diagnose", "HELP"),
    "montecarlo": ("_montecarlo", "add_montecarlo_parser", "run_montecarlo", "HELP"),
    "design": ("_design", "add_design_parser", "run_design", "HELP"),
    "run": ("_run", "add_run_parser", "run_run", "HELP"),
}


def _command_module(command: str):
    return importlib.import_module(f".{_COMMANDS[command][0]}", __package__)


class _StoreOnce(argparse.Action):
    """argparse's default action (store the flag's value) for a flag given at most once: a
    second value is refused naming both, where argparse would keep the last silently. The
    flags seen are the parser's, for the parse under way (`_Parser.parse_known_args`): the
    namespace holds the flags alone."""

    def __call__(self, parser, namespace, values, option_string=None):
        given = parser.__dict__.setdefault("given_once", {})
        if option_string is not None and self.dest in given:
            parser.error(f"{option_string}: given twice ({given[self.dest]}, then {option_string} "
                         f"{_shown(values)}); give it once.")
        if option_string is not None:
            given[self.dest] = f"{option_string} {_shown(values)}"
        setattr(namespace, self.dest, values)


def _shown(values) -> str:
    return " ".join(map(str, values)) if isinstance(values, list) else str(values)


class _Parser(argparse.ArgumentParser):
    """`argparse.ArgumentParser` whose flags store once (`_StoreOnce`); its sub-commands'
    parsers are of this class too."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.register("action", None, _StoreOnce)
        self.register("action", "store", _StoreOnce)

    def parse_known_args(self, args=None, namespace=None):
        """argparse's, with the flags seen (`_StoreOnce`) forgotten before each parse."""
        self.given_once = {}
        return super().parse_known_args(args, namespace)


def _parser(only: str | None = None) -> argparse.ArgumentParser:
    """The whole parser, or (`only` a command name, or "" for none) the full parser of that
    command alone beside one-line stubs of the others: enough to parse a command line that
    names `only`, or to print `--help`, without importing what the other commands need
    (JAX itself is imported by the commands' runners, not here)."""
    parser = _Parser(
        prog="teflon-jax",
        description="Differentiable simulation of PTFE sliding bearings (Constantinou, Mokha & "
        "Reinhorn 1990) on JAX.",
    )
    parser.add_argument("--version", action="version", version=f"teflon-jax {project_version()}",
                        help="print the version of teflon-jax and exit")
    parser.add_argument("--float32", action="store_true", help="compute in single precision "
                        "(default: double precision)")
    parser.add_argument("--cpu-devices", type=int, default=None, metavar="N",
                        help="split the processor into N JAX devices; `montecarlo` shares its "
                        "motions out over them (default: one per core, unless XLA_FLAGS sets "
                        "--xla_force_host_platform_device_count)")
    parser.add_argument("--no-compile-cache", action="store_true",
                        help="do not keep compiled programs between runs (default: kept in "
                        "$XDG_CACHE_HOME/teflon-jax/jax, else ~/.cache/teflon-jax/jax)")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for command, (_, adder, _, help_name) in _COMMANDS.items():
        module = _command_module(command)
        if only is None or command == only:
            getattr(module, adder)(sub)
        else:
            sub.add_parser(command, help=getattr(module, help_name), add_help=False)
    return parser


def _named_command(argv) -> str:
    """The command a command line names ("" when none): its first word that is one."""
    return next((word for word in argv if word in _COMMANDS), "")


def _split_cpu(jax, requested: int | None) -> None:
    """One JAX CPU device per core (or `requested`), set before JAX's first computation."""
    if requested is None and "xla_force_host_platform_device_count" in os.environ.get("XLA_FLAGS", ""):
        return
    count = os.cpu_count() or 1 if requested is None else requested
    try:
        jax.config.update("jax_num_cpu_devices", count)
    except RuntimeError as error:  # JAX already ran in this process (e.g. main() from Python)
        if requested is not None:
            raise ValueError(f"--cpu-devices: {error}") from None


_RUNTIME_CHECK = re.compile(r"EquinoxRuntimeError: (.+?)(?:\n\s*\n|\n-{5,}|$)", re.DOTALL)


def runtime_check_message(error) -> str | None:
    """The message of a check that stopped a compiled run (`equinox.error_if` inside the
    step, such as Table 1's constants beyond its extended rows), out of the runtime error
    JAX raises around it; None for any other error."""
    found = _RUNTIME_CHECK.search(str(error))
    return None if found is None else " ".join(found.group(1).split())


def compile_cache_dir() -> pathlib.Path:
    """Folder of the persistent JAX compilation cache: `$XDG_CACHE_HOME/teflon-jax/jax`, or
    `~/.cache/teflon-jax/jax` when XDG_CACHE_HOME is unset or empty."""
    base = os.environ.get("XDG_CACHE_HOME") or str(pathlib.Path.home() / ".cache")
    return pathlib.Path(base) / "teflon-jax" / "jax"


def _use_compile_cache(jax) -> None:
    """Keep every compiled program (however small or quick to compile) in the user's cache,
    so that a repeated job skips XLA's compilation; JAX keys the entries by program, options,
    device and version."""
    path = compile_cache_dir()
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        print(f"teflon-jax: warning: no compilation cache ({error}); use --no-compile-cache "
              "to silence this", file=sys.stderr)
        return
    jax.config.update("jax_compilation_cache_dir", str(path))
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)
    jax.config.update("jax_persistent_cache_min_entry_size_bytes", 0)


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    set_command_line(argv)  # written into every JSON the command writes
    parser = _parser(only=_named_command(argv))
    args = parser.parse_args(argv)
    if args.cpu_devices is not None and args.cpu_devices < 1:
        parser.error(f"--cpu-devices: must be >= 1, got {args.cpu_devices}")
    import jax

    from ..studies import prefer_wide_cpu_vectors

    prefer_wide_cpu_vectors()  # before JAX's first computation, as the CPU devices
    try:
        _split_cpu(jax, args.cpu_devices)
    except ValueError as error:
        print(f"teflon-jax: error: {error}", file=sys.stderr)
        return 2
    jax.config.update("jax_enable_x64", not args.float32)
    if not args.no_compile_cache:
        _use_compile_cache(jax)
    runner = getattr(_command_module(args.command), _COMMANDS[args.command][2])
    from ..studies import ClusterRunError

    created = []
    try:
        read_quantities(args, args.command)
        created = check_outputs(args, args.command)  # before any work
        check_scheduler(args)
        set_arguments(args, output_flags(args.command))  # its input files hashed, for every result it writes
        started = math.floor(time.time()) - 1  # file times may be whole seconds
        status = runner(args)
        stamp_outputs(started)
        if status == 2:  # refused: the folders made for its outputs go again
            remove_empty_folders(created)
        return status
    except (ValueError, FileNotFoundError, ConnectionError) as error:
        print(f"teflon-jax {args.command}: error: {error}", file=sys.stderr)
        remove_empty_folders(created)
        return 2
    except ClusterRunError as error:  # the input was fine; the cluster could not finish the run
        print(f"teflon-jax {args.command}: error: {error}", file=sys.stderr)
        return 1
    except RuntimeError as error:  # a check inside the compiled run stopped it: its message, no traceback
        message = runtime_check_message(error)
        if message is None:
            raise
        print(f"teflon-jax {args.command}: error: the run stopped: {message}", file=sys.stderr)
        return 1
    finally:
        clear_arguments()


if __name__ == "__main__":
    sys.exit(main())
