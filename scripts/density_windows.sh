# Training windows of one survey at six chunk-point densities (issue 17: real surveys in
# 50,000-point chunks hold from about 40 to about 1,500 chunk points per 960 m window).
# Sourced by scripts/loso_eval.sh and scripts/train_model.sh; needs python/lidarscout_train.
#
#   density_windows REPO BIN SURVEY PREFIX PATCHES THREADS
#
# writes PREFIX.probe (one window at the auto stride, about 369 chunk points) and, for the six
# levels 40, 100, 200, 369, 700 and 1,500 chunk points per window, PREFIX.cpN.bin: 10 m windows
# on 16 shifted lattices, ceil(PATCHES / 6) per lattice, a different window draw per level
# (--seed 1..6), no region split. An existing file is kept (resumable). Prints the files; a level
# at which a small survey holds no window is left out with a message.
density_windows() {
  local repo="$1" bin="$2" survey="$3" prefix="$4" patches="$5" threads="$6"
  local common=(--texel 10 --offsets 16 --val-fraction 0 --threads "$threads")
  [ -f "$prefix.probe" ] || "$bin" train-data "$survey" -o "$prefix.probe" --patches 1 "${common[@]}" > /dev/null
  local k=0 cp stride
  for cp in 40 100 200 369 700 1500; do
    k=$((k + 1))
    if [ ! -f "$prefix.cp$cp.bin" ]; then
      stride=$(cd "$repo/python" && /usr/bin/python3 -m lidarscout_train.loso stride "$prefix.probe" "$cp")
      local log
      if ! log=$("$bin" train-data "$survey" -o "$prefix.cp$cp.bin.tmp" --patches $(( (patches + 5) / 6 )) --seed "$k" \
          --stride "$stride" "${common[@]}" 2>&1); then
        # A small survey holds no window with enough chunk points at the sparsest levels: that level
        # is left out (and said so); any other failure stops.
        [[ "$log" == *"no sample in"* ]] || { echo "$log" >&2; return 1; }
        echo "density_windows: $survey: no window at $cp chunk points per window, level left out" >&2
        continue
      fi
      echo "$log" >&2
      mv "$prefix.cp$cp.bin.tmp" "$prefix.cp$cp.bin"
    fi
    echo "$prefix.cp$cp.bin"
  done
}
