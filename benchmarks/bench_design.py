"""Benchmark of `teflon-jax design`: wall time of the whole command and its stages, for one or
more source trees of the package (e.g. a checkout of an earlier commit beside this one), run in
turn so that a shared machine's load falls on each alike.

Each run is a fresh process with an empty compilation cache (a first run, as a new user sees
it); its wall time and its CPU time (user and system, which a loaded machine changes less) are
recorded. The stages are timed from outside the command, by wrapping the functions it calls, so
that any tree with those functions can be measured:

- `grid`: `design_sweep` (the grid of the objective);
- `bfgs`: every BFGS run (`optimistix.minimise` or `minimise_in_box`: the first, the reruns
  with a variable held on a bound, the restarts on a corrected limit), with its steps;
  `bfgs_runs` lists them;
- `check`: `design_gradient_check` (the central differences at the optimum);
- `plot`: `plot_design`;
- `compile`: the time JAX spent tracing, lowering and compiling (its monitoring events),
  within the stages above and in all.

Usage (from the repository root; `/tmp/design_old` e.g. made by `git worktree add`):

    python benchmarks/bench_design.py --trees /tmp/design_old . --rounds 2 \\
        --case readme --case tutorial --out benchmarks/results/design.json

Cases: `readme` is the README's `teflon-jax design --json design.json --plot design.png`;
`tutorial` the first command of docs/tutorials/design.md.
"""

import argparse
import contextlib
import json
import os
import pathlib
import platform
import resource
import subprocess
import sys
import tempfile
import time

CASES = {
    "readme": ["design", "--json", "design.json", "--plot", "design.png", "--no-progress"],
    "tutorial": ["design", "--motions", "4", "--duration", "15s", "--strong-motion", "5s", "--grid", "3",
                 "--json", "design.json", "--plot", "design.png", "--no-progress"],
}
"""The commands timed: name -> `teflon-jax` arguments."""

_COMPILE_EVENTS = ("/jax/core/compile/jaxpr_trace_duration", "/jax/core/compile/jaxpr_to_mlir_module_duration",
                   "/jax/core/compile/backend_compile_duration")


class _Clock:
    """Seconds per stage, and the compile seconds spent inside each."""

    def __init__(self):
        self.stages, self.compile, self.stack, self.runs = {}, {"total": 0.0}, [], []

    def on_event(self, event, duration, **_):
        if event in _COMPILE_EVENTS:
            self.compile["total"] += duration
            if self.stack:
                self.compile[self.stack[-1]] = self.compile.get(self.stack[-1], 0.0) + duration

    @contextlib.contextmanager
    def stage(self, name):
        outer = bool(self.stack) and self.stack[-1] == name
        self.stack.append(name)
        tic = time.perf_counter()
        try:
            yield
        finally:
            self.stack.pop()
            if not outer:
                self.stages[name] = self.stages.get(name, 0.0) + time.perf_counter() - tic


def _wrap(clock, owner, attribute, name, after=None):
    function = getattr(owner, attribute, None)
    if function is None:
        return

    def timed(*args, **kwargs):
        tic = time.perf_counter()
        with clock.stage(name):
            out = function(*args, **kwargs)
        if after is not None:
            after(out, time.perf_counter() - tic)
        return out

    setattr(owner, attribute, timed)


def _child(tree: str, argv: list, out: str) -> None:
    """Run `teflon-jax argv` from `tree` with the stages timed; write them to `out`."""
    sys.path.insert(0, tree)
    import jax
    import optimistix

    import teflon_jax.report
    import teflon_jax.studies
    import teflon_jax.studies._design as design_module
    from teflon_jax.cli._main import main

    clock = _Clock()
    jax.monitoring.register_event_duration_secs_listener(clock.on_event)

    def bfgs_run(solution, seconds):
        steps = solution.stats["num_steps"] if hasattr(solution, "stats") else solution.steps
        clock.runs.append({"steps": int(steps), "s": seconds})

    _wrap(clock, optimistix, "minimise", "bfgs", bfgs_run)
    _wrap(clock, design_module, "minimise_in_box", "bfgs", bfgs_run)
    _wrap(clock, teflon_jax.studies, "design_sweep", "grid")
    _wrap(clock, design_module, "design_gradient_check", "check")
    _wrap(clock, teflon_jax.report, "plot_design", "plot")
    tic = time.perf_counter()
    status = main(argv)
    wall = time.perf_counter() - tic
    summary = json.loads(pathlib.Path("design.json").read_text())
    optimum = summary["optimum"]
    pathlib.Path(out).write_text(json.dumps({
        "status": status, "wall_s": wall, "stages_s": clock.stages, "compile_s": clock.compile,
        "bfgs_runs": clock.runs, "optimum": {k: v for k, v in optimum.items() if not isinstance(v, (list, dict))},
        "gradient_rel_error": summary["gradient_rel_error"], "gradient_check": summary["gradient_check"],
        "messages": summary["messages"], "stages_reported_s": summary.get("stages_s"),
    }))


