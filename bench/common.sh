# Sourced by the bench scripts (methods.sh, quality.sh, simplify.sh): the
# checkout's root as the working folder, the program (built when missing),
# and the quality benchmark's clouds, so that every script measures the same.
#
#   root, recon, python    the checkout, build/release's program, the system's python3
#   eval_dir, data_dir     ../shared/eval and ../shared/data, or QUALITY_EVAL, QUALITY_DATA
#   make_cloud NAME        $work/NAME.ply (the cloud) and $work/NAME_gt.ply (the truth)

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
python=/usr/bin/python3
recon="$root/build/release/app/recon"
[ -x "$recon" ] || cmake --build --preset release --target recon_cli
eval_dir="${QUALITY_EVAL:-$root/../shared/eval}"
data_dir="${QUALITY_DATA:-$root/../shared/data}"

# Needs $work, the folder the caller writes into.
make_cloud() {
  local name="$1" out="$work/$1.ply"
  case "$name" in
    sphere|torus) $python "$eval_dir/gen_synthetic.py" "$name" "$out" --n 100000 --seed 1 ;;
    box) $python "$eval_dir/gen_synthetic.py" box "$out" --n 60000 --seed 1 ;;
    plate) $python "$eval_dir/gen_synthetic.py" plate "$out" --n 40000 --thickness 0.05 --seed 1 ;;
    noisy-torus) $python "$eval_dir/gen_synthetic.py" torus "$out" --n 100000 --noise 0.002 --seed 1 ;;
    ellipsoid|part|handle) "$recon" generate "$name" -n 20000 --seed 1 -o "$out" --truth "$work/${name}_gt.ply" ;;
    part-4100) "$recon" generate part -n 4100 --seed 1 -o "$out" --truth "$work/${name}_gt.ply" ;;
    conics) "$recon" generate conics --seed 1 -o "$out" --truth "$work/${name}_gt.ply" ;;
    scan-part) "$recon" generate part --scan 4 -n 40000 --noise 0.002 --misregistration 0.001 --seed 1 -o "$out" --truth "$work/${name}_gt.ply" ;;
    scan-conics) "$recon" generate conics --scan 4 -n 20000 --noise 0.005 --seed 1 -o "$out" --truth "$work/${name}_gt.ply" ;;
    plate-thin) "$recon" generate plate --thickness 0.015 -n 40000 --seed 1 -o "$out" --truth "$work/${name}_gt.ply" ;;
    club|cup|two-cavities) "$recon" generate "$name" -n 40000 --seed 1 -o "$out" --truth "$work/${name}_gt.ply" ;;
    bunny)  # the scan's vertices are the cloud (every program reads a PLY's vertices); its mesh is the truth
      cp "$data_dir/stanford_bunny/bun_zipper.ply" "$work/bunny_gt.ply"
      cp "$data_dir/stanford_bunny/bun_zipper.ply" "$out" ;;
    *) echo "$(basename "$0"): unknown cloud '$name'" >&2; exit 2 ;;
  esac > /dev/null
}
