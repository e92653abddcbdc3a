# Runs DRIVER once per entry of RUNS ("prefix|arguments", ';'-separated),
# collects the summary keys of each run as <prefix>_<key>, and compares them
# with BASELINE (lines "key value rel_tol abs_tol": passes when
# |x - value| <= abs_tol + rel_tol |value|, every value a finite number),
# then checks INVARIANTS (awk conditions on the collected keys, which must
# hold whatever the baseline says).  With -DWRITE_BASELINE=ON it writes
# BASELINE from these runs instead, with the tolerances of TOLERANCES
# ("key rel abs;...") and the command that produced it.
include(${CMAKE_CURRENT_LIST_DIR}/../check_values.cmake)
set(prefixes "")
foreach(run IN LISTS RUNS)
  string(REGEX REPLACE "\\|.*" "" prefix "${run}")
  string(REGEX REPLACE "^[^|]*\\|" "" argline "${run}")
  separate_arguments(args UNIX_COMMAND "${argline}")
  execute_process(COMMAND ${DRIVER} ${args} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("== ${prefix}: ${DRIVER} ${argline}\n${out}${err}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${DRIVER} failed (exit ${rc}) in run ${prefix}")
  endif()
  talus_read_summary("${out}" val_${prefix}_ "run ${prefix}")
  list(APPEND prefixes val_${prefix}_)
endforeach()
if(WRITE_BASELINE)
  talus_write_baseline(${BASELINE}
    "# produced by: cmake -S . -B build -DTALUS_WRITE_ELASTIC_BASELINE=ON && (cd build && ctest -R ${TEST_NAME})\n# key value rel_tol abs_tol\n"
    val_ "${TOLERANCES}")
  return()
endif()
set(failed 0)
talus_check_baseline(${BASELINE} val_ ${AWK})
talus_check_invariants("${prefixes}" "${INVARIANTS}" ${AWK})
if(failed)
  message(FATAL_ERROR "${TEST_NAME} failed")
endif()
