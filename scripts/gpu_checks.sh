#!/bin/bash
# Every path of the CUDA rasterizer checked in one short run on a GPU machine (issue 55): the CUDA
# plugin and bench/gpu_harness.cpp (linked with the render and core stages only) draw every case of
# tests/render/gpu_cases.hpp (every colour mode, EDL, point filters, the bare-earth tint, adaptive
# point sizes over a real spacing, the heightmap pass, data kept on the GPU) on the CPU and the GPU
# and compare the images; compute-sanitizer's memcheck runs the GPU side again; bench_raster --frames
# times the frames; then summary.md and summary.json. The first thing to run when a GPU is lent.
#
#   scripts/gpu_checks.sh pack [--build DIR] [--to DIR]
#       HERE: the device machine has no Debian packages (another OS, CMake and nvcc but none of our
#       libraries), so the programs built here travel: gpu_harness, bench_raster and
#       liblidarscout_cuda_raster.so from DIR (default build; build them first, see below) with the
#       libraries ldd lists for them (not libc, libm, libdl, libpthread, librt, libcuda), xz-packed
#       into --to (default .gpu-checks, git-ignored) as payload.tar.xz. Fails when what travels (the
#       repository's files, the payload and .gpu-train when there) is over 64 MiB.
#   scripts/gpu_checks.sh [--dry-run] [--train] [--budget S] [--from DIR] [--tree DIR] OUT_DIR
#       ON THE GPU MACHINE (from the repository root, the payload carried): unpacks --from (default
#       .gpu-checks), runs the steps within S seconds in all (default 480: the device call's 8
#       minutes), and writes OUT_DIR/summary.md, summary.json and checks.log (the programs' output).
#       --train: then scripts/train_gpu.sh run --tree DIR (default .gpu-train) in the time left, its
#       files in OUT_DIR/train/ (at most 8 files come back from a device call: these 3 and its 4 or 5).
#       --dry-run: the same steps on a machine without a GPU, made small: the harness's CPU side (the
#       plugin must load and say cleanly that there is no device), a small bench_raster, training
#       with --device cpu --tiny; the GPU steps are "not run". The suite runs it
#       (tests/scripts/gpu_checks_test.cpp). Exit status 0 when every step that ran passed.
#
# From a session, with the device tool (`run`):
#   here:  flock /tmp/build.lock ninja -C build gpu_harness bench_raster lidarscout_cuda_raster
#          scripts/gpu_checks.sh pack
#   run:   command   bash scripts/gpu_checks.sh "$OUT"
#          carry     [".gpu-checks"]
#          timeout_s 540
#   with training (scripts/train_gpu.sh pack first): command bash scripts/gpu_checks.sh --train "$OUT",
#   carry [".gpu-checks", ".gpu-train"], timeout_s 540. The summary is printed at the end (the call's
#   output_tail) and comes back in $OUT.
set -euo pipefail

# All in one function, so that bash reads the whole file before running any of it.
main() {
repo=$(cd "$(dirname "$0")/.." && pwd)
if [ "${1:-}" = pack ]; then
  shift
  pack "$@"
  return
fi
# (paths given are the caller's; the defaults are the repository's)
dry_run=0 train=0 budget=480 from="$repo/.gpu-checks" tree="$repo/.gpu-train" out=""
while [ $# -gt 0 ]; do
  case "$1" in
    --dry-run) dry_run=1; shift ;;
    --train) train=1; shift ;;
    --budget) budget="$2"; shift 2 ;;
    --from) from=$(realpath -m "$2"); shift 2 ;;
    --tree) tree=$(realpath -m "$2"); shift 2 ;;
    -*) echo "gpu_checks.sh: unknown option $1" >&2; exit 2 ;;
    *) [ -z "$out" ] || { echo "gpu_checks.sh: one OUT_DIR, not $out and $1" >&2; exit 2; }
       out=$(realpath -m "$1"); shift ;;
  esac
done
[[ "$budget" =~ ^[0-9]+$ ]] || { echo "gpu_checks.sh: --budget takes whole seconds, not '$budget'" >&2; exit 2; }
[ -n "$out" ] || { sed -n '2,36p' "$0" >&2; exit 2; }
cd "$repo"
check
}

