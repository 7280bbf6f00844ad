#!/bin/bash
# Compares a candidate heightmap network with the shipped one, linear interpolation and the
# paper's released model on surveys that neither network was trained on (issue 17): for every
# survey, texel size and density, `lidarscout eval` scores the same patches with
# linear + the candidate, linear + the shipped model and linear + the released model; one table
# per texel size and density (python3 -m lidarscout_train.loso table --shipped-dir) with the
# survey means, written as JSON to --json-dir.
#
#   scripts/compare_models.sh --candidate MODEL.pt [--shipped MODEL.pt] [--released FILE]
#       [--texels 10,5] [--densities 40,1500] [--patches 150] [--offsets 8] [--threads 1]
#       [--work DIR] [--json-dir DIR] SURVEY_DIR...
#
#   Without --candidate only the shipped and released columns are scored (ahead of a candidate;
#   no table).
#   --densities LIST  besides the auto stride (about 369 chunk points per window), the strides that
#                     give these many chunk points per window (from a probe file at the auto stride)
#   --released FILE   the paper's ipes_cnn.pt converted for the CPU (python3 -m lidarscout_train.released_cpu)
#   --work DIR        eval outputs (default /work/nnwork/compare); resumable: an existing output is kept
#   --json-dir DIR    tables as TEXELm[.cpN].json (default DIR/tables)
set -euo pipefail

# All in one function, so that bash reads the whole file before running any of it.
main() {
cd "$(dirname "$0")/.."
repo=$(pwd)
candidate=""
shipped=models/heightmap_cnn.pt
released=""
texels=10
densities=""
patches=150
offsets=8
threads=1
work=/work/nnwork/compare
json_dir=""
bin=build/lidarscout
surveys=()
while [ $# -gt 0 ]; do
  case "$1" in
    --candidate) candidate="$(realpath "$2")"; shift 2 ;;
    --shipped) shipped="$2"; shift 2 ;;
    --released) released="$(realpath "$2")"; shift 2 ;;
    --texels) texels="$2"; shift 2 ;;
    --densities) densities="$2"; shift 2 ;;
    --patches) patches="$2"; shift 2 ;;
    --offsets) offsets="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    --work) work="$2"; shift 2 ;;
    --json-dir) json_dir="$2"; shift 2 ;;
    --lidarscout) bin="$2"; shift 2 ;;
    -*) echo "compare_models.sh: unknown option $1" >&2; exit 2 ;;
    *) surveys+=("$(realpath "$1")"); shift ;;
  esac
done
[ "${#surveys[@]}" -gt 0 ] || { echo "compare_models.sh: no surveys given" >&2; exit 2; }
json_dir="${json_dir:-$work/tables}"
mkdir -p "$work/probe" "$work/candidate" "$work/shipped" "$work/released" "$json_dir"
py() { (cd "$repo/python" && /usr/bin/python3 -m "$@"); }

score() {  # dir name survey texel stride-args...: one eval into dir/name.json unless it exists
  local out="$work/$1/$2.json"
  [ -f "$out" ] && return
  local methods=(--methods linear,cnn --model "$candidate")
  [ "$1" = shipped ] && methods=(--methods linear,cnn --model "$shipped")
  [ "$1" = released ] && methods=(--methods linear,released --released-model "$released")
  "$bin" eval "$3" "${methods[@]}" --texel "$4" --patches "$patches" --offsets "$offsets" --threads "$threads" \
    --json "${@:5}" > "$out.tmp"
  mv "$out.tmp" "$out"
}

for texel in ${texels//,/ }; do
  for tag in "" ${densities//,/ }; do
    names=()
    for s in "${surveys[@]}"; do
      name="$(basename "$s").${texel}m${tag:+.cp$tag}"
      stride=()
      if [ -n "$tag" ]; then
        probe="$work/probe/$(basename "$s").${texel}m.bin"
        [ -f "$probe" ] || "$bin" train-data "$s" -o "$probe" --texel "$texel" --patches 1 --val-fraction 0 \
          --threads "$threads" > /dev/null
        stride=(--stride "$(py lidarscout_train.loso stride "$probe" "$tag")")
      fi
      [ -z "$candidate" ] || score candidate "$name" "$s" "$texel" "${stride[@]}"
      score shipped "$name" "$s" "$texel" "${stride[@]}"
      [ -z "$released" ] || score released "$name" "$s" "$texel" "${stride[@]}"
      names+=("$work/candidate/$name.json")
    done
    [ -n "$candidate" ] || continue
    echo
    echo "${texel} m texels, ${tag:-auto (about 369)} chunk points per window:"
    py lidarscout_train.loso table "${names[@]}" --shipped-dir "$work/shipped" --released-dir "$work/released" \
      --json "$(realpath "$json_dir")/${texel}m${tag:+.cp$tag}.json"
  done
done
}

main "$@"
