# Runs particle_cantilever with ARGS, then compares its summary line and the
# last row of trajectory.csv with BASELINE (lines "key value rel_tol abs_tol":
# passes when |x - value| <= abs_tol + rel_tol |value|), and applies the
# physics checks: x-symmetry kept (sym_dev <= SYM_MAX, when given) and
# energy bounded (E_max <= E_BOUND), and when given err_avg <= ERR_MAX and
# T_OFF_MIN <= t_off <= T_OFF_MAX; a run that must reproduce a failure
# gives E_MIN (E_max >= E_MIN) and SYM_MIN (sym_dev >= SYM_MIN) instead of
# E_BOUND and SYM_MAX.  With -DWRITE_BASELINE=1 it writes
# BASELINE from this run instead (tolerances from TOLERANCES, "key rel abs").
# A missing or empty baseline fails loudly; BASELINE=NONE (paper-scale runs
# only) skips the regression part.
separate_arguments(args UNIX_COMMAND "${ARGS}")
execute_process(COMMAND ${DRIVER} ${args} -output_dir ${OUT} -snapshot_dt 0
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "particle_cantilever failed (exit ${rc}):\n${err}")
endif()
include(${CMAKE_CURRENT_LIST_DIR}/../check_values.cmake)
talus_read_summary("${out}" val_ "particle_cantilever")
# Last row of the trajectory: final positions of both particles.
file(STRINGS ${OUT}/trajectory.csv rows)
list(GET rows -1 last)
string(REPLACE "," ";" last "${last}")
list(GET last 1 val_x1)
list(GET last 2 val_y1)
list(GET last 3 val_z1)
list(GET last 4 val_x2)
list(GET last 5 val_y2)
list(GET last 6 val_z2)

if(WRITE_BASELINE)
  talus_write_baseline(${BASELINE} "# produced by: cmake -S . -B build -DTALUS_WRITE_PC_BASELINE=ON && ctest --test-dir build -R selftest_particle_cantilever\n# key value rel_tol abs_tol\n" val_ "${TOLERANCES}")
  if(DEFINED TRAJ_BASELINE)
    file(COPY_FILE ${OUT}/trajectory.csv ${TRAJ_BASELINE})
    message("wrote ${TRAJ_BASELINE}")
  endif()
  return()
endif()
# Every value a check uses must be a finite number (awk reads "nan" as 0).
set(failed 0)
if(NOT BASELINE STREQUAL "NONE") # NONE: paper-scale runs, physics checks only (below)
  talus_check_baseline(${BASELINE} val_ ${AWK})
endif()
# The whole trajectory (every row and column of trajectory.csv, its
# leading '#' provenance lines left out) against
# TRAJ_BASELINE: the same number of rows, every field a number, and each
# within TRAJ_TOL (absolute; positions in m, counts exactly equal at any
# tolerance below 1).
if(DEFINED TRAJ_BASELINE)
  if(NOT EXISTS ${TRAJ_BASELINE})
    message(FATAL_ERROR "trajectory baseline ${TRAJ_BASELINE} is missing")
  endif()
  execute_process(COMMAND ${AWK} -F, -v tol=${TRAJ_TOL} "
      /^#/ { next }
      { r = ++rows[FILENAME] }
      r == 1 { next }
      NR == FNR { for (i = 1; i <= NF; ++i) b[r, i] = $i; nb = r; nf = NF; next }
      { n = r
        if (NF != nf) { print \"row \" r \": \" NF \" fields, baseline \" nf; bad = 1; next }
        for (i = 1; i <= NF; ++i) {
          if ($i !~ /^[-+]?([0-9]+[.]?[0-9]*|[.][0-9]+)([eE][-+]?[0-9]+)?$/) { print \"row \" r \" field \" i \": '\" $i \"' is not a number\"; bad = 1; continue }
          d = $i - b[r, i]; if (d < 0) d = -d
          if (!(d <= tol)) { if (++shown <= 5) print \"row \" r \" field \" i \": \" $i \" against \" b[r, i]; bad = 1 }
        } }
      END { if (n != nb) { print n \" rows, baseline \" nb; bad = 1 }; exit bad }"
    ${TRAJ_BASELINE} ${OUT}/trajectory.csv RESULT_VARIABLE bad OUTPUT_VARIABLE why)
  if(NOT bad EQUAL 0)
    message(SEND_ERROR "trajectory differs from ${TRAJ_BASELINE} beyond ${TRAJ_TOL}:\n${why}")
    set(failed 1)
  else()
    message("  trajectory: every row within ${TRAJ_TOL} of ${TRAJ_BASELINE}")
  endif()
endif()
# One physics check: when LIMIT is defined, awk evaluates CONDITION; if it
# does not hold, MESSAGE is reported and the test fails.
function(check_physics LIMIT CONDITION MESSAGE)
  if(NOT DEFINED ${LIMIT})
    return()
  endif()
  # the condition's operands (the run's values and the limits) must be numbers
  string(REGEX REPLACE "(<=|>=|&&)" ";" operands "${CONDITION}")
  foreach(v IN LISTS operands)
    string(STRIP "${v}" v)
    if(NOT v MATCHES "${number_re}")
      message(SEND_ERROR "${MESSAGE} ('${v}' is not a finite number)")
      set(failed 1 PARENT_SCOPE)
      return()
    endif()
  endforeach()
  execute_process(COMMAND ${AWK} "BEGIN { exit !(${CONDITION}) }" RESULT_VARIABLE ok)
  if(NOT ok EQUAL 0)
    message(SEND_ERROR "${MESSAGE}")
    set(failed 1 PARENT_SCOPE)
  endif()
endfunction()
check_physics(SYM_MAX "${val_sym_dev} <= ${SYM_MAX}"
              "x-symmetry lost: largest |x1 + x2| = ${val_sym_dev} m > ${SYM_MAX} m")
check_physics(SYM_MIN "${val_sym_dev} >= ${SYM_MIN}"
              "x-symmetry kept (largest |x1 + x2| = ${val_sym_dev} m < ${SYM_MIN} m) where it must be lost")
check_physics(E_BOUND "${val_E_max} <= ${E_BOUND}"
              "energy not bounded: largest total energy ${val_E_max} J > ${E_BOUND} J")
check_physics(E_MIN "${val_E_max} >= ${E_MIN}"
              "largest total energy ${val_E_max} J < ${E_MIN} J: the failure is not reproduced")
check_physics(ERR_MAX "${val_err_avg} <= ${ERR_MAX}" "err_avg = ${val_err_avg} m > ${ERR_MAX} m")
check_physics(T_OFF_MIN "${val_t_off} >= ${T_OFF_MIN} && ${val_t_off} <= ${T_OFF_MAX}"
              "particles leave the beam at t_off = ${val_t_off} s, outside [${T_OFF_MIN}, ${T_OFF_MAX}] s")
if(failed)
  message(FATAL_ERROR "particle_cantilever self-test failed")
endif()
