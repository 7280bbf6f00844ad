#!/bin/bash
# The heightmap network trained in one short GPU run (issue 35): the seven leave-one-survey-out
# folds and the final model of the relief-scaled network with the shipped per-window RMSE loss, at
# the whole, half and quarter length (fast_train plan), all at once on one GPU within a wall-clock
# budget (python/lidarscout_train/fast_train.py), then exported and scored here.
#
#   scripts/train_gpu.sh data   [--work DIR] [--extra DIR] [--threads N]
#       training windows of every survey of ../shared/data/surveys and every extra source of
#       scripts/build_training_set.sh (less the three held out for the unseen comparison):
#       10 m windows at six chunk-point densities (scripts/density_windows.sh) and 1, 2.5 and 5 m
#       windows at the auto stride (the first run had 2.5 and 5 m only). Resumable.
#   scripts/train_gpu.sh pack   [--work DIR] [--per-group N] [--tree DIR]
#       a random N windows (default 42) of every (file, texel size) group, losslessly into
#       DIR/windows.xz (default .gpu-train, git-ignored); what travels to the device machine (this
#       repository's files and the tree) is at most 64 MiB, so it fails when the tree does not fit.
#   scripts/train_gpu.sh run    [--tree DIR] [--budget S] [--out DIR] [--device cuda|cpu] [--tiny] [--runs A,B]
#       ON THE GPU MACHINE (from the repository root, the tree carried): unpacks the windows, starts
#       one training process per model (python3 -m lidarscout_train.fast_train) with a common
#       deadline S seconds ahead (default 450, unpacking and loading included), waits, and writes
#       to --out (default $OUT) the float16 state dicts in bundles of at most 15 MiB, one JSON of
#       every run's history and the runs' logs. --tiny: two runs at batch 8 (with --device cpu: the
#       end-to-end check on this machine). --runs: these runs instead of the plan (a subset or controls).
#   scripts/train_gpu.sh export [--from DIR] [--work DIR]
#       the bundles brought back -> one TorchScript model.pt per run (Debian's torch), under
#       DIR/runs/NAME/; ship DIR/runs/shipped-scaled-rmse-final/model.pt as models/heightmap_cnn.pt.
#   scripts/train_gpu.sh eval   [--work DIR] [--released FILE] [--variant NAME]
#       LOSO: every fold's model (runs/NAME-fold-SURVEY; NAME default shipped-scaled-rmse, or e.g.
#       shipped-scaled-rmse-half) on its held-out survey (lidarscout eval, 10 m, 150 patches, 8
#       lattices; 40 and 1,500 chunk points per window too) beside linear and the released
#       model, tables as in scripts/loso_eval.sh.
#
# The device-side command (one call, timeout 540 s; .gpu-train carried):
#   scripts/train_gpu.sh run --tree .gpu-train --budget 450
set -euo pipefail

# All in one function, so that bash reads the whole file before running any of it.
main() {
cd "$(dirname "$0")/.."
repo=$(pwd)
stage="${1:-}"
[ $# -gt 0 ] && shift
work=/work/nnwork/gpu
extra=/work/traindata
tree=.gpu-train
threads=2
per_group=42
budget=450
out="${OUT:-}"
from=""
device=cuda
tiny=0
only_runs=""
released=""
variant=shipped-scaled-rmse
while [ $# -gt 0 ]; do
  case "$1" in
    --work) work="$2"; shift 2 ;;
    --extra) extra="$2"; shift 2 ;;
    --tree) tree="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    --per-group) per_group="$2"; shift 2 ;;
    --budget) budget="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --from) from="$2"; shift 2 ;;
    --device) device="$2"; shift 2 ;;
    --tiny) tiny=1; shift ;;
    --runs) only_runs="$2"; shift 2 ;;
    --released) released="$(realpath "$2")"; shift 2 ;;
    --variant) variant="$2"; shift 2 ;;
    *) echo "train_gpu.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
bin=build/lidarscout
surveys=../shared/data/surveys
held_out=(autzen-oregon-ept ky-georgetown ky-n066e379)
case "$stage" in
  data) stage_data ;;
  pack) stage_pack ;;
  run) stage_run ;;
  export) stage_export ;;
  eval) stage_eval ;;
  *) sed -n '2,33p' "$0" >&2; exit 2 ;;
esac
}

py() { (cd "$repo/python" && /usr/bin/python3 -m "$@"); }

sources() {  # every training source: the seven surveys, then the extra ones not held out
  local s name
  for s in "$surveys"/* "$extra"/*/; do
    s="${s%/}"
    name=$(basename "$s")
    [ -d "$s" ] || continue
    [[ " ${held_out[*]} " == *" $name "* ]] && continue
    echo "$s"
  done
}

stage_data() {
  source scripts/density_windows.sh
  mkdir -p "$work/data"
  local s name
  while read -r s; do
    name=$(basename "$s")
    density_windows "$repo" "$bin" "$s" "$work/data/$name" 300 "$threads" > /dev/null
    if [ ! -f "$work/data/$name.fine.bin" ]; then
      "$bin" train-data "$s" -o "$work/data/$name.fine.tmp" --texel 1,2.5,5 --patches 60 --offsets 4 \
        --val-fraction 0 --threads "$threads" > /dev/null
      mv "$work/data/$name.fine.tmp" "$work/data/$name.fine.bin"
    fi
    echo "$name: $(ls "$work/data/$name".*.bin | wc -l) files"
  done < <(sources)
}

