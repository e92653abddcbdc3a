#!/usr/bin/env bash
# Runs one peer-code scene (LAMMPS or LIGGGHTS) and reports its speed.
#
#   run_peer.sh <scene> [--ranks N] [--steps N] [--repeat N] [--prepare]
#
# Scenes: chute_lammps chute_liggghts hertz_lammps_classic hertz_lammps_granular
#         mesh_liggghts_rest mesh_liggghts_roll plane_liggghts_rest plane_lammps_rest
#         mesh_liggghts_ntri=<N>   (N = 2 n^2 triangles: 200, 800, 3200, 12800, ...)
#
# Each repeat is a fresh run of the peer; its own "Loop time" of the timed run
# (after the deck's warm-up run) gives microseconds per particle-step.  One line
# per repeat, then the machine-readable last line
#   peer: scene=<s> code=<lammps|liggghts> ranks=<n> particles=<N> steps=<n>
#         loop_time=<s> us_per_particle_step=<min> median=<m>
# (on one line; loop_time is that of the fastest repeat).  Repeat lines also
# give cpu_share (CPU over wall time x ranks, from GNU time) and load (the
# 1-minute load average before the run): both tell how busy the machine was.
#
# --prepare only prepares the scene's inputs and prints
#   peer-data: scene=<s> data=<file> [stl=<file>]
# so that a Talus benchmark can load the very particles the peer runs on.
#
# Environment: TALUS_PEERS_DIR (the peers' decks; default ../shared/peers next
# to the repository), TALUS_PEERS_CACHE (prepared inputs and logs; default
# ${TMPDIR:-/tmp}/talus-peers), TALUS_PEERS_KEEP_LOGS=1 keeps every log.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
peers="${TALUS_PEERS_DIR:-$repo/../shared/peers}"
cache="${TALUS_PEERS_CACHE:-${TMPDIR:-/tmp}/talus-peers}"

usage() {
  awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"
  exit "${1:-2}"
}
die() { echo "run_peer.sh: $*" >&2; exit 1; }

[ $# -ge 1 ] || usage 2
scene="$1"; shift
case "$scene" in -h|--help|-help) usage 0 ;; esac
ranks=1; steps=""; repeat=3; prepare_only=0
while [ $# -gt 0 ]; do
  case "$1" in
    --ranks) ranks="${2:-}"; shift 2 ;;
    --steps) steps="${2:-}"; shift 2 ;;
    --repeat) repeat="${2:-}"; shift 2 ;;
    --prepare) prepare_only=1; shift ;;
    -h|--help|-help) usage 0 ;;
    *) die "unknown argument '$1' (expected --ranks N, --steps N, --repeat N, --prepare)" ;;
  esac
done
is_pos_int() { [[ "$1" =~ ^[1-9][0-9]*$ ]]; }
is_pos_int "$ranks" || die "--ranks '$ranks' must be a positive integer"
is_pos_int "$repeat" || die "--repeat '$repeat' must be a positive integer"
[ -z "$steps" ] || is_pos_int "$steps" || die "--steps '$steps' must be a positive integer"
[ -d "$peers" ] || die "peers folder '$peers' not found (set TALUS_PEERS_DIR)"

# ------------------------------------------------------------- the scene table
# code, deck, run folder, default steps, extra -var arguments
vars=()
case "$scene" in
  chute_lammps|chute_liggghts)
    code="${scene#chute_}"; deck="$here/in.chute_$code"; default_steps=1000; prep=chute ;;
  hertz_lammps_classic)
    code=lammps; deck="$peers/hertz_packing/in.hm_classic"; default_steps=2000; prep=hertz ;;
  hertz_lammps_granular)
    code=lammps; deck="$peers/hertz_packing/in.hm_granular"; default_steps=2000; prep=hertz ;;
  mesh_liggghts_rest)
    code=liggghts; deck="$peers/mesh_wall/in.lig_bench"; default_steps=5000; prep=mesh; vars=(wall mesh tilt 0) ;;
  mesh_liggghts_roll)
    code=liggghts; deck="$peers/mesh_wall/in.lig_bench"; default_steps=5000; prep=mesh; vars=(wall mesh tilt 20) ;;
  plane_liggghts_rest)
    code=liggghts; deck="$peers/mesh_wall/in.lig_bench"; default_steps=5000; prep=mesh; vars=(wall prim tilt 0) ;;
  plane_lammps_rest)
    code=lammps; deck="$peers/mesh_wall/in.lmp_bench"; default_steps=5000; prep=mesh; vars=(wall prim tilt 0) ;;
  mesh_liggghts_ntri=*)
    ntri="${scene#mesh_liggghts_ntri=}"
    is_pos_int "$ntri" || die "triangle count '$ntri' in '$scene' must be a positive integer"
    nside=$(awk -v t="$ntri" 'BEGIN { n = int(sqrt(t / 2) + 0.5); print (2 * n * n == t) ? n : 0 }')
    [ "$nside" -gt 0 ] || die "triangle count $ntri is not 2 n^2 (the floor is n x n squares of two triangles): try 200, 800, 3200, 12800"
    code=liggghts; deck="$peers/mesh_wall/in.lig_bench"; default_steps=5000; prep=mesh
    vars=(wall meshv tilt 0 stl "plane_${ntri}.stl") ;;
  *) die "unknown scene '$scene'; scenes: chute_lammps chute_liggghts hertz_lammps_classic hertz_lammps_granular mesh_liggghts_rest mesh_liggghts_roll plane_liggghts_rest plane_lammps_rest mesh_liggghts_ntri=<N>" ;;
