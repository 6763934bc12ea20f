#!/usr/bin/env bash
# A tiled run under a memory limit too small for one phase I over the
# whole cloud (tiles/statistics.h) against the in-memory run, on the
# scan-like terrain of bench/terrain_stream.py: the cloud-wide measures
# (k, rho, the cell) and the mesh's counts side by side, and each run's
# seconds and peak (its --stats). docs/scaling.md keeps the figures.
#
#   bench/tiled_statistics.sh                  # N = 4M points, --max-memory 400M
#   N=1000000 MAX_MEMORY=120M bench/tiled_statistics.sh
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
recon="$root/build/release/app/recon"
n="${N:-4000000}"
limit="${MAX_MEMORY:-400M}"
scratch="${SCRATCH:-/tmp}/recon-tiled-statistics"
mkdir -p "$scratch"
[[ -x "$recon" ]] || { echo "build first: cmake --build --preset release" >&2; exit 1; }
cloud="$scratch/terrain-$n.ply"
[[ -f "$cloud" ]] || /usr/bin/python3 "$root/bench/terrain_stream.py" "$n" "$cloud"

echo "machine: $(nproc) cores, $(free -g | awk '/Mem:/ {print $2}') GiB; commit $(git -C "$root" rev-parse --short HEAD); $(date -u +%F)"
"$recon" --quiet reconstruct "$cloud" -o "$scratch/memory.ply" --stats "$scratch/memory.json"
"$recon" --quiet reconstruct "$cloud" -o "$scratch/tiles.ply" --max-memory "$limit" --stats "$scratch/tiles.json"
/usr/bin/python3 - "$scratch" "$n" "$limit" <<'PY'
import json, sys
scratch, n, limit = sys.argv[1], int(sys.argv[2]), sys.argv[3]
memory, tiles = json.load(open(f"{scratch}/memory.json")), json.load(open(f"{scratch}/tiles.json"))
plan = tiles["tiled"]
def faces(s):
    mesh = s["mesh"]
    return mesh.get("triangles", mesh.get("faces"))
print("| run | k | rho | cell | vertices | triangles | seconds (of which the plan) | peak MiB |")
print("|---|---|---|---|---|---|---|---|")
p1, p4 = memory["tangent_planes"], memory["contouring"]
def row(label, k, rho, cell, s, plan_seconds):
    mesh = s["mesh"]
    print(f"| {label} | {k} | {rho:.6g} | {cell:.6g} | {mesh['vertices']:,} | {faces(s):,} | "
          f"{s['seconds_total']:.1f} ({plan_seconds}) | {s['memory']['peak_mib_total']:.0f} |")
row(f"in memory, {n:,} points", p1["k"], p1["rho"], p4["cell"], memory, "-")
row(f"tiles, --max-memory {limit}: {plan['tiles']} tiles, measures over the tiles: "
    f"{plan.get('statistics_over_tiles')}, inexact samples: {plan.get('statistics_inexact')}",
    plan["k"], plan["rho"], plan["cell"], tiles, f"{plan['seconds_plan']:.1f}")
PY
rm -f "$scratch/memory.ply" "$scratch/tiles.ply"
