# Sourced by the scripts that run two builds side by side (two_builds.sh,
# simplify_speed.sh) with the script's arguments OLD_RECON NEW_RECON:
#
#   old, new                the two programs
#   root, scratch           the checkout, and a folder removed when the script ends
#   alternate_builds STEP   STEP RUN BUILD PROGRAM for runs 1 to $runs, old then new

[ $# -eq 2 ] || { echo "usage: $0 OLD_RECON NEW_RECON" >&2; exit 2; }
old="$1"
new="$2"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT

# The builds alternate, so that a shared, noisy machine slows both alike.
alternate_builds() {
  local run
  for run in $(seq 1 "$runs"); do
    "$1" "$run" old "$old"
    "$1" "$run" new "$new"
  done
}
