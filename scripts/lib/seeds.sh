# Sourced by the scripts that take --seeds A-B (realdata, scan-consistency-table, office3d-runs):
# parse_seeds NAME A-B sets $first and $last, or exits 2 with one line naming the script.
parse_seeds() {
  first=${2%-*} last=${2#*-}
  [[ "$first" =~ ^[0-9]+$ && "$last" =~ ^[0-9]+$ && $first -le $last ]] || {
    echo "$1: --seeds '$2' is not A-B" >&2
    exit 2
  }
}
