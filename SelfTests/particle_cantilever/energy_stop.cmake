# Runs particle_cantilever with ARGS on a configuration that goes unstable
# and asserts that it stops with the energy diagnosis: a non-zero exit, the
# diagnosis on stderr naming the energy, the time and the limit LIMIT, the
# energy over LIMIT times its start, and the stop before the run's end T_END.
separate_arguments(args UNIX_COMMAND "${ARGS}")
execute_process(COMMAND ${DRIVER} ${args} -energy_limit ${LIMIT} -t_end ${T_END} -output_dir ${OUT} -snapshot_dt 0
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(rc EQUAL 0)
  message(FATAL_ERROR "the unstable run ended with exit 0: the energy limit ${LIMIT} did not stop it")
endif()
set(num "[-+]?[0-9]+(\\.[0-9]*)?([eE][-+]?[0-9]+)?")
string(REGEX MATCH "coupled total energy (${num}) J at t = (${num}) s exceeds ${LIMIT} x its start (${num}) J" hit "${err}")
if(hit STREQUAL "")
  message(FATAL_ERROR "exit ${rc} without the energy diagnosis on stderr")
endif()
set(energy "${CMAKE_MATCH_1}")
set(t "${CMAKE_MATCH_4}")
set(start "${CMAKE_MATCH_7}")
# the values matched as numbers only (so no nan or inf gets here)
execute_process(COMMAND ${AWK} "BEGIN { exit !(${energy} > ${LIMIT} * ${start} && ${t} > 0 && ${t} < ${T_END}) }"
                RESULT_VARIABLE bad)
if(NOT bad EQUAL 0)
  message(FATAL_ERROR "diagnosis with E = ${energy} J, start ${start} J, t = ${t} s: not E > ${LIMIT} x start within (0, ${T_END}) s")
endif()
message("stopped at t = ${t} s with E = ${energy} J > ${LIMIT} x ${start} J (exit ${rc})")
# The advice fits the run: a lock-step run (no -substeps given) is not told
# to use fewer sub-steps or lock-step, and no line of the report is printed
# twice (each trace line names one place once).
if(NOT args MATCHES "-substeps" AND err MATCHES "fewer sub-steps|fewer DEM steps|or lock-step")
  message(FATAL_ERROR "a lock-step run advised to use fewer sub-steps or lock-step:\n${err}")
endif()
if(NOT err MATCHES "the run is lock-step")
  message(FATAL_ERROR "the diagnosis of a lock-step run does not say it is lock-step:\n${err}")
endif()
string(REPLACE ";" "," err_lines "${err}") # a CMake list splits at semicolons
string(REPLACE "\n" ";" lines "${err_lines}")
set(seen "")
foreach(line IN LISTS lines)
  if(line STREQUAL "")
    continue()
  endif()
  list(FIND seen "${line}" at)
  if(NOT at EQUAL -1)
    message(FATAL_ERROR "stderr repeats the line '${line}':\n${err}")
  endif()
  list(APPEND seen "${line}")
endforeach()
