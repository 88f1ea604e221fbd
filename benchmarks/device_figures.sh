#!/usr/bin/env bash
# The accelerator figures of benchmarks/README.md in one run, on one machine:
#   B3 (library, chunks of CHUNK), the `montecarlo` command at its default chunk and at CHUNK,
#   two horizontal components, a heating bearing (benchmarks/hot_bearing.json), and B7 (single
#   friction pendulum beside flat sliders).
# Usage: bash benchmarks/device_figures.sh OUT_DIR [MOTIONS] [CHUNK]
#   MOTIONS (default 196608) motions per one-component command, half that with two components;
#   CHUNK (default 65536). Each step writes its JSON and log to OUT_DIR and is timed apart; a step
#   that fails is logged and the others still run. A CPU dry run: MOTIONS=64 CHUNK=32.
set -u
out=${1:?usage: device_figures.sh OUT_DIR [MOTIONS] [CHUNK]}
motions=${2:-196608}
chunk=${3:-65536}
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
step b3 "$py" "$here/bench_gpu.py" --parts B3 --chunk "$chunk" --chunks 3 --json "$out/b3.json"
for kind in building rigid; do
  mc "cmd-$kind-default" --structure "$kind" --motions "$motions"
  mc "cmd-$kind-chunk" --structure "$kind" --motions "$motions" --chunk-size "$chunk"
  mc "cmd-$kind-2comp" --structure "$kind" --motions "$half" --components 2
  mc "cmd-$kind-hot" --structure "$kind" --motions "$motions" --pressure 3000psi \
    --bearing "$here/hot_bearing.json"
  mc "cmd-$kind-hot-2comp" --structure "$kind" --motions "$half" --components 2 --pressure 3000psi \
    --bearing "$here/hot_bearing.json"
done
step b7 "$py" "$here/bench_pendulum.py" --motions "$((2 * chunk))" --chunk "$chunk" --repeats 1 \
  --json "$out/b7.json"
"$py" - "$out" <<'EOF'
import json, pathlib, sys
out = pathlib.Path(sys.argv[1])
rows = {}
for path in sorted(out.glob("cmd-*.json")):
    d = json.loads(path.read_text())
    rows[path.stem] = {k: d.get(k) for k in ("device_kind", "n_motions", "n_converged", "chunk_size",
                                              "time_step_s", "wall_s", "compile_s", "records_per_s")}
    rows[path.stem]["p50_base_disp_in"] = d["statistics"]["base_disp_in"]["p50"]
(out / "summary.json").write_text(json.dumps(rows, indent=1))
for name, row in rows.items():
    print(f"{name:24s} {row['records_per_s']:10.0f} records/s  chunk {row['chunk_size']:6d}  "
          f"wall {row['wall_s']:6.1f} s  compile {row['compile_s']:5.1f} s  p50 {row['p50_base_disp_in']:.3f} in")
EOF