def _run(tree: str, case: str) -> dict:
    with tempfile.TemporaryDirectory() as folder:
        env = dict(os.environ, XDG_CACHE_HOME=os.path.join(folder, "cache"),
                   PYTHONPATH=os.path.abspath(tree))
        result = os.path.join(folder, "result.json")
        before, tic = resource.getrusage(resource.RUSAGE_CHILDREN), time.perf_counter()
        process = subprocess.run([sys.executable, os.path.abspath(__file__), "--child", os.path.abspath(tree),
                                  "--result", result, "--", *CASES[case]], cwd=folder, env=env,
                                 capture_output=True, text=True)
        wall, after = time.perf_counter() - tic, resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
        if not os.path.exists(result):
            raise RuntimeError(f"{tree} {case} failed:\n{process.stderr[-3000:]}")
        data = json.loads(pathlib.Path(result).read_text())
    printed = [line for line in process.stdout.splitlines() if line.startswith("optimum:")]
    return {"tree": tree, "case": case, "process_wall_s": wall, "process_cpu_s": cpu, "load_average": os.getloadavg(),
            "printed": printed, "stderr": process.stderr.strip().splitlines()[-6:], **data}


def _environment() -> dict:
    import jax
    import optimistix

    return {"machine": platform.machine(), "processor": platform.processor(), "cpus": os.cpu_count(),
            "python": platform.python_version(), "jax": jax.__version__, "optimistix": optimistix.__version__,
            "date": time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime())}


def table(path: str) -> str:
    """The runs of a results file as a markdown table: wall time, stages, optimum, check."""
    rows = ["| case | tree | wall [s] | grid | compile + 1st evaluation | BFGS (steps) | gradient check "
            "(its compile) | plot | compile in all | optimum | check | load |", "|" + "---|" * 12]
    for run in json.loads(pathlib.Path(path).read_text())["runs"]:
        stages, reported, compiled = run["stages_s"], run.get("stages_reported_s") or {}, run["compile_s"]
        optimum = run["optimum"]
        steps = "+".join(str(r["steps"]) for r in run["bfgs_runs"])
        first = reported.get("compile_and_first_evaluation")
        bfgs = reported.get("optimiser", stages.get("bfgs", 0.0))
        rows.append(
            f"| {run['case']} | {run['tree']} | {run['wall_s']:.1f} | {stages.get('grid', 0):.1f} | "
            f"{'-' if first is None else f'{first:.1f}'} | {bfgs:.1f} ({steps}) | "
            f"{stages.get('check', 0):.1f} ({compiled.get('check', 0):.1f}) | {stages.get('plot', 0):.1f} | "
            f"{compiled['total']:.1f} | Tb = {optimum['isolation_period_s']:.4f} s, "
            f"{optimum['pressure_psi']:.0f} psi, {optimum['mean_peak_base_disp_in']:.4f} in, "
            f"V/W {optimum['mean_peak_base_shear_ratio']:.4f} | {run['gradient_rel_error']:.2g} | "
            f"{run['load_average'][0]:.1f} |")
    return "\n".join(rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trees", nargs="+", default=["."], help="source trees to time, in turn")
    parser.add_argument("--case", action="append", choices=tuple(CASES), help="commands (default: all)")
    parser.add_argument("--rounds", type=int, default=1, help="times each tree runs each case")
    parser.add_argument("--out", default=None, help="JSON file of the runs")
    parser.add_argument("--table", default=None, metavar="JSON", help="print the runs of a results file as a table")
    parser.add_argument("--child", default=None, help=argparse.SUPPRESS)
    parser.add_argument("--result", default=None, help=argparse.SUPPRESS)
    parser.add_argument("argv", nargs="*", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child is not None:
        _child(args.child, args.argv, args.result)
        return
    if args.table is not None:
        print(table(args.table))
        return
    runs = []
    for _ in range(args.rounds):
        for case in args.case or tuple(CASES):
            for tree in args.trees:
                run = _run(tree, case)
                runs.append(run)
                print(json.dumps({k: run[k] for k in ("tree", "case", "status", "wall_s", "process_cpu_s", "stages_s",
                                                      "compile_s", "load_average")}), flush=True)
                print("  ", run["printed"], [(r["steps"], round(r["s"], 1)) for r in run["bfgs_runs"]], flush=True)
                if args.out is not None:
                    pathlib.Path(args.out).write_text(json.dumps({"environment": _environment(), "runs": runs},
                                                                 indent=1))


if __name__ == "__main__":
    main()
