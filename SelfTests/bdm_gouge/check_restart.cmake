# Bit-for-bit restart of a coupled run: DRIVER with ARGS to STEPS steps in
# one go, and the same run stopped at HALF (checkpoint) then restarted from
# its checkpoint to STEPS; the last rows of both histories (time, the
# monitored planes' displacements, the coupling's report, %.17g) must be
# identical strings.
separate_arguments(args UNIX_COMMAND "${ARGS}")
execute_process(COMMAND ${DRIVER} ${args} -steps ${STEPS} -output_dir ${OUT}/whole RESULT_VARIABLE r1 OUTPUT_VARIABLE o1 ERROR_VARIABLE e1)
execute_process(COMMAND ${DRIVER} ${args} -steps ${STEPS} -stop_step ${HALF} -checkpoint_every ${HALF} -output_dir ${OUT}/first
                RESULT_VARIABLE r2 OUTPUT_VARIABLE o2 ERROR_VARIABLE e2)
execute_process(COMMAND ${DRIVER} ${args} -steps ${STEPS} -restart ${OUT}/first/checkpoint.h5 -output_dir ${OUT}/second
                RESULT_VARIABLE r3 OUTPUT_VARIABLE o3 ERROR_VARIABLE e3)
message("${o1}${e1}\n${o2}${e2}\n${o3}${e3}")
if(NOT r1 EQUAL 0 OR NOT r2 EQUAL 0 OR NOT r3 EQUAL 0)
  message(FATAL_ERROR "a run failed (exits ${r1}, ${r2}, ${r3})")
endif()
file(STRINGS ${OUT}/whole/history.csv a REGEX "^[^#]")
file(STRINGS ${OUT}/second/history_restart${HALF}.csv b REGEX "^[^#]")
list(GET a -1 la)
list(GET b -1 lb)
list(LENGTH a na)
list(LENGTH b nb)
if(na LESS 3 OR nb LESS 2)
  message(FATAL_ERROR "histories too short (${na}, ${nb} lines)")
endif()
# The restarted run must have started at HALF (its first row), not from
# the beginning: otherwise equal last rows would prove nothing.
list(GET b 1 first_row)
string(REGEX MATCH "^[^,]*,([0-9]+)," m "${first_row}")
if(NOT CMAKE_MATCH_1 EQUAL ${HALF} OR NOT nb LESS na)
  message(FATAL_ERROR "the restarted run did not start at step ${HALF}: first row '${first_row}', ${nb} rows against ${na}")
endif()
if(NOT la STREQUAL lb)
  message(FATAL_ERROR "restarted run differs:\n  whole:     ${la}\n  restarted: ${lb}")
endif()
message("restart bit for bit at step ${STEPS}: ${la}")