# --- pack (here) ----------------------------------------------------------------------------
pack() {
  local build="$repo/build" to="$repo/.gpu-checks"
  while [ $# -gt 0 ]; do
    case "$1" in
      --build) build=$(realpath -m "$2"); shift 2 ;;
      --to) to=$(realpath -m "$2"); shift 2 ;;
      *) echo "gpu_checks.sh pack: unknown option $1" >&2; exit 2 ;;
    esac
  done
  cd "$repo"
  local f
  for f in bench/gpu_harness bench/bench_raster; do
    [ -x "$build/$f" ] || { echo "gpu_checks.sh pack: no $build/$f: build it first" \
      "(ninja -C $build gpu_harness bench_raster lidarscout_cuda_raster)" >&2; exit 1; }
  done
  local stage
  stage=$(mktemp -d)
  mkdir -p "$stage/bin" "$stage/lib"
  strip -o "$stage/bin/gpu_harness" "$build/bench/gpu_harness"
  strip -o "$stage/bin/bench_raster" "$build/bench/bench_raster"
  if [ -f "$build/liblidarscout_cuda_raster.so" ]; then
    cp "$build/liblidarscout_cuda_raster.so" "$stage/bin/"
  else
    echo "gpu_checks.sh pack: no $build/liblidarscout_cuda_raster.so (built without nvcc): the GPU side cannot run" >&2
  fi
  for f in "$stage"/bin/*; do
    ldd "$f" | awk '$2 == "=>" && $3 ~ /^\// {print $3}'
  done | sort -u | grep -Ev '/(libc|libm|libdl|libpthread|librt|libcuda)\.so' | while read -r f; do
    cp -L "$f" "$stage/lib/"
  done
  {
    echo "revision $(git describe --always --dirty --abbrev=12 2>/dev/null || echo unknown)"
    echo "packed $(date -u +%Y-%m-%dT%H:%M:%SZ) on $(. /etc/os-release && echo "$PRETTY_NAME")"
    (cd "$stage" && find bin lib -type f -printf '%p %s\n' | sort)
  } > "$stage/MANIFEST"
  mkdir -p "$to"
  tar -C "$stage" -cf - . | xz -T2 -6 > "$to/payload.tar.xz.part"
  mv "$to/payload.tar.xz.part" "$to/payload.tar.xz"
  rm -rf "$stage"
  # What travels to the device machine (the repository's files and the carried folders) is at most 64 MiB.
  local repo_bytes payload_bytes train_bytes=0 limit=$((64 * 1024 * 1024))
  repo_bytes=$( (git ls-files -z 2> /dev/null || true) | xargs -0 -r stat -c %s | awk '{ s += $1 } END { print s + 0 }')
  payload_bytes=$(du -sb "$to" | cut -f1)
  [ -d .gpu-train ] && train_bytes=$(du -sb .gpu-train | cut -f1)
  echo "$to: $payload_bytes bytes; with the repository's $repo_bytes and .gpu-train's $train_bytes:" \
    "$((repo_bytes + payload_bytes + train_bytes)) of $limit"
  [ $((repo_bytes + payload_bytes + train_bytes)) -le "$limit" ] || {
    echo "gpu_checks.sh pack: too much to carry to the device machine (with --train: fewer --per-group)" >&2; exit 1; }
}

# --- the checks (on the GPU machine) ---------------------------------------------------------
now() { date +%s.%N; }
since() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.1f", b - a }'; }
left() { echo $(( deadline - $(date +%s) )); }

# step NAME STATUS SECONDS [DETAIL]: one row of the steps' table.
step() { printf '%s\t%s\t%s\t%s\n' "$1" "$2" "$3" "${4:-}" >> "$work/steps.tsv"; }

# timed NAME CAP RESERVE COMMAND...: runs COMMAND for at most CAP seconds, keeping RESERVE seconds
# of the budget for what follows (its output in checks.log and $work/NAME.out); sets `status`
# (passed, failed (exit N), timed out after S s, or not run: no time left) and `seconds`.
timed() {
  local name=$1 cap=$2 reserve=$3 limit rc=0 t0
  shift 3
  limit=$(( $(left) - reserve ))
  [ "$limit" -le "$cap" ] || limit=$cap
  seconds=0
  if [ "$limit" -lt 5 ]; then
    status="not run: no time left"
    return 0
  fi
  echo "== $name: $*" >> "$log"
  t0=$(now)
  timeout --kill-after=10 "$limit" "$@" > "$work/$name.out" 2>&1 || rc=$?
  seconds=$(since "$t0")
  cat "$work/$name.out" >> "$log"
  status=passed
  [ "$rc" = 0 ] || status="failed (exit $rc)"
  [ "$rc" != 124 ] && [ "$rc" != 137 ] || status="timed out after $limit s"
}

run_step() {
  timed "$@"
  step "$1" "$status" "$seconds"
}

machine() {
  local gpu="none" nvcc="none"
  if [ "$dry_run" = 0 ] && command -v nvidia-smi > /dev/null; then
    gpu=$(nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>&1 | head -n 1)
  fi
  command -v nvcc > /dev/null && nvcc=$(nvcc --version | tail -n 1)
  printf 'gpu\t%s\nnvcc\t%s\ncores\t%s\nos\t%s\n' "$gpu" "$nvcc" "$(nproc)" \
    "$(. /etc/os-release 2>/dev/null && echo "${PRETTY_NAME:-unknown}")" > "$work/machine.tsv"
}

sanitizer_step() {
  if [ "$dry_run" = 1 ]; then
    step memcheck "not run: dry run" 0
  elif ! command -v compute-sanitizer > /dev/null; then
    step memcheck "not run: no compute-sanitizer" 0
  elif ! grep -q '"gpu_side": "run"' "$work/harness.json" 2>/dev/null; then
    step memcheck "not run: the harness drew nothing on the GPU" 0
  else
    timed memcheck 150 "$1" "${ours[@]}" compute-sanitizer --tool memcheck --print-limit 20 "$work/bin/gpu_harness" \
      --cases rgb_edl,elevation,filter_combined,tint,adaptive_spacing,heightmaps_full_detail,kept_on_gpu
    # Only a sanitizer that reported on a whole run of the harness counts: one the machine refuses says so.
    local summary
    summary=$(grep -o 'ERROR SUMMARY: [0-9]* error' "$work/memcheck.out" | tail -n 1 || true)
    grep -q '^gpu_harness: [0-9]* cases' "$work/memcheck.out" || summary=""
    if [ -z "$summary" ] && [ "$status" != "not run: no time left" ]; then
      status="not usable here ($status, no error summary: see checks.log)"
    elif [ -n "$summary" ] && [ "$summary" != "ERROR SUMMARY: 0 error" ]; then
      status="failed (${summary}s)"
    fi
    step memcheck "$status" "$seconds"
  fi
}

bench_step() {
  local args=(--frames --runs 3)
  [ "$dry_run" = 1 ] && args=(--frames --runs 1 --points 0.2 --patches 40 --threads 2)
  run_step bench_raster 180 "$1" "${ours[@]}" "$work/bin/bench_raster" "${args[@]}"
}

train_step() {
  if [ "$train" = 0 ]; then
    step train "not run: no --train" 0
    return
  fi
  if [ ! -f "$tree/windows.xz" ]; then
    step train "not run: no $tree/windows.xz (scripts/train_gpu.sh pack)" 0
    return
  fi
  local seconds extra=()
  seconds=$(( $(left) - 45 ))  # (then the bundles and the summary)
  if [ "$dry_run" = 1 ]; then
    extra=(--device cpu --tiny)
    [ "$seconds" -le 20 ] || seconds=20
  elif [ "$seconds" -lt 60 ]; then
    step train "not run: $seconds s left" 0
    return
  fi
  [ "$seconds" -gt 0 ] || { step train "not run: no time left" 0; return; }
  run_step train $((seconds + 40)) 5 bash scripts/train_gpu.sh run --tree "$tree" --budget "$seconds" --out "$out/train" \
    "${extra[@]}"
}

check() {
  deadline=$(( $(date +%s) + budget ))
  [ -f "$from/payload.tar.xz" ] || { echo "gpu_checks.sh: no $from/payload.tar.xz (scripts/gpu_checks.sh pack)" >&2; exit 1; }
  mkdir -p "$out"
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
  log="$out/checks.log"
  # Our programs run with the libraries they came with (they only: python3 and the tools keep the system's).
  ours=(env "LD_LIBRARY_PATH=$work/lib")
  : > "$log"
  : > "$work/steps.tsv"
  local t0
  t0=$(now)
  # (tar's xz, or Python's lzma where the machine has no xz program)
  tar -C "$work" -xJf "$from/payload.tar.xz" 2> /dev/null || python3 -c \
    'import sys, tarfile; tarfile.open(sys.argv[1]).extractall(sys.argv[2], filter="data")' "$from/payload.tar.xz" "$work"
  step unpack passed "$(since "$t0")"
  machine
  local harness_args=(--json "$work/harness.json")
  [ "$dry_run" = 1 ] && harness_args+=(--cpu-only)
  run_step harness 90 60 "${ours[@]}" "$work/bin/gpu_harness" "${harness_args[@]}"
  bench_step 60
  sanitizer_step 30
  train_step
  python3 "$repo/scripts/gpu_summary.py" --work "$work" --out "$out" --budget "$budget" \
    --mode "$([ "$dry_run" = 1 ] && echo 'dry run' || echo device)"
  cat "$out/summary.md"
  local files
  files=$(find "$out" -type f | wc -l)
  [ "$files" -le 8 ] || echo "gpu_checks.sh: $files files in $out: a device call brings back 8" >&2
  grep -q '^passed: yes' "$out/summary.md"
}

main "$@"
