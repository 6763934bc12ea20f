#!/usr/bin/env bash
# Phase VI (simplification.h) on the quality benchmark's clouds: the
# Hausdorff-95 to the true surface before and after simplifying to a tenth
# of the triangles, and its growth in units of the run's rho (issue 30: at
# most 0.5 rho). Then recon_simplify_bench: phase VI against Debian's
# meshoptimizer 0.18, and the time on a million triangles.
#
#   bench/simplify.sh                       # about 5 minutes on 2 cores
#   SIMPLIFY_CLOUDS="torus box" SIMPLIFY_BIG=0 bench/simplify.sh
#
#   SIMPLIFY_CLOUDS  names from bench/quality.sh's list (default: torus box part part-4100 noisy-torus bunny)
#   SIMPLIFY_RATIO   the fraction kept (default 0.1)
#   SIMPLIFY_BIG     points of the timing run (default 1000000; 0: skip)
set -euo pipefail

source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
clouds="${SIMPLIFY_CLOUDS:-torus box part part-4100 noisy-torus bunny}"
ratio="${SIMPLIFY_RATIO:-0.1}"
work="$root/build/simplify"
mkdir -p "$work"

echo "| cloud | triangles | simplified | H95 before | H95 after | growth / rho | seconds |"
echo "|---|---|---|---|---|---|---|"
for name in $clouds; do
  make_cloud "$name"
  "$recon" reconstruct "$work/$name.ply" -o "$work/$name-full.ply" --stats "$work/$name-full.json" -q
  "$recon" reconstruct "$work/$name.ply" -o "$work/$name-simple.ply" --simplify "$ratio" --stats "$work/$name-simple.json" -q
  $python - "$name" "$work" "$eval_dir" <<'PY'
import json, subprocess, sys
name, work, eval_dir = sys.argv[1:4]
def metrics(mesh):
    out = subprocess.run([sys.executable, f"{eval_dir}/metrics.py", mesh, f"{work}/{name}_gt.ply"],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)
full, simple = metrics(f"{work}/{name}-full.ply"), metrics(f"{work}/{name}-simple.ply")
before, after, diag = full["hausdorff95"], simple["hausdorff95"], full["diag"]
stats = json.load(open(f"{work}/{name}-simple.json"))
rho = stats["tangent_planes"]["rho"]
s = stats["simplification"]
print("| %s | %d | %d | %.3g | %.3g | %+.3f | %.3f |" % (name, s["triangles_before"], s["triangles_after"], before, after,
      (after - before) * diag / rho, s["seconds"]))
PY
done
echo
cmake --build --preset release --target recon_simplify_bench > /dev/null
"$root/build/release/bench/recon_simplify_bench" --big "${SIMPLIFY_BIG:-1000000}" --ratio "$ratio"