stage_pack() {
  local files=()
  mapfile -t files < <(ls "$work"/data/*.bin)
  rm -rf "$tree"
  mkdir -p "$tree"
  py lidarscout_train.window_pack pack "${files[@]}" --out "$(realpath "$tree")/windows.xz" --per-group "$per_group" \
    --surveys "$(cd "$surveys" && ls | paste -sd, -)"
  # What travels to the device machine (this repository's files, the tree and the GPU checks' payload
  # when packed) is at most 64 MiB. (One awk sum: xargs splits thousands of files into several `du -c`
  # runs, and the last one's total alone counted only a part of them.)
  local bytes repo_bytes checks_bytes=0 limit
  bytes=$(du -sb "$tree" | cut -f1)
  repo_bytes=$(git ls-files -z | xargs -0 -r stat -c %s | awk '{ s += $1 } END { print s + 0 }')
  [ -d .gpu-checks ] && checks_bytes=$(du -sb .gpu-checks | cut -f1)
  limit=$((64 * 1024 * 1024 - repo_bytes - checks_bytes - 1024 * 1024))
  echo "$tree: $bytes bytes (at most $limit beside the repository's $repo_bytes and .gpu-checks' $checks_bytes)"
  [ "$bytes" -le "$limit" ] || { echo "train_gpu.sh: $tree is too large for the device machine: fewer --per-group" >&2; exit 1; }
}

stage_run() {
  [ -n "$out" ] || { echo "train_gpu.sh run: --out DIR (or \$OUT)" >&2; exit 2; }
  local py_bin=python3 runs
  [ "$device" = cpu ] && py_bin=/usr/bin/python3
  mkdir -p "$out"
  local scratch
  scratch=$(mktemp -d)
  local deadline=$(( $(date +%s) + budget ))
  local xz
  xz=$(realpath "$tree/windows.xz")
  (cd python && PYTHONUNBUFFERED=1 "$py_bin" -m lidarscout_train.window_pack unpack "$xz" "$scratch/windows")
  runs=$(cd python && "$py_bin" -m lidarscout_train.fast_train plan "$scratch/windows" $([ "$tiny" = 1 ] && echo --tiny))
  [ -z "$only_runs" ] || runs="${only_runs//,/ }"
  local name pids=()
  for name in $runs; do
    (cd python && PYTHONUNBUFFERED=1 "$py_bin" -m lidarscout_train.fast_train train "$scratch/windows" \
      --run "$name" --out "$scratch/runs/$name" --deadline "$deadline" --device "$device" \
      $([ "$tiny" = 1 ] && echo --tiny) > "$scratch/$name.log" 2>&1) &
    pids+=($!)
  done
  local failed=0 pid
  for pid in "${pids[@]}"; do wait "$pid" || failed=$((failed + 1)); done
  for name in $runs; do echo "== $name"; tail -n 3 "$scratch/$name.log"; done
  (cd python && "$py_bin" -m lidarscout_train.fast_train bundle "$scratch/runs" --out "$out")
  cat "$scratch"/*.log > "$out/train.log"
  rm -rf "$scratch"
  [ "$failed" = 0 ] || { echo "train_gpu.sh: $failed run(s) failed" >&2; exit 1; }
}

stage_export() {
  [ -n "$from" ] || { echo "train_gpu.sh export: --from DIR (the files brought back)" >&2; exit 2; }
  py lidarscout_train.fast_train unbundle "$(realpath "$from")" --out "$work/runs"
}

score() {  # out.json eval-args...: one `lidarscout eval --json` into out.json unless it is there; a
  # density at which a small survey holds no patch is left out of the table (said so)
  local out="$1"
  shift
  [ -f "$out" ] && return
  if ! "$bin" eval "$@" 2> "$out.err" > "$out.tmp"; then
    grep -q "no patch could be scored" "$out.err" || { cat "$out.err" >&2; exit 1; }
    echo "train_gpu.sh: $(tail -n 1 "$out.err") (left out)" >&2
    rm -f "$out.tmp" "$out.err"
    return
  fi
  rm -f "$out.err"
  mv "$out.tmp" "$out"
}

stage_eval() {
  mkdir -p "$work/eval/$variant" "$work/released"
  local s held model cp tag stride common=(--texel 10 --patches 150 --offsets 8 --threads 2 --json)
  for s in "$surveys"/*; do
    held=$(basename "$s")
    model="$work/runs/$variant-fold-$held/model.pt"
    [ -f "$model" ] || { echo "train_gpu.sh: no $model" >&2; exit 1; }
    for cp in "" 40 1500; do
      tag="" stride=()
      [ -n "$cp" ] && { tag=".cp$cp"; stride=(--stride "$(py lidarscout_train.loso stride "$work/data/$held.probe" "$cp")"); }
      score "$work/eval/$variant/$held$tag.json" "$s" --methods linear,cnn --model "$model" "${common[@]}" "${stride[@]}"
      [ -z "$released" ] || score "$work/released/$held$tag.json" "$s" --methods linear,released \
        --released-model "$released" "${common[@]}" "${stride[@]}"
    done
  done
  local files f
  for cp in "" 40 1500; do
    echo
    echo "LOSO, $variant, 10 m, ${cp:-auto (about 369)} chunk points per window:"
    files=()
    for s in "$surveys"/*; do
      f="$work/eval/$variant/$(basename "$s")${cp:+.cp$cp}.json"
      [ -f "$f" ] && files+=("$f")
    done
    py lidarscout_train.loso table "${files[@]}" --released-dir "$work/released" \
      --json "$work/eval/$variant/loso${cp:+.cp$cp}.json"
  done
}

main "$@"
