#!/usr/bin/env bash
# Accuracy versus time for S1: particle_cantilever over the CG widths
# c in {0, 2d, 4d, 6d, 10d, 15d} and over the stepping choices (implicit
# Newmark or explicit central difference for the beam; 1, 5 or 20 DEM steps
# per FEM step), each run until the particles leave the beam.  Writes
# <out>/sweep.md (a Markdown table: c, FEM stepper, sub-steps, err_avg,
# sym_dev, E_max, t_off, wall) and <out>/sweep.csv, and keeps every run's
# folder for the plots (tools/plot_particle_cantilever.py <run folder>).
#
# usage: tools/sweep_particle_cantilever.sh [build dir] [out dir] [extra driver options]
#   WIDTHS="0 10d" FEMS="central_difference" SUBSTEPS="1" to restrict the sweep.
set -euo pipefail
build=${1:-build}
out=${2:-results/sweep_particle_cantilever}
shift $(( $# > 2 ? 2 : $# )) || true
driver=$build/bin/particle_cantilever
widths=${WIDTHS:-"0 2d 4d 6d 10d 15d"}
fems=${FEMS:-"newmark central_difference"}
substeps=${SUBSTEPS:-"1 5 20"}
mkdir -p "$out"
csv=$out/sweep.csv
echo "c,fem,substeps,err_avg,sym_dev,E_max,t_off,wall" > "$csv.tmp"
for fem in $fems; do
  for k in $substeps; do
    for c in $widths; do
      run=$out/c${c}_${fem}_k${k}
      line=$("$driver" -cg_width "$c" -fem "$fem" -substeps "$k" -snapshot_dt 0 -output_dir "$run" "$@" \
             2>"$run.err" | tee "$run.log" | grep '^summary:' || true)
      if [ -z "$line" ]; then
        echo "$c,$fem,$k,failed,,,," >> "$csv.tmp"
        continue
      fi
      get() { echo "$line" | tr ' ' '\n' | sed -n "s/^$1=//p"; }
      echo "$c,$fem,$k,$(get err_avg),$(get sym_dev),$(get E_max),$(get t_off),$(get wall)" >> "$csv.tmp"
    done
  done
done
mv "$csv.tmp" "$csv"
{
  echo "| c | FEM | DEM steps per FEM step | err_avg (m) | max abs(x1 + x2) (m) | E_max (J) | t_off (s) | wall (s) |"
  echo "|---|---|---|---|---|---|---|---|"
  tail -n +2 "$csv" | awk -F, '{printf "| %s | %s | %s | %s | %s | %s | %s | %s |\n", $1, $2, $3, $4, $5, $6, $7, $8}'
} > "$out/sweep.md.tmp"
mv "$out/sweep.md.tmp" "$out/sweep.md"
cat "$out/sweep.md"
