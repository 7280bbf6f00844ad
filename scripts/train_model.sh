#!/bin/bash
# Reproduces the shipped heightmap network (models/README.md) on the CPU, and optionally the
# fine-tuning stage for unseen surveys that was tried and NOT shipped (issue 17):
#   1. the shipped network: training data from the real surveys in ../shared/data/surveys (region
#      split), 40 epochs from scratch, and its held-out evaluation (DIR/run/model.pt);
#   2. --fine-tune: from the stage-1 weights, on every survey of ../shared/data/surveys and the
#      extra training data of scripts/build_training_set.sh less the sources held out for the
#      unseen comparison, 10 m windows at six chunk-point densities (40..1,500 per window) and
#      1, 2.5 and 5 m windows at the auto stride (DIR/tuned/model.pt); then the comparison with
#      stage 1 on the held-out sources (scripts/compare_models.sh). Its figures did not beat the
#      shipped network (models/README.md, "Fine-tuning for unseen surveys").
#
#   scripts/train_model.sh [--out DIR] [--gpu] [--fine-tune [--extra DIR] [--init MODEL.pt] [--released FILE]]
#
#   --out DIR      work folder (default build/training); copy DIR/run/model.pt to models/heightmap_cnn.pt to ship it
#   --gpu          stage 1 in the paper-size configuration on a CUDA machine (not run yet)
#   --extra DIR    the extra training data (default ../traindata): build it from local mirrors with
#                  scripts/build_training_set.sh --out DIR (see its header)
#   --init FILE    skip stage 1 and fine-tune this TorchScript model (e.g. models/heightmap_cnn.pt)
#   --released F   the paper's released model converted for the CPU: its column in the comparison
#
# Each stage resumes where it stopped (existing data files and checkpoints are kept).
set -euo pipefail

# All in one function, so that bash reads the whole file before running any of it.
main() {
cd "$(dirname "$0")/.."
repo=$(pwd)
source scripts/density_windows.sh
out=build/training
extra=../traindata
init=""
released=""
gpu=0
fine_tune=0
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out="$2"; shift 2 ;;
    --extra) extra="$2"; shift 2 ;;
    --init) init="$(realpath "$2")"; shift 2 ;;
    --released) released="$2"; shift 2 ;;
    --gpu) gpu=1; shift ;;
    --fine-tune) fine_tune=1; shift ;;
    *) echo "train_model.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
surveys=../shared/data/surveys
bin=build/lidarscout
mkdir -p "$out"
py() { (cd python && /usr/bin/python3 -m "$@"); }

if [ -z "$init" ]; then
  # 1. Training data: four texel sizes, four shifted lattices each; region split 2 km blocks,
  #    a quarter held out (seed 1), the same split eval --split validation uses. A 10 m window
  #    covers 960 m, so these small surveys hold few of them: a second file adds 10 m windows
  #    from sixteen shifted lattices (same split).
  split=(--split-block 2000 --val-fraction 0.25 --split-seed 1)
  [ -f "$out/data.bin" ] || "$bin" train-data "$surveys"/* -o "$out/data.bin" --texel 1,2.5,5,10 --patches 200 \
    --offsets 4 "${split[@]}"
  [ -f "$out/data10.bin" ] || "$bin" train-data "$surveys"/* -o "$out/data10.bin" --texel 10 --patches 2000 \
    --offsets 16 "${split[@]}"
  if [ "$gpu" = 1 ]; then
    py lidarscout_train.train "../$out/data.bin" "../$out/data10.bin" --out "../$out/run" --device cuda \
       --decoder upsample --width 16 --head-kernel 9 --epochs 75 --batch 50 --resume
    echo "paper-size model: $out/run/model.pt"
    return
  fi
  [ -f "$out/run/model.pt" ] || py lidarscout_train.train "../$out/data.bin" "../$out/data10.bin" --out "../$out/run" \
    --threads 2 --decoder upsample --width 8 --head-kernel 5 --epochs 40 --batch 32 --resume
  for texel in 10 5 2.5; do
    "$bin" eval "$surveys"/* --methods linear,cnn --model "$out/run/model.pt" --texel "$texel" \
      --split validation --offsets 4 --patches 400 --json > "$out/eval_${texel}m.json"
  done
  init="$(realpath "$out/run/model.pt")"
fi
if [ "$fine_tune" = 0 ]; then
  echo "model: $out/run/model.pt; held-out figures: $out/eval_*m.json"
  return
fi

# 2. Fine-tuning data: every survey and every extra source except the held-out ones.
held_out=(autzen-oregon-ept ky-georgetown ky-n066e379)
if [ ! -d "$extra" ]; then
  echo "train_model.sh: no extra training data in $extra (scripts/build_training_set.sh)" >&2
  exit 1
fi
mkdir -p "$out/tune-data"
files=()
for s in "$surveys"/* "$extra"/*/; do
  s="${s%/}"
  name=$(basename "$s")
  [[ " ${held_out[*]} " == *" $name "* ]] && continue
  [ -f "$out/tune-data/$name.fine.bin" ] || { "$bin" train-data "$s" -o "$out/tune-data/$name.fine.tmp" \
    --texel 1,2.5,5 --patches 60 --offsets 4 --val-fraction 0 --threads 2 && \
    mv "$out/tune-data/$name.fine.tmp" "$out/tune-data/$name.fine.bin"; }
  files+=("$(realpath "$out/tune-data/$name.fine.bin")")
  density_windows "$repo" "$bin" "$s" "$(realpath "$out/tune-data")/$name" 300 2 > "$out/tune-data/$name.list"
  mapfile -t -O "${#files[@]}" files < "$out/tune-data/$name.list"
done
py lidarscout_train.train "${files[@]}" --init "$init" --decoder upsample --width 8 --head-kernel 5 \
  --out "$(realpath "$out")/tuned" --threads 1 --epochs 10 --max-steps 80 --lr 5e-5 --milestones 8 --batch 32 \
  --max-per-file 150 --resume

# 3. The unseen comparison: linear, the stage-1 network, the fine-tuned one (and the released model).
scripts/compare_models.sh --candidate "$out/tuned/model.pt" --shipped "$init" ${released:+--released "$released"} \
  --texels 10,5 --densities 40,1500 --work "$out/compare" "${held_out[@]/#/$extra/}"
echo "fine-tuned model: $out/tuned/model.pt; unseen comparison: $out/compare/tables/*.json"
}

main "$@"
