#!/usr/bin/env bash
# The accelerator figures of benchmarks/README.md in one run, on one machine.
# Usage: bash benchmarks/device_figures.sh OUT_DIR [MOTIONS] [CHUNK]
#   MOTIONS (default 196608) motions per one-component command, half that with two components;
#   CHUNK (default 65536). FIGURES (environment, default all, in this order) picks the groups:
#     b3        B3 (library, chunks of CHUNK) with its accuracy against 0.5 ms steps
#     command   the `montecarlo` command at its default chunk and at CHUNK, two components, and a
#               bearing that heats up (benchmarks/hot_bearing.json)
#     pair      the command with one and two components on two full chunks each
#     long      the command on 16 chunks (1,048,576 motions by default), and at chunks of 512
#     isolators single and triple friction pendulums (benchmarks/triple_isolator.json) and a
#               vertical component, through the command
#     b7        B7: flat sliders, single and triple friction pendulums in one run
#     b7pair    B7 with two horizontal components (two full chunks of CHUNK pairs per isolator), and
#               the command on single and triple pendulums with two components
# Each step writes its JSON and log to OUT_DIR and is timed apart; a step that fails is logged
# and the others still run. A CPU dry run: FIGURES="command isolators" bash ... /tmp/dry 64 32
set -u
out=${1:?usage: device_figures.sh OUT_DIR [MOTIONS] [CHUNK]}
motions=${2:-196608}
chunk=${3:-65536}
groups=${FIGURES:-b3 command pair long isolators b7}
half=$((motions / 2))
mkdir -p "$out"
here=$(cd "$(dirname "$0")" && pwd)
py=${PYTHON:-python3}
export PYTHONUNBUFFERED=1

step() {  # step NAME COMMAND...: run, log, keep going
  local name=$1; shift
  local tic=$(date +%s%N)
  "$@" >"$out/$name.log" 2>&1
  local rc=$?
  printf '%-28s rc=%s %6d ms\n' "$name" "$rc" "$((($(date +%s%N) - tic) / 1000000))" | tee -a "$out/steps.txt"
  tail -n 4 "$out/$name.log"
}

mc() {  # mc NAME ARGS...: the montecarlo command, JSON to OUT_DIR/NAME.json
  local name=$1; shift
  step "$name" "$py" -m teflon_jax montecarlo --no-progress --json "$out/$name.json" "$@"
}

"$py" -c "import jax; print(jax.__version__, jax.devices())" | tee "$out/device.txt"
for group in $groups; do
  case $group in
  b3)
    step b3 "$py" "$here/bench_gpu.py" --parts B3 --chunk "$chunk" --chunks 3 --json "$out/b3.json" ;;
  command)
    for kind in building rigid; do
      mc "cmd-$kind-default" --structure "$kind" --motions "$motions"
      mc "cmd-$kind-chunk" --structure "$kind" --motions "$motions" --chunk-size "$chunk"
      mc "cmd-$kind-2comp" --structure "$kind" --motions "$half" --components 2
      mc "cmd-$kind-hot" --structure "$kind" --motions "$motions" --pressure 3000psi \
        --bearing "$here/hot_bearing.json"
      mc "cmd-$kind-hot-2comp" --structure "$kind" --motions "$half" --components 2 --pressure 3000psi \
        --bearing "$here/hot_bearing.json"
    done ;;
  pair)
    for kind in building rigid; do
      mc "pair-$kind" --structure "$kind" --motions "$((2 * chunk))"
      mc "pair-$kind-2comp" --structure "$kind" --motions "$((2 * chunk))" --components 2
    done ;;
  long)
    for kind in building rigid; do
      mc "long-$kind" --structure "$kind" --motions "$((16 * chunk))"
      mc "long-$kind-2comp" --structure "$kind" --motions "$((2 * chunk))" --components 2
    done
    mc "long-building-chunk512" --structure building --motions "$((chunk / 4))" --chunk-size 512 ;;
  isolators)
    for kind in rigid building; do
      mc "iso-$kind-single-fp" --structure "$kind" --motions "$motions" --isolator single-fp --radius 39in
      mc "iso-$kind-single-fp-vertical" --structure "$kind" --motions "$motions" --isolator single-fp \
        --radius 39in --vertical-ratio 0.67
      mc "iso-$kind-triple-fp" --structure "$kind" --motions "$motions" --isolator triple-fp \
        --isolator-file "$here/triple_isolator.json"
    done ;;
  b7)
    step b7 "$py" "$here/bench_pendulum.py" --motions "$((2 * chunk))" --chunk "$chunk" --repeats 1 \
      --json "$out/b7.json" ;;
  b7pair)
    step b7pair "$py" "$here/bench_pendulum.py" --components 2 --motions "$((2 * chunk))" --chunk "$chunk" \
      --repeats 1 --json "$out/b7pair.json"
    for kind in rigid building; do
      mc "iso2-$kind-single-fp" --structure "$kind" --motions "$((2 * chunk))" --chunk-size "$chunk" \
        --components 2 --isolator single-fp --radius 39in
      mc "iso2-$kind-triple-fp" --structure "$kind" --motions "$((2 * chunk))" --chunk-size "$chunk" \
        --components 2 --isolator triple-fp --isolator-file "$here/triple_isolator.json"
    done ;;
  *) echo "unknown group $group" >&2 ;;
  esac
done
"$py" - "$out" <<'EOF'
import json, pathlib, sys
out = pathlib.Path(sys.argv[1])
rows = {}
for path in sorted(out.glob("*.json")):
    d = json.loads(path.read_text())
    if "records_per_s" not in d:
        continue
    rows[path.stem] = {k: d.get(k) for k in ("device_kind", "n_motions", "n_converged", "chunk_size",
                                              "time_step_s", "wall_s", "compile_s", "records_per_s",
                                              "records_per_s_after_first_chunk", "vertical")}
    rows[path.stem]["p50_base_disp_in"] = d["statistics"]["base_disp_in"]["p50"]
(out / "summary.json").write_text(json.dumps(rows, indent=1))
for name, row in rows.items():
    steady = row["records_per_s_after_first_chunk"]
    print(f"{name:30s} {row['records_per_s']:10.0f} records/s over the run, "
          f"{'-' if steady is None else f'{steady:.0f}'} after the first chunk; chunk {row['chunk_size']}, "
          f"wall {row['wall_s']:.1f} s, compile {row['compile_s']:.1f} s, p50 {row['p50_base_disp_in']:.3f} in")
EOF
