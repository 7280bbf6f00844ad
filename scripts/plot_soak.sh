#!/usr/bin/env bash
# Draws the CSV of `bench_view --soak` (bench/view_soak.hpp) as a PNG with gnuplot (Debian's
# gnuplot-nox): resident size, heap in use and the scheduler's bytes against its budget (MB, left
# axis) and each second's median and worst frame time (ms, right axis) over the soak's minutes.
# Usage: scripts/plot_soak.sh SOAK.csv OUT.png [TITLE]
set -euo pipefail
if [ $# -lt 2 ]; then
  echo "usage: $0 SOAK.csv OUT.png [TITLE]" >&2
  exit 1
fi
csv=$1 png=$2 title=${3:-bench_view --soak}
tmp="$png.tmp-$$.png"
trap 'rm -f "$tmp"' EXIT
gnuplot <<GP
set datafile separator ","
set terminal pngcairo size 1400,700 font ",11"
set output "$tmp"
set title "$title" noenhanced
set key outside bottom center horizontal
set xlabel "minutes"
set ylabel "MB"
set y2label "frame ms"
set y2tics
set ytics nomirror
set grid
plot "$csv" using (\$1/60):2 every ::1 with lines lw 2 title "resident", \
     "$csv" using (\$1/60):3 every ::1 with lines title "heap in use", \
     "$csv" using (\$1/60):5 every ::1 with lines title "scheduler", \
     "$csv" using (\$1/60):6 every ::1 with lines dt 2 title "budget", \
     "$csv" using (\$1/60):8 every ::1 axes x1y2 with lines lc rgb "#999999" title "median frame", \
     "$csv" using (\$1/60):9 every ::1 axes x1y2 with lines lw 0.5 lc rgb "#cc0000" title "worst frame"
GP
mv "$tmp" "$png"
trap - EXIT
echo "plot_soak: wrote $png"