esac
steps="${steps:-$default_steps}"
[ -f "$deck" ] || die "deck '$deck' not found"

# ------------------------------------------------------------- the peer codes
case "$code" in
  lammps) exe=lmp; pkg=lammps ;;
  liggghts) exe=liggghts; pkg=liggghts ;;
esac
need_package() { # binary package
  command -v "$1" > /dev/null 2>&1 && return 0
  if [ "$(id -u)" -eq 0 ]; then
    echo "run_peer.sh: installing $2 (apt-get install -y $2)" >&2
    DEBIAN_FRONTEND=noninteractive apt-get install -y "$2" >&2 || die "apt-get install -y $2 failed"
    command -v "$1" > /dev/null 2>&1 || die "'$1' still missing after installing $2"
  else
    echo "run_peer.sh: '$1' is not installed; as root run: apt-get install -y $2" >&2
    exit 3
  fi
}
need_package "$exe" "$pkg"
[ "$ranks" -eq 1 ] || need_package mpirun openmpi-bin
export OMP_NUM_THREADS=1

# Runs the peer in folder $1 on deck $2, log $3, remaining args are -var pairs.
run_code() {
  local dir="$1" in="$2" log="$3" exe_="$4"; shift 4
  local args=(-in "$in" -log "$log" -echo none) # screen output goes to $log.out (LIGGGHTS needs a screen)
  while [ $# -gt 0 ]; do args+=(-var "$1" "$2"); shift 2; done
  local mpi=()
  if [ "$ranks" -gt 1 ]; then
    mpi=(mpirun -np "$ranks" --oversubscribe)
    [ "$(id -u)" -ne 0 ] || mpi+=(--allow-run-as-root)
  fi
  # GNU time, when present, records wall and CPU seconds: their ratio tells how
  # much of the machine the peer actually had (a noise indicator).
  local timer=()
  [ ! -x /usr/bin/time ] || timer=(/usr/bin/time -f "%e %U %S" -o "$log.time")
  (cd "$dir" && "${timer[@]}" "${mpi[@]}" "$exe_" "${args[@]}" > "$log.out" 2>&1) || {
    echo "run_peer.sh: $exe_ failed in $dir on $in; last lines of its log $log:" >&2
    tail -n 20 "$log" "$log.out" >&2 2> /dev/null || true
    return 1
  }
}

# ------------------------------------------------------------- preparation
# Prepared inputs live in the cache, keyed by the checksum of what made them,
# built in a scratch folder and moved into place, under a lock so that two
# benchmarks starting together prepare once.
mkdir -p "$cache" || die "cannot create cache folder '$cache'"
exec 9> "$cache/.lock"
have_flock=0
if command -v flock > /dev/null 2>&1; then have_flock=1; flock 9; fi

stamp_ok() { [ -f "$1" ] && [ -f "$1.sum" ] && [ "$(cat "$1.sum")" = "$2" ]; }
prepare_settled() { # name exe deck output-file extra-files...
  local name="$1" exe_="$2" in="$3" out="$4"; shift 4
  local sum; sum=$(cat "$in" "$@" 2> /dev/null | md5sum | cut -d' ' -f1)
  local dir="$cache/$name"
  mkdir -p "$dir"
  if stamp_ok "$dir/$out" "$sum"; then return 0; fi
  need_package "$exe_" "$( [ "$exe_" = lmp ] && echo lammps || echo liggghts )"
  echo "run_peer.sh: preparing $dir/$out (untimed settling run, a few minutes, once)" >&2
  local tmp; tmp=$(mktemp -d "$dir/.prep.XXXXXX")
  local f; for f in "$@"; do cp "$f" "$tmp/"; done
  local saved_ranks="$ranks"; ranks=1 # one rank: the same packing whatever the timed run uses
  run_code "$tmp" "$in" "$tmp/prep.log" "$exe_" || { ranks="$saved_ranks"; die "preparation of $out failed (folder $tmp kept)"; }
  ranks="$saved_ranks"
  [ -s "$tmp/$out" ] || die "preparation wrote no $out (folder $tmp kept)"
  mv "$tmp/prep.log" "$dir/$out.prep.log"
  mv "$tmp/$out" "$dir/$out"
  echo "$sum" > "$dir/$out.sum"
  rm -rf "$tmp"
}

stl=""
case "$prep" in
  chute)
    rundir="$cache/chute"; mkdir -p "$rundir"
    data="$peers/chute/data.chute"; [ -f "$data" ] || die "'$data' not found"
    vars+=(datafile "$data") ;;
  hertz)
    prepare_settled hertz_packing lmp "$peers/hertz_packing/in.settle" packing.data
    rundir="$cache/hertz_packing"; data="$rundir/packing.data" ;;
  mesh)
    rundir="$cache/mesh_wall"; mkdir -p "$rundir"
    command -v python3 > /dev/null 2>&1 || die "python3 is needed to write the STL floors"
    python3 "$peers/mesh_wall/make_stl.py" 40 0.1 "$rundir/.plane40.stl.tmp" > /dev/null
    if ! cmp -s "$rundir/.plane40.stl.tmp" "$rundir/plane40.stl"; then mv "$rundir/.plane40.stl.tmp" "$rundir/plane40.stl"; else rm -f "$rundir/.plane40.stl.tmp"; fi
    # in.prep reads plane40.stl from its folder; the checksum covers deck, STL and generator
    prepare_settled mesh_wall liggghts "$peers/mesh_wall/in.prep" settled.data "$rundir/plane40.stl"
    for f in "$peers"/mesh_wall/wall_*.lig "$peers"/mesh_wall/wall_*.lmp; do ln -sf "$f" "$rundir/"; done
    data="$rundir/settled.data"
    stl="$rundir/plane40.stl"
    if [ -n "${ntri:-}" ]; then
      stl="$rundir/plane_${ntri}.stl"
      if [ ! -s "$stl" ]; then
        python3 "$peers/mesh_wall/make_stl.py" "$nside" 0.1 "$stl.tmp" > /dev/null && mv "$stl.tmp" "$stl"
      fi
    fi ;;
