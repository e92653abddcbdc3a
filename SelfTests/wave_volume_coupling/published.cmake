# The published configuration against the authors' own run (label long): runs
# DRIVER with ARGS and checks the dissipated fraction of its summary against
# PUBLISHED (the authors' figure at the same c, tools/v1_published_runs.py,
# docs/v1_published_runs.csv) within TOL, and the run's own -check.
include(${CMAKE_CURRENT_LIST_DIR}/../check_values.cmake)
foreach(v DRIVER ARGS PUBLISHED TOL AWK)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "published.cmake: ${v} is required")
  endif()
endforeach()
separate_arguments(args UNIX_COMMAND "${ARGS}")
execute_process(COMMAND ${DRIVER} ${args} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${DRIVER} failed (exit ${rc})")
endif()
talus_read_summary("${out}" val_ "wave_volume_coupling -configuration published")
set(failed 0)
talus_check_value(dissipated "${val_dissipated}" ${PUBLISHED} 0 ${TOL} ${AWK})
if(failed)
  message(FATAL_ERROR "dissipated fraction off the published run's ${PUBLISHED} by more than ${TOL}")
endif()
