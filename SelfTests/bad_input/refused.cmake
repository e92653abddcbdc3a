# Runs DRIVER with ARGS (a ;-list) in OUT and passes when the run is refused:
# a non-zero exit, stderr or stdout matching EXPECT (a regular expression
# naming the value and the limit), and no "nan" or "inf" printed anywhere.
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