esac
[ "$have_flock" -eq 0 ] || flock -u 9
exec 9>&-

if [ "$prepare_only" -eq 1 ]; then
  echo "peer-data: scene=$scene data=$data${stl:+ stl=$stl}"
  exit 0
fi

# ------------------------------------------------------------- timed runs
logs="$cache/logs"; mkdir -p "$logs"
times=(); particles=""; steps_run=""
for ((k = 1; k <= repeat; ++k)); do
  log="$logs/${scene}_r${ranks}_$$_$k.log"
  load=""
  [ ! -r /proc/loadavg ] || load=" load=$(cut -d' ' -f1 /proc/loadavg)" # runnable processes before the run
  run_code "$rundir" "$deck" "$log" "$exe" "${vars[@]}" nsteps "$steps" || exit 1
  # "Loop time of T on P procs for S steps with A atoms": the last one is the timed run
  line=$(grep '^Loop time of' "$log" | tail -n 1)
  [ -n "$line" ] || die "no 'Loop time' line in $log"
  read -r t p s a < <(echo "$line" | awk '{ print $4, $6, $9, $12 }')
  [ "$s" = "$steps" ] || die "timed run did $s steps, expected $steps (log $log)"
  [ "$p" = "$ranks" ] || die "peer ran on $p ranks, expected $ranks (log $log)"
  us=$(awk -v t="$t" -v a="$a" -v s="$s" 'BEGIN { printf "%.4f", t / (a * s) * 1e6 }')
  cpu=""
  if [ -s "$log.time" ]; then
    cpu=$(awk -v r="$ranks" 'NF == 3 { if ($1 > 0) printf " cpu_share=%.2f", ($2 + $3) / ($1 * r) }' "$log.time")
  fi
  # the answer: the last thermo line of the timed run (the one just before
  # its "Loop time"), when the deck prints "Step Atoms KinEng <rotational>"
  answer=$(awk '/^ *Step +Atoms +KinEng/ { h = 1; next } h && /^ *[0-9]/ { last = $0 } /^Loop time of/ { h = 0; keep = last }
                END { if (keep != "") { split(keep, f, " "); printf " ke=%s erot=%s", f[3], f[4] } }' "$log")
  echo "run $k/$repeat: scene=$scene code=$code ranks=$ranks particles=$a steps=$s loop_time=$t us_per_particle_step=$us$cpu$load$answer"
  times+=("$t"); particles="$a"; steps_run="$s"; last_answer="$answer"
  [ "${TALUS_PEERS_KEEP_LOGS:-0}" = 1 ] || rm -f "$log" "$log.out" "$log.time"
done

printf '%s\n' "${times[@]}" | sort -g | awk -v scene="$scene" -v code="$code" -v ranks="$ranks" \
    -v n="$particles" -v s="$steps_run" -v answer="${last_answer:-}" '
  { t[NR] = $1 }
  END {
    med = (NR % 2) ? t[(NR + 1) / 2] : 0.5 * (t[NR / 2] + t[NR / 2 + 1])
    scale = 1e6 / (n * s)
    printf "spread: max/min = %.3f over %d runs\n", t[NR] / t[1], NR
    printf "peer: scene=%s code=%s ranks=%d particles=%d steps=%d loop_time=%g us_per_particle_step=%.4f median=%.4f%s\n",
      scene, code, ranks, n, s, t[1], t[1] * scale, med * scale, answer
  }'
