#!/bin/bash
# Leave-one-survey-out (LOSO) evaluation of the heightmap network: for every survey S, train
# without S, evaluate on S (`lidarscout eval --methods linear,cnn[,released] --texel 10`), and
# print one table (per survey: patches, linear RMSE, CNN RMSE, ratio, the released model's
# column when --released is given) with the mean ratio. Resumable: a step whose output exists
# is skipped (training continues from its checkpoint), so rerunning after an interruption goes on.
#
#   scripts/loso_eval.sh [--work DIR] [--variant base|density] [--surveys DIR] [--extra-survey DIR]...
#       [--epochs N] [--steps N] [--lr X] [--patches N] [--eval-patches N] [--eval-offsets N] [--densities 40,1500]
#       [--released FILE] [--threads N] [--device cpu|cuda] [--smoke]
#
#   --variant base     training windows at the auto stride (about 369 chunk points per window)
#   --variant density  every survey's windows at six strides giving 40, 100, 200, 369, 700 and
#                      1,500 chunk points per window (a different window draw per level; windows
#                      with < 25 chunk points are dropped); same training steps as base
#   --extra-survey DIR more training surveys (e.g. /work/traindata/*: each must pass
#                      ../shared/tools/reserved.py --scan), exported like the others and added to
#                      every fold, never held out; the runs go to DIR/VARIANT+extra
#   --densities LIST   also evaluate every held-out survey at these chunk points per window
#   --released FILE    the paper's released ipes_cnn.pt converted for the CPU
#                      (python3 -m lidarscout_train.released_cpu): its column beside ours
#   --device cuda      train on a GPU (PyTorch with CUDA there); then e.g. --epochs 40 --steps 0 is the
#                      shipped recipe's length
#   --smoke            a tiny recipe (2 epochs, 40 windows, 20 eval patches) to check the wiring
#
# The reduced recipe (default; the shipped recipe takes ~35 min per model on 2 cores, 7 folds do
# not fit): 10 m texels only, per survey --patches 300 windows on 16 shifted lattices, the cheap
# network (width 8, 5 x 5 heads, upsample decoder), --epochs 10 of --steps 16 batches of 32
# (random windows each epoch), AdamW lr --lr 5e-4 dropped x0.1 for the last epoch,
# augmentation as train.py. --steps 0: whole epochs. Data and models stay under DIR (default
# /work/nnwork/loso), outside the repository.
set -euo pipefail

# All in one function, so that bash reads the whole file before running any of it.
main() {
cd "$(dirname "$0")/.."
repo=$(pwd)
source scripts/density_windows.sh
work=/work/nnwork/loso
variant=base
surveys=../shared/data/surveys
extra=()
epochs=10
steps=16
lr=5e-4
patches=300
eval_patches=150
eval_offsets=8
densities=""
released=""
threads=2
device=cpu
smoke=0
bin=build/lidarscout
while [ $# -gt 0 ]; do
  case "$1" in
    --work) work="$2"; shift 2 ;;
    --variant) variant="$2"; shift 2 ;;
    --surveys) surveys="$2"; shift 2 ;;
    --extra-survey) extra+=("$(realpath "$2")"); shift 2 ;;
    --epochs) epochs="$2"; shift 2 ;;
    --steps) steps="$2"; shift 2 ;;
    --lr) lr="$2"; shift 2 ;;
    --patches) patches="$2"; shift 2 ;;
    --eval-patches) eval_patches="$2"; shift 2 ;;
    --eval-offsets) eval_offsets="$2"; shift 2 ;;
    --densities) densities="$2"; shift 2 ;;
    --released) released="$(realpath "$2")"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    --device) device="$2"; shift 2 ;;
    --lidarscout) bin="$2"; shift 2 ;;
    --smoke) smoke=1; shift ;;
    *) echo "loso_eval.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
