#!/usr/bin/env bash
# Two builds of recon side by side on one cloud: a restructuring must leave
# speed, memory and output as they were. Runs alternate (the machine is
# shared and noisy), each reading its wall time, phase times and peak memory
# from --stats; every mesh is compared byte for byte with the first build's.
#
#   bench/two_builds.sh OLD_RECON NEW_RECON            # 1M-point torus, refined, 3 runs each
#   TWO_SHAPE=terrain TWO_POINTS=1000000 TWO_METHOD=hoppe92 TWO_RUNS=5 bench/two_builds.sh OLD NEW
#
# To build the old one: git worktree add /tmp/old REV && cmake -S /tmp/old -B /tmp/old/build
#   -DCMAKE_BUILD_TYPE=Release -DRECON_REPORT=OFF -DRECON_PYTHON=OFF && cmake --build /tmp/old/build --target recon_cli
set -euo pipefail

source "$(dirname "${BASH_SOURCE[0]}")/old_and_new.sh"
shape="${TWO_SHAPE:-torus}"
points="${TWO_POINTS:-1000000}"
method="${TWO_METHOD:-refined}"
runs="${TWO_RUNS:-3}"

"$new" generate "$shape" -n "$points" --seed 1 -o "$scratch/cloud.ply" > /dev/null
echo "$shape, $points points, $method, commit $(git -C "$root" rev-parse --short HEAD), $(date -u '+%Y-%m-%d %H:%M UTC'), load $(cut -d' ' -f1-3 /proc/loadavg)"
echo
echo "| build | run | wall s | I s | II s | III s | IV s | V s | peak MiB | mesh |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---|"
one_run() {
  local run="$1" build="$2" binary="$3" same="(first)"
  "$binary" reconstruct "$scratch/cloud.ply" --method "$method" -o "$scratch/$build.ply" --stats "$scratch/stats.json" --quiet
  [ -f "$scratch/reference.ply" ] || cp "$scratch/$build.ply" "$scratch/reference.ply"
  if [ "$build" = new ] || [ "$run" -gt 1 ]; then
    if cmp -s "$scratch/$build.ply" "$scratch/reference.ply"; then same="same bytes"; else same="DIFFERS"; fi
  fi
  /usr/bin/python3 "$root/bench/stats_row.py" "$scratch/stats.json" "$build" "$run" "$same"
}
alternate_builds one_run
