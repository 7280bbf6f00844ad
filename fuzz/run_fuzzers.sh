#!/bin/sh
# Runs every libFuzzer target for SECONDS (default 3600) at once, each from the committed corpus
# plus its seeds (../shared/data/formats for tile and report, fuzz/make_chunk_seeds.py for chunk),
# then merges what each found into a small minimised corpus (inputs of at most MAX_KEEP bytes)
# under OUT/NAME, ready to replace fuzz/corpus/NAME. Logs (executions, coverage) go to OUT/NAME.log.
#   fuzz/run_fuzzers.sh BUILD_FUZZ_DIR OUT_DIR [SECONDS [NAME...]]
# (NAME...: only those targets; all seven by default)
# BUILD_FUZZ_DIR is a clang build with -DLIDARSCOUT_FUZZ=ON (see README). Runs under `nice`, so
# an input may wait for the CPU: the time limit per input is 60 s, not 10 (the slowest inputs
# found so far take 0.2 s of CPU under the sanitizers: PROJ's database search for a rare CRS in
# report, the 256 byte models of a POINT10 chunk in chunk).
set -eu
build=$1
out=$2
seconds=${3:-3600}
shift $(( $# < 3 ? $# : 3 ))
names=${*:-tile chunk report multipart catalog session polygon}
here=$(cd "$(dirname "$0")" && pwd)
formats="$here/../../shared/data/formats"
max_keep=16384
mkdir -p "$out"
python3 "$here/make_chunk_seeds.py" "$out/seeds-chunk"

seeds() {
  case $1 in
    tile|report) echo "$formats" ;;
    chunk) echo "$out/seeds-chunk" ;;
    *) echo "" ;;
  esac
}
max_len() {
  case $1 in
    tile|report) echo 262144 ;;
    chunk) echo 70000 ;;
    catalog|session|polygon) echo 65536 ;;
    *) echo 4096 ;;
  esac
}

for name in $names; do
  mkdir -p "$out/work-$name"
  [ -d "$here/corpus/$name" ] && cp -n "$here/corpus/$name"/* "$out/work-$name"/ 2>/dev/null || true
  # shellcheck disable=SC2046
  nice -n 19 "$build/fuzz/fuzz_$name" "$out/work-$name" $(seeds $name) -max_len="$(max_len $name)" \
    -max_total_time="$seconds" -timeout=60 -rss_limit_mb=4096 -print_final_stats=1 \
    -artifact_prefix="$out/$name-" \
    > "$out/$name.log" 2>&1 &
done
wait

for name in $names; do
  rm -rf "$out/$name" && mkdir -p "$out/$name"
  "$build/fuzz/fuzz_$name" -merge=1 -max_len="$max_keep" "$out/$name" "$out/work-$name" \
    > "$out/$name.merge.log" 2>&1
  echo "$name: $(ls "$out/$name" | wc -l) inputs, $(du -sk "$out/$name" | cut -f1) KiB;" \
       "$(grep -E '^(stat::number_of_executed_units|#[0-9]+ *DONE)' "$out/$name.log" | tr '\n' ' ')"
done
