#!/bin/sh
# Sweeps wave_volume_coupling over CG widths for a set of cases and
# excitations and prints one Markdown row per run: case, excitation,
# variant, c, dissipated fraction, profile error, momentum drift, Eq. 41,
# wall time of the coupled run and of the full-DEM reference (s), profile
# error of the weighted (Arlequin) field.  Runs go one at a time.
#   tools/sweep_wave.sh BIN OUTDIR "1P 2P" "pulse" "0 0.5h 1h 1.5h 2h 2.5h" [extra options]
# e.g. tools/sweep_wave.sh build/bin/wave_volume_coupling results/sweep "1P" "pulse" "0 1.5h" -variant spring
set -e
bin=$1; out=$2; cases=$3; excitations=$4; widths=$5
shift 5
mkdir -p "$out"
echo "| case | excitation | variant | c | dissipated | profile_err | momentum_drift | eq41 | wall coupled (s) | wall reference (s) | profile_err_weighted |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for cs in $cases; do
  for ex in $excitations; do
    for c in $widths; do
      log="$out/${cs}_${ex}_c${c}$(echo "$*" | tr -d ' -').log"
      if "$bin" -progress 0 -case "$cs" -excitation "$ex" -cg_width "$c" -output_dir "$out/${cs}_${ex}_c${c}" "$@" >"$log" 2>&1; then
        line=$(grep '^summary:' "$log" | tail -1)
        get() { echo "$line" | tr ' ' '\n' | grep "^$1=" | cut -d= -f2; }
        ref=$(grep -o 'reference [0-9.]* s' "$log" | tail -1 | cut -d' ' -f2)
        echo "| $cs | $ex | $(get variant) | $c | $(get dissipated) | $(get profile_err) | $(get momentum_drift) | $(get eq41) | $(get wall_coupled) | $ref | $(get profile_err_weighted) |"
      else
        echo "| $cs | $ex | - | $c | failed: $(grep -m1 error "$log" | cut -c1-160) | | | | | | |"
      fi
    done
  done
done
