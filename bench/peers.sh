#!/usr/bin/env bash
# recon side by side with the peers a user would pick instead, where Debian
# packages them: Open3D and CGAL for oriented normals, PCL for the mesh.
# Wall time, peak memory and orientation accuracy against the true normals of
# a generated torus; writes bench/results/peers.md.
#
#   bench/peers.sh                        # 100k and 1M points: 10-25 minutes on 2 cores (Open3D and PCL at 1M take most of it)
#   PEERS_POINTS=20000 PEERS_OUTPUT=/tmp/peers.md bench/peers.sh   # a quick check
#
#   PEERS_POINTS      point counts, space-separated (default "100000 1000000")
#   PEERS_K           neighbours per tangent plane, the point itself included,
#                     given to every program (default 15)
#   PEERS_RESOLUTION  lattice cubes along the longest side, for recon
#                     reconstruct and PCL's MarchingCubesHoppe (default 256)
#   PEERS_TIMEOUT     seconds before a program is stopped (default 600)
#   PEERS_OUTPUT      the markdown written (default bench/results/peers.md)
#   PEERS_SKIP_INSTALL=1, PEERS_SKIP_BUILD=1
#
# Installs what it needs from Debian (libpcl-dev libcgal-dev libtbb-dev
# python3-open3d python3-numpy time) if missing; builds bench/peers, a CMake
# project of its own, into build/peers; builds recon only if
# build/release/app/recon is missing, and runs a copy of it so that a rebuild
# during the run changes nothing. Runs, inputs and outputs stay in
# build/peers/runs/N. Everything runs under `nice`, one program at a time.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
started=$SECONDS
points="${PEERS_POINTS:-100000 1000000}"
k="${PEERS_K:-15}"
resolution="${PEERS_RESOLUTION:-256}"
limit="${PEERS_TIMEOUT:-600}"
output="${PEERS_OUTPUT:-$root/bench/results/peers.md}"
peers_build="$root/build/peers"
runs="$peers_build/runs"
# Debian's python3-open3d lives in the system interpreter's dist-packages; a
# python3 earlier on PATH (pyenv, a virtualenv) would not see it.
python=/usr/bin/python3
cores="$(nproc)"

say() { echo "peers: $*" >&2; }

