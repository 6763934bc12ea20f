#!/usr/bin/env bash
# Builds the release preset, runs both benchmarks, and writes everything
# (machine, commit, summary tables, raw output) to bench/results/latest.txt;
# prints the markdown summary tables too.
#
#   bench/run.sh                      # about 4 minutes on 2 cores, plus the build
#   RECON_BENCH_SWEEP=1 bench/run.sh  # also the kd-tree leaf-size sweep (3 more minutes)
#   RECON_END_TO_END="torus:1000000" bench/run.sh   # end-to-end runs: shape:points ...
#   RECON_BENCH_REPS=3 bench/run.sh   # more repetitions (default and least 2; the
#                                     # tables show the fastest repetition)
#   RECON_BENCH_SKIP_BUILD=1 bench/run.sh
#   RECON_BENCH_FILTER='n:100000/' RECON_BENCH_SWEEP_FILTER='leaf:8/' \
#     RECON_PIPELINE_ARGS='--points 20000' bench/run.sh   # a quick subset
#
# Everything runs under `nice` and builds with -j2: the machine is shared.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
reps="${RECON_BENCH_REPS:-2}"
((reps >= 2)) || reps=2  # with one repetition there is no "min" row (and the CSV writer aborts)
build="$root/build/release"
results="$root/bench/results"
mkdir -p "$results"
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT

if [[ "${RECON_BENCH_SKIP_BUILD:-0}" != 1 ]]; then
  # Boost.Graph, the reference for Prim (recon_graph_bench); not needed by
  # recon itself, so scripts/setup does not install it.
  if ! dpkg-query -W -f='${Status}' libboost-graph-dev 2>/dev/null | grep -q 'install ok installed'; then
    sudo=()
    ((EUID == 0)) || sudo=(sudo)
    DEBIAN_FRONTEND=noninteractive nice "${sudo[@]}" apt-get install -y --no-install-recommends libboost-graph-dev
  fi
  nice cmake --preset release >/dev/null
  nice cmake --build "$build" -j2
fi

# --- machine and revision --------------------------------------------------
compiler="$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$build/CMakeCache.txt")"
commit="$(git rev-parse --short HEAD)"
git diff --quiet HEAD -- include src 2>/dev/null || commit="$commit (library has uncommitted changes)"
{
  echo "# recon benchmarks"
  echo
  echo "- date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "- commit: $commit"
  echo "- cpu: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores"
  echo "- memory: $(free -g | awk '/^Mem:/ {print $2}') GiB"
  echo "- kernel: $(uname -r)"
  echo "- compiler: $("${compiler:-c++}" --version | head -n 1)"
  echo "- load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "- kd-tree figures: fastest of $reps repetitions (Google Benchmark 'min')"
  echo
} >"$scratch/header.md"

# --- kd-tree ---------------------------------------------------------------
# Two runs, because Google Benchmark's CSV output needs every row of one run
# to have the same counters: the comparisons, then the leaf-size sweep.
# Repetitions are interleaved in random order, so that a colleague's build
# slows ours and nanoflann's runs alike rather than whichever came first.
kdtree_bench() {  # <filter> <name>
  nice "$build/bench/recon_kdtree_bench" --benchmark_filter="$1" --benchmark_min_time=0.2 \
    --benchmark_repetitions="$reps" --benchmark_enable_random_interleaving=true \
    --benchmark_report_aggregates_only=true \
    --benchmark_out="$scratch/$2.csv" --benchmark_out_format=csv >"$scratch/$2.txt" 2>&1
}
kdtree_bench "${RECON_BENCH_FILTER:-^(build|knn|planes)_}" compare
if [[ "${RECON_BENCH_SWEEP:-0}" == 1 ]]; then
  kdtree_bench "${RECON_BENCH_SWEEP_FILTER:-^leaf_sweep_}" sweep
else
  : >"$scratch/sweep.csv"
  echo "(leaf-size sweep skipped; RECON_BENCH_SWEEP=1 runs it)" >"$scratch/sweep.txt"
fi

