#!/usr/bin/env bash
# What the refined method costs: `recon reconstruct` with the default
# (refined) and with --method hoppe92 on the same cloud, run alternately
# (the machine is shared and noisy: side by side in one run), reading each
# run's wall time, phase times, peak memory and triangle count from --stats.
#
#   bench/methods.sh                           # the 1M-point torus, 3 runs of each (about a minute)
#   METHODS_SHAPE=terrain METHODS_POINTS=1000000 METHODS_RUNS=5 bench/methods.sh
set -euo pipefail

source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
shape="${METHODS_SHAPE:-torus}"
points="${METHODS_POINTS:-1000000}"
runs="${METHODS_RUNS:-3}"
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT

"$recon" generate "$shape" -n "$points" --seed 1 -o "$scratch/cloud.ply" > /dev/null
echo "$shape, $points points, commit $(git rev-parse --short HEAD), $(date -u '+%Y-%m-%d %H:%M UTC'), load $(cut -d' ' -f1-3 /proc/loadavg)"
echo
echo "| method | run | wall s | I s | II s | III s | IV s | V s | peak MiB | triangles |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for run in $(seq 1 "$runs"); do
  for method in refined hoppe92; do
    nice "$recon" reconstruct "$scratch/cloud.ply" --method "$method" -o "$scratch/mesh.ply" --stats "$scratch/stats.json" --quiet
    /usr/bin/python3 "$root/bench/stats_row.py" "$scratch/stats.json" "$method" "$run"
  done
done