# --- (a) Debian packages ---------------------------------------------------
if [[ "${PEERS_SKIP_INSTALL:-0}" != 1 ]]; then
  missing=()
  for package in libpcl-dev libcgal-dev libtbb-dev python3-open3d python3-numpy time cmake g++; do
    dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q 'install ok installed' ||
      missing+=("$package")
  done
  if ((${#missing[@]})); then
    say "installing ${missing[*]}"
    sudo=()
    ((EUID == 0)) || sudo=(sudo)
    export DEBIAN_FRONTEND=noninteractive
    nice "${sudo[@]}" apt-get install -y --no-install-recommends "${missing[@]}" ||
      { nice "${sudo[@]}" apt-get update && nice "${sudo[@]}" apt-get install -y --no-install-recommends "${missing[@]}"; }
  fi
fi

# --- (b) builds --------------------------------------------------------------
if [[ ! -x build/release/app/recon ]]; then
  say "building recon (release preset)"
  nice cmake --preset release >/dev/null
  nice cmake --build build/release -j2 --target recon_cli
fi
if [[ "${PEERS_SKIP_BUILD:-0}" != 1 || ! -x "$peers_build/pcl_hoppe" ]]; then
  say "building bench/peers into build/peers"
  mkdir -p "$peers_build"
  nice cmake -S bench/peers -B "$peers_build" -DCMAKE_BUILD_TYPE=Release >"$peers_build/configure.log" 2>&1 ||
    { cat "$peers_build/configure.log" >&2; exit 1; }
  nice cmake --build "$peers_build" -j2 >/dev/null
fi
mkdir -p "$runs"
recon="$runs/recon"
cp build/release/app/recon "$recon"

# --- machine and revisions -------------------------------------------------
commit="$(git rev-parse --short HEAD)"
git diff --quiet HEAD -- include src app 2>/dev/null ||
  commit="$commit (with uncommitted changes to the library or CLI)"
version() { dpkg-query -W -f='${Version}' "$1" 2>/dev/null || echo "?"; }
header="$(
  echo "# recon and its peers"
  echo
  echo "Written by \`bench/peers.sh\`; the programs are in \`bench/peers/\`."
  echo
  echo "- date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "- recon: commit $commit, binary built $(date -u -r build/release/app/recon '+%Y-%m-%d %H:%M UTC')"
  echo "- cpu: $(lscpu | sed -n 's/^Model name: *//p'), $cores cores ($(nproc --all) online)"
  echo "- memory: $(free -g | awk '/^Mem:/ {print $2}') GiB; $(lsb_release -ds 2>/dev/null || sed -n 's/^PRETTY_NAME=//p' /etc/os-release | tr -d '"')"
  echo "- peers (Debian): Open3D $(version python3-open3d), PCL $(version libpcl-dev), CGAL $(version libcgal-dev), TBB $(version libtbb-dev), $(g++ --version | head -n 1)"
  echo "- k = $k for every program (the point itself included; CGAL, whose k excludes it, is given k - 1),"
  echo "  lattice $resolution cubes along the longest side for both meshes, time limit ${limit} s"
  echo "- load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
)"

# --- one program under time and timeout --------------------------------------
# run <name> <label> <kind> <reference> <threads> -- command...
run() {
  local name="$1" label="$2" kind="$3" reference="$4" threads="$5"
  shift 6
  local status=ok rc=0 start=$SECONDS
  say "  $label"
  rm -f "$dir/$name.time" "$dir/$name".*.json
  nice timeout --kill-after=10 "$limit" /usr/bin/time -f '%e %M %U %S' -o "$dir/$name.time" "$@" \
    >"$dir/$name.log" 2>&1 || rc=$?
  # 124: timeout's TERM ended it; 137 after the limit: its KILL did.
  if ((rc == 124 || (rc == 137 && SECONDS - start >= limit))); then
    status=stopped
    say "    stopped after $limit s"
  elif ((rc != 0)); then
    status="failed (exit $rc)"
    say "    failed with exit status $rc; see $dir/$name.log"
  fi
  printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$label" "$kind" "$reference" "$threads" "$status" >>"$dir/runs.tsv"
  [[ $status == ok ]]
}
compare() {  # <name> normals|mesh <file>
  local name="$1" what="$2" file="$3"
  local args=(mesh "$file")
  [[ $what == mesh ]] || args=(normals "$input" "$file")
  nice "$python" bench/peers/compare_normals.py "${args[@]}" >"$dir/$name.$what.json" ||
    { say "    no $what figures for $name"; rm -f "$dir/$name.$what.json"; }
}

# --- (c, d, e) per point count ----------------------------------------------
sections=()
for n in $points; do
  dir="$runs/$n"
  mkdir -p "$dir"
  rm -f "$dir/runs.tsv"
  echo "$n" >"$dir/points"
  echo "$limit" >"$dir/limit"
  input="$dir/torus.ply"
  say "$n points: generating $input"
  nice "$recon" generate torus -n "$n" --with-normals -o "$input" >/dev/null

  out="$dir/recon_normals.ply"
  run recon_normals "recon normals" normals recon_normals "$cores (all cores)" -- \
    "$recon" normals "$input" -o "$out" --k "$k" --stats "$dir/recon_normals.stats.json" &&
    compare recon_normals normals "$out"
  out="$dir/recon_mesh.ply"
  run recon_reconstruct "recon reconstruct" mesh recon_reconstruct "$cores (all cores)" -- \
    "$recon" reconstruct "$input" -o "$out" --k "$k" --resolution "$resolution" \
    --stats "$dir/recon_reconstruct.stats.json" &&
    compare recon_reconstruct mesh "$out"
  out="$dir/open3d_normals.ply"
  run open3d "Open3D estimate_normals + orient_normals_consistent_tangent_plane" normals recon_normals \
    "OpenMP, $cores" -- "$python" bench/peers/open3d_normals.py "$input" -o "$out" --k "$k" &&
    compare open3d normals "$out"
  out="$dir/cgal_normals.ply"
  run cgal "CGAL pca_estimate_normals + mst_orient_normals" normals recon_normals \
    "TBB $cores (PCA), 1 (MST)" -- "$peers_build/cgal_normals" "$input" -o "$out" --k "$k" --threads 0 &&
    compare cgal normals "$out"
  out="$dir/pcl_mesh.ply"
  run pcl "PCL NormalEstimationOMP + MarchingCubesHoppe (viewpoint orientation)" mesh recon_reconstruct \
    "OpenMP $cores (normals), 1 (MC)" -- "$peers_build/pcl_hoppe" "$input" -o "$out" \
    --normals-out "$dir/pcl_normals.ply" --k "$k" --resolution "$resolution" --threads 0 &&
    compare pcl normals "$dir/pcl_normals.ply" && compare pcl mesh "$out"
  sections+=("$dir")
done

# Memory Open3D costs before it sees a point: the interpreter and the import.
run_baseline() {
  nice /usr/bin/time -f '%M' -o "$runs/open3d_import.time" "$python" -c 'import open3d' >/dev/null 2>&1 &&
    awk '{printf "%.0f", $1 / 1024}' "$runs/open3d_import.time"
}
import_mib="$(run_baseline || echo '?')"

# --- (f) the report -----------------------------------------------------------
mkdir -p "$(dirname "$output")"
{
  echo "$header"
  echo "- load average after: $(cut -d' ' -f1-3 /proc/loadavg); the whole script took $(((SECONDS - started) / 60)) min $(((SECONDS - started) % 60)) s"
  echo
  cat <<EOF
How to read the tables:

- **wall s** and **peak MiB** are GNU time's (\`%e\`, \`%M\`) for the whole process:
  reading the PLY, the work, writing the result. Open3D runs in Python; the
  interpreter with \`import open3d\` alone takes ${import_mib} MiB and the import
  about 1.5 s, both included.
- **÷ recon**: wall time divided by \`recon normals\`'s for the normals-only
  programs (Open3D, CGAL) and by \`recon reconstruct\`'s for PCL, which builds a mesh.
- **CPU/wall**: user + system time over wall time, the cores a program kept busy.
  **threads** says what each may use: recon's parallel phases take all cores
  (\`--threads\` limits them); Open3D uses OpenMP; CGAL's PCA runs on TBB and
  its orientation on one thread; PCL's NormalEstimationOMP uses OpenMP and its
  MarchingCubesHoppe one thread.
- **outward %**: normals with a positive dot product with the true outward
  normal. **consistent %** is the larger of outward and inward: 100 for a
  program that oriented every normal the same way, right or wrong; about 50
  for one that did not orient. **|dot| > 0.9 %** judges the unoriented line
  alone (within about 26°). **undefined / unoriented**: NaN or zero normals
  (counted wrong), and for CGAL the points mst_orient_normals left unoriented.
- PCL has no orientation step: NormalEstimation flips every normal to face a
  viewpoint, the origin by default, which for this torus (around the origin)
  is the centre of its hole. That is what PCL does and what is measured; its
  mesh is contoured from those normals.
- **mesh vertices (unique)**: PCL writes one vertex per triangle corner; the
  unique count is the welded mesh. **dist. to torus**: distance from each mesh
  vertex to the true torus (R = 1, r = 0.35), RMS and largest; a spurious sheet
  shows as a large maximum.
- Where the peers' time goes (their own step timings are below each table):
  Open3D's orient_normals_consistent_tangent_plane builds its graph from a
  Delaunay tetrahedralisation of the whole cloud (Qhull; the Euclidean MST is a
  subgraph of it) plus the k-NN edges; PCL's MarchingCubesHoppe makes an exact
  nearest-neighbour query at every lattice vertex, near the points or not, on
  one thread.
- The machine may be shared: the load averages above say how busy it was, and
  a CPU/wall well below the threads a program may use is the sign of it.
- The inputs are \`recon generate torus -n N --with-normals\` (seed 1), uniform on
  the torus, no noise.

EOF
  "$python" bench/peers/report.py "${sections[@]}"
} >"$output"
say "wrote $output ($(((SECONDS - started) / 60)) min $(((SECONDS - started) % 60)) s)"
