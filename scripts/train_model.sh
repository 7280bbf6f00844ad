#!/bin/bash
# Reproduces the shipped heightmap network: training data from the real surveys in
# ../shared/data/surveys, training on the CPU (or --gpu: the paper-size configuration on a CUDA
# machine), export to TorchScript, and the held-out evaluation. See models/README.md.
#
#   scripts/train_model.sh [--out DIR] [--gpu]      (default DIR: build/training)
#
# The shipped file is DIR/run/model.pt; copy it to models/heightmap_cnn.pt to ship it.
set -euo pipefail
cd "$(dirname "$0")/.."
out=build/training
gpu=0
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out="$2"; shift 2 ;;
    --gpu) gpu=1; shift ;;
    *) echo "train_model.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
surveys=../shared/data/surveys
mkdir -p "$out"

# 1. Training data: four texel sizes, four shifted lattices each; region split 2 km blocks,
#    a quarter held out (seed 1), the same split eval --split validation uses. A 10 m window
#    covers 960 m, so these small surveys hold few of them: a second file adds 10 m windows
#    from sixteen shifted lattices (same split).
split=(--split-block 2000 --val-fraction 0.25 --split-seed 1)
build/lidarscout train-data "$surveys"/* -o "$out/data.bin" --texel 1,2.5,5,10 --patches 200 --offsets 4 "${split[@]}"
build/lidarscout train-data "$surveys"/* -o "$out/data10.bin" --texel 10 --patches 2000 --offsets 16 "${split[@]}"

# 2. Training.
if [ "$gpu" = 1 ]; then
  (cd python && /usr/bin/python3 -m lidarscout_train.train "../$out/data.bin" "../$out/data10.bin" --out "../$out/run" --device cuda \
     --decoder upsample --width 16 --head-kernel 9 --epochs 75 --batch 50)
else
  (cd python && /usr/bin/python3 -m lidarscout_train.train "../$out/data.bin" "../$out/data10.bin" --out "../$out/run" --threads 2 \
     --decoder upsample --width 8 --head-kernel 5 --epochs 40 --batch 32)
fi

# 3. Held-out evaluation at every texel size.
for texel in 10 5 2.5; do
  build/lidarscout eval "$surveys"/* --methods linear,cnn --model "$out/run/model.pt" --texel "$texel" \
    --split validation --offsets 4 --patches 400 --json > "$out/eval_${texel}m.json"
done
echo "model: $out/run/model.pt; held-out figures: $out/eval_*m.json"
