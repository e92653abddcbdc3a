# Runs DRIVER with ARGS and compares the keys of its summary line with
# BASELINE (lines "key value rel_tol abs_tol": passes when |x - value| <=
# abs_tol + rel_tol |value|; every value must be a finite number).  With
# -DWRITE_BASELINE=ON it writes BASELINE from this run instead, with the
# tolerances of TOLERANCES ("key rel abs;...").
include(${CMAKE_CURRENT_LIST_DIR}/../check_values.cmake)
separate_arguments(args UNIX_COMMAND "${ARGS}")
execute_process(COMMAND ${DRIVER} ${args} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${DRIVER} failed (exit ${rc})")
endif()
talus_read_summary("${out}" val_ "periodic_compress")
if(WRITE_BASELINE)
  talus_write_baseline(${BASELINE}
    "# produced by: cmake -S . -B build -DTALUS_WRITE_PERIODIC_BASELINE=ON && ctest --test-dir build -R selftest_periodic_compress\n# key value rel_tol abs_tol\n"
    val_ "${TOLERANCES}")
  return()
endif()
set(failed 0)
talus_check_baseline(${BASELINE} val_ ${AWK})
# INVARIANTS: awk conditions on the summary's keys ("n_small + n_large == n;..."),
# each of which must hold whatever the baseline says.
if(DEFINED INVARIANTS)
  talus_check_invariants(val_ "${INVARIANTS}" ${AWK})
endif()
if(failed)
  message(FATAL_ERROR "periodic_compress self-test failed")
endif()
