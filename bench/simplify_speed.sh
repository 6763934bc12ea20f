#!/usr/bin/env bash
# Phase VI's speed, two builds side by side (issue 30's target: a
# 1M-triangle mesh in at most 1 s here). Phase V's mesh of a 1M-point
# torus (973,520 triangles) simplified to a tenth by `recon simplify`, on 1
# and 2 threads; runs alternate between the builds (the machine is shared
# and noisy). Each row: the step's seconds from --stats (the numbering
# included, reading and writing not) and the load average. Each build's
# meshes must be the same bytes on 1 and 2 threads.
#
#   bench/simplify_speed.sh OLD_RECON NEW_RECON        # 5 runs each
#   SPEED_RUNS=3 SPEED_MESH=mesh.ply bench/simplify_speed.sh OLD NEW
#
# OLD_RECON: a build of another commit (bench/two_builds.sh says how).
set -euo pipefail

source "$(dirname "${BASH_SOURCE[0]}")/old_and_new.sh"
runs="${SPEED_RUNS:-5}"

mesh="${SPEED_MESH:-}"
if [ -z "$mesh" ]; then
  "$new" generate torus -n 1000000 --seed 2 -o "$scratch/cloud.ply" > /dev/null
  "$new" reconstruct "$scratch/cloud.ply" -o "$scratch/mesh.ply" --quiet
  mesh="$scratch/mesh.ply"
fi
echo "commit $(git -C "$root" rev-parse --short HEAD), $(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores"
echo
echo "| build | run | threads | triangles | seconds | load (1 min) |"
echo "|---|---:|---:|---:|---:|---:|"
one_run() {
  local run="$1" build="$2" binary="$3" threads
  for threads in 1 2; do
    "$binary" simplify "$mesh" -o "$scratch/$build-$threads.ply" --to 10% --threads "$threads" \
      --stats "$scratch/stats.json" --quiet
    /usr/bin/python3 - "$scratch/stats.json" "$build" "$run" "$threads" <<'PY'
import json, sys
stats, build, run, threads = sys.argv[1:5]
s = json.load(open(stats))["simplification"]
load = open("/proc/loadavg").read().split()[0]
print(f"| {build} | {run} | {threads} | {s['triangles_after']} | {s['seconds']:.3f} | {load} |")
PY
  done
  cmp -s "$scratch/$build-1.ply" "$scratch/$build-2.ply" || echo "$build: 1 and 2 threads DIFFER"
}
alternate_builds one_run
