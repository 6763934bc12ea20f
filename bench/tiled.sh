#!/usr/bin/env bash
# The scaling benchmark of tiled runs (tiles.h; docs/scaling.md): a
# scan-like terrain written by bench/terrain_stream.py (never held whole),
# reconstructed
#   1. in memory, at 10M points (the reference per point),
#   2. in tiles under --max-memory 8G, at 10M and at N points,
#   3. on a local Dask cluster of 2 workers (python3 -m recon.distributed),
#      at N points,
# printing one markdown row per run: points, seconds, microseconds a point,
# peak resident memory (the run's --stats; for Dask, the largest worker's
# and the client's), tiles, triangles. Each run's --stats is kept as
# stats-N.json.
#
#   bench/tiled.sh                 # N = 100M: about 25 GB of disk under $SCRATCH, 15-25 minutes
#   N=20000000 SCRATCH=/tmp bench/tiled.sh
#   SKIP_DASK=1 bench/tiled.sh
#
# Run it on a quiet machine: it uses both cores throughout.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
recon="$root/build/release/app/recon"
n="${N:-100000000}"
scratch="${SCRATCH:-/tmp}/recon-scaling"
mkdir -p "$scratch"
[[ -x "$recon" ]] || { echo "build first: cmake --build --preset release" >&2; exit 1; }

terrain() {  # terrain POINTS: the file's path, written once
  local file="$scratch/terrain-$1.ply"
  [[ -f "$file" ]] || /usr/bin/python3 "$root/bench/terrain_stream.py" "$1" "$file"
  echo "$file"
}

# row LABEL POINTS STATS TIMEFILE
row() {
  /usr/bin/python3 - "$@" <<'EOF'
import json, sys
label, points, stats, timing = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
seconds, kib = open(timing).read().split()
s = json.load(open(stats))
tiles = s.get("tiled", {}).get("tiles", "-")
# (The peak from --stats: an in-memory run clears the kernel's high-water
# mark at each phase to measure the phases' own, so GNU time's is the last
# phase's there.)
kib = s.get("memory", {}).get("peak_mib_total", int(kib) / 1024) * 1024
mesh = s.get("mesh", {})
triangles = mesh.get("triangles", mesh.get("faces"))  # (an in-memory run's summary says faces)
triangles = f"{triangles:,}" if isinstance(triangles, int) else "-"
print(f"| {label} | {points:,} | {float(seconds):.0f} | {1e6 * float(seconds) / points:.2f} | "
      f"{int(kib) / 1024:.0f} | {tiles} | {triangles} |")
EOF
}

run() {  # run LABEL POINTS ARGS...
  local label="$1" points="$2"
  shift 2
  /usr/bin/time -f "%e %M" -o "$scratch/time.txt" "$recon" --quiet reconstruct "$@" --stats "$scratch/stats.json" \
    -o "$scratch/mesh.ply"
  row "$label" "$points" "$scratch/stats.json" "$scratch/time.txt"
  runs=$((${runs:-0} + 1))
  cp "$scratch/stats.json" "$scratch/stats-$runs.json"  # (kept for the details)
  rm -f "$scratch/mesh.ply"
}

echo "machine: $(nproc) cores, $(free -g | awk '/Mem:/ {print $2}') GiB; commit $(git -C "$root" rev-parse --short HEAD); $(date -u +%F)"
echo
echo "| run | points | seconds | us / point | peak MiB | tiles | triangles |"
echo "|---|---|---|---|---|---|---|"
ten="$(terrain 10000000)"
run "in memory (refined, phases I-V)" 10000000 "$ten"
run "in memory, hoppe92" 10000000 "$ten" --method hoppe92
run "tiles, --max-memory 8G (refined, phases I-V)" 10000000 "$ten" --max-memory 8G --tile-size 0.7
big="$(terrain "$n")"
run "tiles, --max-memory 8G (refined, phases I-V)" "$n" "$big" --max-memory 8G
if [[ "${SKIP_DASK:-0}" != 1 ]]; then
  PYTHONPATH="$root/build/release/python" /usr/bin/time -f "%e %M" -o "$scratch/time.txt" /usr/bin/python3 \
    -m recon.distributed "$big" -o "$scratch/mesh.ply" --workers 2 --max-memory 8G --stats "$scratch/stats.json" --quiet
  /usr/bin/python3 - "$n" "$scratch/stats.json" "$scratch/time.txt" <<'EOF2'
import json, sys
points, s = int(sys.argv[1]), json.load(open(sys.argv[2]))
seconds = float(open(sys.argv[3]).read().split()[0])
workers = ", ".join(f"{w['peak_rss_mib']:.0f}" for w in s["workers"].values())
print(f"| Dask, 2 local workers (peak: client {s['client_peak_rss_mib']:.0f}; workers {workers}) | {points:,} | "
      f"{seconds:.0f} | {1e6 * seconds / points:.2f} | {max(w['peak_rss_mib'] for w in s['workers'].values()):.0f} | "
      f"{s['plan']['tiles']} | {s['mesh']['triangles']:,} |")
EOF2
  rm -f "$scratch/mesh.ply"
fi
