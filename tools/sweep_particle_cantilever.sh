#!/usr/bin/env bash
# Accuracy versus time for S1: particle_cantilever over the CG widths
# c in {0, 2d, 4d, 6d, 10d, 15d} and over the stepping choices (implicit
# Newmark or explicit central difference for the beam; 1, 5 or 20 DEM steps
# per FEM step), each run until the particles leave the beam (or stop at
# the energy limit: an unstable coupling), one thread
# per run.  Writes <out>/sweep.md (a Markdown table: c, FEM stepper,
# sub-steps, err_avg, sym_dev, E_max, t_off, CPU and wall seconds, or the
# reason a run was refused) and <out>/sweep.csv, and keeps every run's
# folder for the plots (tools/plot_particle_cantilever.py <run folder>;
# tools/plot_sweep_particle_cantilever.py <out> for the table's plot).
#
# usage: tools/sweep_particle_cantilever.sh [build dir] [out dir] [extra driver options]
#   WIDTHS="0 10d" FEMS="central_difference" SUBSTEPS="1" restrict the sweep;
#   JOBS=2 runs two at a time (wall times then include the contention; the
#   CPU column does not); TABLE_ONLY=1 rebuilds the table from the logs.
set -euo pipefail
build=${1:-build}
out=${2:-results/sweep_particle_cantilever}
shift $(( $# > 2 ? 2 : $# )) || true
driver=$build/bin/particle_cantilever
widths=${WIDTHS:-"0 2d 4d 6d 10d 15d"}
fems=${FEMS:-"newmark central_difference"}
substeps=${SUBSTEPS:-"1 2 5 20"}
jobs=${JOBS:-1}
mkdir -p "$out"
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1

if [ -z "${TABLE_ONLY:-}" ]; then
  running=0
  for fem in $fems; do
    for k in $substeps; do
      for c in $widths; do
        run=$out/c${c}_${fem}_k${k}
        ( "$driver" -cg_width "$c" -stepper "$fem" -substeps "$k" -snapshot_dt 0 -output_dir "$run" "$@" \
            > "$run.log" 2> "$run.err" || true ) &
        running=$((running + 1))
        if [ "$running" -ge "$jobs" ]; then
          wait -n || true
          running=$((running - 1))
        fi
      done
    done
  done
  wait || true
fi

csv=$out/sweep.csv
echo "c,fem,substeps,err_avg,sym_dev,E_max,t_off,cpu,wall,note" > "$csv.tmp"
for fem in $fems; do
  for k in $substeps; do
    for c in $widths; do
      run=$out/c${c}_${fem}_k${k}
      line=$(grep '^summary:' "$run.log" 2>/dev/null || true)
      if [ -z "$line" ]; then
        why=$( { head -n 1 "$run.err" 2>/dev/null || true; } | sed 's/^[Ee]rror (\([a-z]*\)): /\1: /; s/,/;/g')
        echo "$c,$fem,$k,,,,,,,${why:-not run (or still running)}" >> "$csv.tmp"
        continue
      fi
      get() { echo "$line" | tr ' ' '\n' | sed -n "s/^$1=//p"; }
      echo "$c,$fem,$k,$(get err_avg),$(get sym_dev),$(get E_max),$(get t_off),$(get cpu),$(get wall)," >> "$csv.tmp"
    done
  done
done
mv "$csv.tmp" "$csv"
{
  echo "| c | FEM | DEM steps per FEM step | err_avg (m) | max abs(x1 + x2) (m) | E_max (J) | t_off (s) | CPU (s) | wall (s) | note |"
  echo "|---|---|---|---|---|---|---|---|---|---|"
  tail -n +2 "$csv" | awk -F, '{printf "| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", $1, $2, $3, $4, $5, $6, $7, $8, $9, $10}'
} > "$out/sweep.md.tmp"
mv "$out/sweep.md.tmp" "$out/sweep.md"
cat "$out/sweep.md"
