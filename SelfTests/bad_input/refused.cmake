# Runs DRIVER with ARGS (a ;-list) in OUT and passes when the run is refused:
# a non-zero exit (EXIT, when given, exactly: 2 for a refused option or
# input, 1 for a run stopped on a diagnosis), stderr or stdout matching
# EXPECT (a regular expression naming the value and the limit), a last
# "summary:" line on stdout whose status= says how the run ended, and no
# "nan" or "inf" printed anywhere.
if(NOT DEFINED DRIVER OR NOT DEFINED EXPECT OR NOT DEFINED OUT)
  message(FATAL_ERROR "refused.cmake: DRIVER, EXPECT and OUT are required")
endif()
# A list drops empty items: "-output_dir ''" in ARGS passes an empty
# folder name in place of OUT.
set(dir "${OUT}")
if(ARGS MATCHES "-output_dir ''")
  string(REPLACE "-output_dir ''" "" ARGS "${ARGS}")
  set(dir "")
endif()
separate_arguments(args UNIX_COMMAND "${ARGS}")
execute_process(COMMAND ${DRIVER} ${args} -output_dir "${dir}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
set(all "${out}${err}")
if(rc EQUAL 0)
  message(FATAL_ERROR "accepted (exit 0), expected a refusal matching '${EXPECT}':\n${all}")
endif()
if(NOT all MATCHES "${EXPECT}")
  message(FATAL_ERROR "refused (exit ${rc}) without the expected message '${EXPECT}':\n${all}")
endif()
if(all MATCHES "(^|[^a-zA-Z_])(-?nan|-?inf)([^a-zA-Z_]|$)")
  message(FATAL_ERROR "the output prints a NaN or an infinity:\n${all}")
endif()
if(DEFINED EXIT AND NOT rc EQUAL EXIT)
  message(FATAL_ERROR "refused with exit ${rc}, expected exit ${EXIT}:\n${all}")
endif()
# The last summary line tells the status without stderr.
string(REGEX MATCHALL "summary:[^\n]*" summaries "${out}")
list(LENGTH summaries n)
if(n EQUAL 0)
  message(FATAL_ERROR "no summary line on stdout:\n${out}")
endif()
list(GET summaries -1 last)
if(rc EQUAL 2)
  set(word "refused")
else()
  set(word "(stopped|undefined|failed)")
endif()
if(NOT last MATCHES " status=${word}( |$)" OR NOT last MATCHES " exit=${rc}( |$)")
  message(FATAL_ERROR "the last summary line '${last}' does not say status=${word} exit=${rc}")
endif()
message("refused, exit ${rc}: ${last}")
