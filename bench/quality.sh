#!/usr/bin/env bash
# How close each reconstruction lies to the true surface: recon's default
# (refined) and --method hoppe92 beside Kazhdan's PoissonRecon (depth 8 and
# 10, given recon's own oriented normals from `recon normals`; and depth 10
# trimmed by SurfaceTrimmer at 7, as for open scans) and Open3D's and CGAL's
# Screened Poisson,
# on the same clouds, measured by ../shared/eval/metrics.py (Chamfer,
# Hausdorff-95, relative to the true surface's bounding-box diagonal, and the
# topology). Writes bench/results/quality.md.
#
#   bench/quality.sh                       # every cloud: about 10 minutes on 2 cores
#   QUALITY_CLOUDS="torus box" bench/quality.sh
#
#   QUALITY_CLOUDS   names from the list below (default: all)
#   QUALITY_OUTPUT   the markdown written (default bench/results/quality.md)
#   QUALITY_EVAL     the evaluation scripts (default ../shared/eval)
#   QUALITY_DATA     the real data (default ../shared/data)
#   QUALITY_PEERS    PoissonRecon and SurfaceTrimmer (default ../shared/peers/poissonrecon)
#
# Clouds: gen_synthetic.py's sphere, torus, box (rotated, sharp), plate
# (thickness 0.05), torus with 0.2 % noise; recon generate's ellipsoid, part
# (genus 3, creases) at 20,000 and at 4,100 points, handle, conics; the
# Stanford bunny (its vertices, measured against its own mesh); recon
# generate --scan's noisy, occluded scans of the part and the conics
# (measured against the whole true surface, so their holes count: compare
# with trimmed Poisson); thin solids: a plate 0.015 thick (0.46 rho),
# the club, the cup, two nested cavities. Needs
# python3-numpy python3-scipy python3-open3d libcgal-dev (bench/peers.sh
# installs them); builds bench/peers' cgal_poisson into build/peers.
set -euo pipefail

source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
output="${QUALITY_OUTPUT:-$root/bench/results/quality.md}"
clouds="${QUALITY_CLOUDS:-sphere torus box plate noisy-torus ellipsoid part part-4100 handle conics bunny scan-part scan-conics plate-thin club cup two-cavities}"
work="$root/build/quality"
mkdir -p "$work"
cmake -S bench/peers -B build/peers -DCMAKE_BUILD_TYPE=Release -G Ninja > "$work/peers-configure.log"
cmake --build build/peers --target cgal_poisson > "$work/peers-build.log"
cgal="$root/build/peers/cgal_poisson"
kazhdan="${QUALITY_PEERS:-$root/../shared/peers/poissonrecon}"
export OMP_WAIT_POLICY=passive  # PoissonRecon's threads otherwise spin on a shared machine

# PoissonRecon at depth 8 and 10 from recon's own oriented normals, and the
# depth-10 mesh trimmed (SurfaceTrimmer --trim 7) where it lies far from the data.
kazhdan_poisson() {
  local name="$1" cloud="$2"
  rm -f "$work/$name-pr8.ply" "$work/$name-pr10.ply" "$work/$name-pr10t.ply"
  [ -x "$kazhdan/PoissonRecon" ] || return 0
  "$recon" normals "$cloud" -o "$work/$name-oriented.ply" > /dev/null 2>&1 || return 0
  for depth in 8 10; do
    timeout 900 "$kazhdan/PoissonRecon" --in "$work/$name-oriented.ply" --out "$work/$name-pr$depth.ply" \
      --depth "$depth" --density > /dev/null 2>&1 || rm -f "$work/$name-pr$depth.ply"
  done
  [ -s "$work/$name-pr10.ply" ] && { "$kazhdan/SurfaceTrimmer" --in "$work/$name-pr10.ply" --out "$work/$name-pr10t.ply" \
    --trim 7 > /dev/null 2>&1 || rm -f "$work/$name-pr10t.ply"; }
  return 0
}

# One row: method, Chamfer, Hausdorff-95, components, watertight, Euler.
measure() {
  local mesh="$1" gt="$2" label="$3"
  if [ ! -s "$mesh" ]; then
    echo "| $label | failed | | | | |"
    return
  fi
  $python "$eval_dir/metrics.py" "$mesh" "$gt" | $python -c '
import json, sys
d = json.load(sys.stdin)
if "error" in d:
    print("| %s | %s | | | | |" % (sys.argv[1], d["error"]))
    sys.exit(0)
print("| %s | %.3g | %.3g | %d | %s | %d |" % (sys.argv[1], d["chamfer"], d["hausdorff95"], d["components"],
      "yes" if d["watertight"] else "no, %d boundary edges" % d["boundary_edges"], d["euler"]))' "$label"
}

{
  echo "# Quality: distance to the true surface"
  echo
  echo "Written by \`bench/quality.sh\` on $(date -u +%Y-%m-%d), commit $(git rev-parse --short HEAD)$(git diff --quiet || echo ' with local changes'),"
  echo "$(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2 / 1048576}' /proc/meminfo)."
  echo "Chamfer and Hausdorff-95 are relative to the true surface's bounding-box diagonal (\`metrics.py\`);"
  echo "every program at its defaults (Open3D: k = 30, depth 8; CGAL: k = 24 for the jet normals and the MST orientation, Poisson at the average spacing; PoissonRecon 18.75 at its defaults but the depth, given \`recon normals\`' output)."
  echo
} > "$output.tmp"
for name in $clouds; do
  make_cloud "$name"
  cloud="$work/$name.ply"
  gt="$work/${name}_gt.ply"
  "$recon" reconstruct "$cloud" -o "$work/$name-refined.ply" > /dev/null 2>&1 || rm -f "$work/$name-refined.ply"
  "$recon" reconstruct "$cloud" --method hoppe92 -o "$work/$name-hoppe92.ply" > /dev/null 2>&1 || rm -f "$work/$name-hoppe92.ply"
  timeout 900 $python bench/peers/open3d_poisson.py "$cloud" -o "$work/$name-open3d.ply" > /dev/null 2>&1 || rm -f "$work/$name-open3d.ply"
  timeout 900 "$cgal" "$cloud" -o "$work/$name-cgal.ply" > /dev/null 2>&1 || rm -f "$work/$name-cgal.ply"
  kazhdan_poisson "$name" "$cloud"
  {
    echo "## $name"
    echo
    echo "| method | Chamfer | Hausdorff-95 | components | closed | Euler |"
    echo "|---|---|---|---|---|---|"
    measure "$work/$name-refined.ply" "$gt" "recon (default: refined)"
    measure "$work/$name-hoppe92.ply" "$gt" "recon --method hoppe92"
    measure "$work/$name-open3d.ply" "$gt" "Open3D Poisson"
    measure "$work/$name-cgal.ply" "$gt" "CGAL Poisson"
    measure "$work/$name-pr8.ply" "$gt" "PoissonRecon depth 8 (recon's normals)"
    measure "$work/$name-pr10.ply" "$gt" "PoissonRecon depth 10 (recon's normals)"
    measure "$work/$name-pr10t.ply" "$gt" "PoissonRecon depth 10, trimmed at 7"
    echo
  } | tee -a "$output.tmp"
done
mv "$output.tmp" "$output"
echo "wrote $output"