if [ "$smoke" = 1 ]; then epochs=2; steps=2; patches=40; eval_patches=20; eval_offsets=2; work="$work-smoke"; fi
case "$variant" in base|density) ;; *) echo "loso_eval.sh: --variant base or density" >&2; exit 2 ;; esac
py() { (cd "$repo/python" && /usr/bin/python3 -m "$@"); }
data="$work/data/$variant"
runs="$work/$variant${extra:+"+extra"}"
mkdir -p "$data" "$runs/eval" "$work/released"
names=()
for s in "$surveys"/*; do names+=("$(basename "$s")"); done

# 1. Training windows of each survey (10 m, all of it: no region split).
export_survey() {  # survey-path name
  local out="$data/$2.bin"
  [ -f "$out" ] && return
  local common=(--texel 10 --offsets 16 --val-fraction 0 --threads "$threads")
  if [ "$variant" = base ]; then
    "$bin" train-data "$1" -o "$out.tmp" --patches "$patches" "${common[@]}"
  else
    density_windows "$repo" "$bin" "$1" "$data/$2" "$patches" "$threads" > "$out.tmp"
  fi
  mv "$out.tmp" "$out"
}
files_of() {  # name: the train-data files of one survey
  if [ "$variant" = base ]; then echo "$data/$1.bin"; else cat "$data/$1.bin"; fi
}
for s in "$surveys"/* "${extra[@]}"; do export_survey "$s" "$(basename "$s")"; done
extra_files=()
for s in "${extra[@]}"; do mapfile -t -O "${#extra_files[@]}" extra_files < <(files_of "$(basename "$s")"); done

# 2.-3. Per fold: train without the survey, evaluate on it.
for held in "${names[@]}"; do
  fold="$runs/fold-$held"
  train=()
  for n in "${names[@]}"; do [ "$n" = "$held" ] || mapfile -t -O "${#train[@]}" train < <(files_of "$n"); done
  if [ ! -f "$fold/model.pt" ]; then
    echo "== fold $held: training on ${#train[@]} files" >&2
    py lidarscout_train.train "${train[@]}" "${extra_files[@]}" --out "$fold" --threads "$threads" --device "$device" \
      --decoder upsample \
      --width 8 --head-kernel 5 --epochs "$epochs" --max-steps "$steps" --lr "$lr" --milestones $((epochs - 1)) \
      --batch 32 --resume > "$fold.log" 2>&1 || { tail "$fold.log" >&2; exit 1; }
  fi
  evaluate() {  # tag stride-args...: ours into $runs/eval, the released model's into $work/released
    local out="$runs/eval/$held$1.json" rel="$work/released/$held$1.json"
    local common=(--texel 10 --patches "$eval_patches" --offsets "$eval_offsets" --threads "$threads" --json)
    if [ ! -f "$out" ]; then
      "$bin" eval "$surveys/$held" --methods linear,cnn --model "$fold/model.pt" "${common[@]}" "${@:2}" > "$out.tmp"
      mv "$out.tmp" "$out"
    fi
    if [ -n "$released" ] && [ ! -f "$rel" ]; then
      "$bin" eval "$surveys/$held" --methods linear,released --released-model "$released" "${common[@]}" "${@:2}" \
        > "$rel.tmp"
      mv "$rel.tmp" "$rel"
    fi
  }
  evaluate ""
  if [ -n "$densities" ]; then
    probe="$data/$held.probe"  # a file at the auto stride: the survey's own (base) or the export's probe
    [ "$variant" = base ] && probe="$data/$held.bin"
    for cp in ${densities//,/ }; do
      evaluate ".cp$cp" --stride "$(py lidarscout_train.loso stride "$probe" "$cp")"
    done
  fi
done

# 4. The table (auto stride), then one per extra density.
echo "LOSO, variant $variant, $epochs epochs, $patches windows per survey, 10 m texels:"
py lidarscout_train.loso table $(for n in "${names[@]}"; do echo "$runs/eval/$n.json"; done) \
  --released-dir "$work/released" --json "$runs/loso.json"
for cp in ${densities//,/ }; do
  echo
  echo "at $cp chunk points per window:"
  py lidarscout_train.loso table $(for n in "${names[@]}"; do echo "$runs/eval/$n.cp$cp.json"; done) \
    --released-dir "$work/released" --json "$runs/loso.cp$cp.json"
done
}

main "$@"
