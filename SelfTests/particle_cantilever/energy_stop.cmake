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