# Markdown tables from the CSV's "min" rows. Wall times in ms; "cores" is
# process CPU time / wall time (2 for a clean 2-thread run; less means the
# machine was busy).
awk -F, '
  function column(name) { return (name in col) ? $col[name] : "" }
  function ratio(a, b) { return (a != "" && b != "" && b > 0) ? sprintf("%.2f", a / b) : "-" }
  function ms(x) { return x == "" ? "-" : sprintf("%.1f", x) }
  function sec(x) { return x == "" ? "-" : sprintf("%.3f", x) }
  function cores(key) { return (key in wall && wall[key] > 0) ? sprintf("%.1f", cpu[key] / wall[key]) : "-" }
  $1 == "name" {
    for (i = 1; i <= NF; ++i) { h = $i; gsub(/"/, "", h); col[h] = i }
    next
  }
  {
    name = $1; gsub(/"/, "", name)
    if (name !~ /_min$/) next
    sub(/(\/process_time)?\/real_time_min$/, "", name)
    if (match(name, /\/leaf:[0-9]+$/) && name ~ /^build_/) {  # build rows: one leaf size each
      leaf[substr(name, 1, index(name, "/") - 1)] = substr(name, RSTART + 6)
      name = substr(name, 1, RSTART - 1)
    }
    wall[name] = column("real_time"); cpu[name] = column("cpu_time")
    build_s[name] = column("build_s"); knn_s[name] = column("knn_s")
  }
  END {
    print "### kd-tree build (ms)"
    print ""
    print "| points | ours (leaf " leaf["build_ours"] ") | nanoflann (leaf " leaf["build_nanoflann"] ") | ours / nanoflann |"
    print "|---:|---:|---:|---:|"
    split("100000 1000000", sizes, " ")
    for (s = 1; s <= 2; ++s) {
      o = "build_ours/n:" sizes[s] "/morton:0"; f = "build_nanoflann/n:" sizes[s] "/morton:0"
      print "| " sizes[s] " | " ms(wall[o]) " | " ms(wall[f]) " | " ratio(wall[o], wall[f]) " |"
    }
    print ""
    print "### all k-NN, k = 15 (ms; cores = CPU time / wall time)"
    print ""
    print "| points | threads | input order | ours all_knn | cores | nanoflann loop | cores | ours / nanoflann | ours knn() loop in input order |"
    print "|---:|---:|---|---:|---:|---:|---:|---:|---:|"
    for (s = 1; s <= 2; ++s)
      for (t = 1; t <= 2; ++t)
        for (m = 0; m <= 1; ++m) {
          args = "n:" sizes[s] "/threads:" t "/morton:" m
          o = "knn_ours/" args; f = "knn_nanoflann/" args; l = "knn_ours_loop/" args
          print "| " sizes[s] " | " t " | " (m ? "Morton" : "sampled") " | " ms(wall[o]) " | " cores(o) " | " \
                ms(wall[f]) " | " cores(f) " | " ratio(wall[o], wall[f]) " | " ms(wall[l]) " |"
        }
    print ""
    print "### phase I floor: build + k-NN + PCA, k = 15, Morton order (ms)"
    print ""
    print "| points | threads | ours (estimate_tangent_planes) | cores | nanoflann + Eigen | cores | ours / theirs |"
    print "|---:|---:|---:|---:|---:|---:|---:|"
    for (s = 1; s <= 2; ++s)
      for (t = 1; t <= 2; ++t) {
        o = "planes_ours/n:" sizes[s] "/threads:" t; f = "planes_nanoflann_eigen/n:" sizes[s] "/threads:" t
        print "| " sizes[s] " | " t " | " ms(wall[o]) " | " cores(o) " | " ms(wall[f]) " | " cores(f) " | " ratio(wall[o], wall[f]) " |"
      }
    if (!("leaf_sweep_ours/leaf:16/morton:0" in wall)) exit
    print ""
    print "### leaf-size sweep, 1M points, one thread: build + all_knn(15) (s)"
    print ""
    print "| leaf | ours build | ours all-kNN | ours total | nanoflann build | nanoflann all-kNN | nanoflann total |"
    print "|---:|---:|---:|---:|---:|---:|---:|"
    split("4 6 8 10 12 16 24 32", leaves, " ")
    best = ""
    for (l = 1; l <= 8; ++l) {
      o = "leaf_sweep_ours/leaf:" leaves[l] "/morton:0"; f = "leaf_sweep_nanoflann/leaf:" leaves[l] "/morton:1"
      if (wall[o] != "" && (best == "" || wall[o] < wall[best])) { best = o; best_leaf = leaves[l] }
      print "| " leaves[l] " | " sec(build_s[o]) " | " sec(knn_s[o]) " | " sec(wall[o] == "" ? "" : wall[o] / 1000) " | " \
            sec(build_s[f]) " | " sec(knn_s[f]) " | " sec(wall[f] == "" ? "" : wall[f] / 1000) " |"
    }
    print ""
    print "Fastest leaf size for ours (build + all-kNN, sampled order): " best_leaf
    print "(ours swept on the sampled order, nanoflann on the Morton order; see kdtree_bench.cpp)"
  }
' "$scratch/compare.csv" "$scratch/sweep.csv" >"$scratch/kdtree.md"

# --- Prim: ours against a lazy std::priority_queue and Boost ----------------
if [[ -x "$build/bench/recon_graph_bench" ]]; then
  nice "$build/bench/recon_graph_bench" --benchmark_repetitions="$reps" --benchmark_report_aggregates_only=true \
    >"$scratch/graph.txt" 2>&1
  {
    echo "### Prim on phase II's graph (1M-point torus, one thread; ms, fastest of $reps)"
    echo
    grep '^check' "$scratch/graph.txt" || true
    echo
    echo "| Prim | ms |"
    echo "|---|---:|"
    awk '$1 ~ /_min$/ { name = $1; sub(/_min$/, "", name); print "| " name " | " $2 " |" }' "$scratch/graph.txt"
  } >"$scratch/graph.md"
else
  echo "(recon_graph_bench not built: Boost.Graph missing)" >"$scratch/graph.md"
fi

# --- the lab's spanning trees: each queue under Prim, Kruskal, Borůvka --------
nice "$build/bench/recon_mst_bench" --reps "$reps" >"$scratch/mst.md" 2>&1

# --- pipeline --------------------------------------------------------------
# shellcheck disable=SC2086  # word splitting of the arguments is wanted
nice "$build/bench/recon_pipeline_bench" ${RECON_PIPELINE_ARGS:---points 100000 --points 1000000 --refine} \
  >"$scratch/pipeline.md" 2>&1

# --- end to end: the program, reading and writing included ------------------
# `recon reconstruct` on generated files (binary PLY); time and peak memory
# from its own --stats (seconds_total; memory.peak_mib_total, the largest
# per-step peak of the whole process). /usr/bin/time's maximum RSS would be
# wrong here: recon resets the kernel's peak between steps.
end_to_end() {  # <shape> <points>
  local shape="$1" n="$2"
  "$build/app/recon" -q generate "$shape" -n "$n" -o "$scratch/$shape-$n.ply"
  local started ended
  started=$(date +%s.%N)
  nice "$build/app/recon" -q reconstruct "$scratch/$shape-$n.ply" -o "$scratch/mesh.ply" --stats "$scratch/stats.json"
  ended=$(date +%s.%N)
  /usr/bin/python3 - "$shape" "$n" "$started" "$ended" "$scratch/stats.json" <<'PY'
import json, sys
shape, n, started, ended, path = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4]), sys.argv[5]
s = json.load(open(path))
t, o, d, c = s["tangent_planes"], s["orientation"], s["signed_distance"], s["contouring"]
one = t["seconds_tree"] + t["seconds_knn_pca"] + t["seconds_spacing"]
two = o["seconds_emst"] + o["seconds_graph"] + o["seconds_mst"]
m = s["mesh"]
print(f"| {shape} | {n} | {ended - started:.2f} | {(ended - started) / (n / 1e6):.2f} | {s['input']['seconds']:.2f} | "
      f"{one:.2f} | {two:.2f} | {d['seconds']:.2f} (+{d.get('seconds_beside_orientation', 0.0):.2f}) | "
      f"{c['seconds']:.2f} | {s['output']['seconds']:.2f} | "
      f"{s['memory']['peak_mib_total']:.0f} | {m['faces']} | {m['components']}, {m['boundary_loops']}, "
      f"{m['euler_characteristic']} |")
PY
  rm -f "$scratch/$shape-$n.ply" "$scratch/mesh.ply"
}
{
  echo "| shape | points | wall s | s per 1M points | read | I | II | III (+ beside II) | IV | write | peak MiB | mesh F | components, boundary loops, chi |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"
  for run in ${RECON_END_TO_END:-torus:1000000 terrain:100000 terrain:1000000 terrain:3000000 terrain:10000000}; do
    end_to_end "${run%%:*}" "${run##*:}"
  done
} >"$scratch/end_to_end.md"

{
  cat "$scratch/header.md"
  echo "## kd-tree against nanoflann"
  echo
  cat "$scratch/kdtree.md"
  echo
  cat "$scratch/graph.md"
  echo
  echo "## The lab's spanning trees (recon_mst_bench: Riemannian graph of the torus, one thread)"
  echo
  cat "$scratch/mst.md"
  echo
  echo "## Pipeline (recon_pipeline_bench)"
  echo
  cat "$scratch/pipeline.md"
  echo
  echo "## End to end (recon reconstruct, all threads)"
  echo
  cat "$scratch/end_to_end.md"
  echo
  echo "- load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo
  echo "## Raw output of recon_kdtree_bench"
  echo
  echo '```'
  grep -h -v -e '_mean ' -e '_stddev ' "$scratch/compare.txt" "$scratch/sweep.txt"
  echo '```'
} >"$results/latest.txt"

cat "$scratch/header.md" "$scratch/kdtree.md"
echo
cat "$scratch/graph.md"
echo
cat "$scratch/mst.md"
echo
cat "$scratch/pipeline.md"
echo
cat "$scratch/end_to_end.md"
echo
echo "written: ${results#"$root"/}/latest.txt"
