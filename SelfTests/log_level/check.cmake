# Runs DRIVER with ARGS (@OUT@ replaced by OUT) at several log levels and
# checks what each prints (CMakeLists.txt says what and why).
if(DEFINED MISSING)
  message(FATAL_ERROR "driver ${MISSING} has no case in SelfTests/log_level/CMakeLists.txt: add its shortest run")
endif()
if(NOT DEFINED DRIVER OR NOT DEFINED OUT OR NOT DEFINED MIN)
  message(FATAL_ERROR "check.cmake: DRIVER, OUT and MIN are required")
endif()
file(MAKE_DIRECTORY "${OUT}")
string(REPLACE "@OUT@" "${OUT}" ARGS "${ARGS}")
separate_arguments(args UNIX_COMMAND "${ARGS}")

# run(<tag> <environment> <arguments...>): out_<tag>, err_<tag>, rc_<tag>.
# The environment is set for the driver alone (cmake -E env), and
# TALUS_LOG_LEVEL is unset unless given, so the caller's cannot leak in.
function(run tag envvar)
  if(envvar)
    set(envcmd ${CMAKE_COMMAND} -E env --unset=TALUS_LOG_LEVEL ${envvar})
  else()
    set(envcmd ${CMAKE_COMMAND} -E env --unset=TALUS_LOG_LEVEL)
  endif()
  execute_process(COMMAND ${envcmd} ${DRIVER} ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err
                  TIMEOUT 240)
  set(out_${tag} "${out}" PARENT_SCOPE)
  set(err_${tag} "${err}" PARENT_SCOPE)
  set(rc_${tag} "${rc}" PARENT_SCOPE)
endfunction()

# The keys of a summary line, in order: "summary: a=1 b=x status=ok" -> a;b;status.
function(summary_keys line var)
  string(REGEX MATCHALL " [A-Za-z0-9_]+=" keys "${line}")
  set(${var} "${keys}" PARENT_SCOPE)
endfunction()

# A quiet run: exit 0, stdout exactly one line, the summary with status=ok,
# stderr empty.
function(expect_quiet tag what)
  if(NOT rc_${tag} EQUAL 0)
    message(FATAL_ERROR "${what}: exit ${rc_${tag}}, expected 0:\n${out_${tag}}${err_${tag}}")
  endif()
  if(NOT out_${tag} MATCHES "^summary: [^\n]* status=ok\n$")
    message(FATAL_ERROR "${what}: stdout is not exactly one line, the summary with status=ok:\n${out_${tag}}")
  endif()
  if(NOT err_${tag} STREQUAL "")
    message(FATAL_ERROR "${what}: stderr is not empty:\n${err_${tag}}")
  endif()
endfunction()

run(error "" ${args} -log_level error)
expect_quiet(error "-log_level error")
run(warn "TALUS_LOG_LEVEL=warn" ${args})
expect_quiet(warn "TALUS_LOG_LEVEL=warn")

# The default level: the usual report, then the same summary.
run(info "" ${args})
if(NOT rc_info EQUAL 0)
  message(FATAL_ERROR "default level: exit ${rc_info}:\n${out_info}${err_info}")
endif()
string(REGEX MATCHALL "[^\n]*\n" lines "${out_info}")
list(LENGTH lines n_info)
if(n_info LESS MIN)
  message(FATAL_ERROR "default level: ${n_info} line(s) on stdout, expected at least ${MIN}:\n${out_info}")
endif()
list(GET lines -1 last_info)
summary_keys("${out_error}" keys_error)
summary_keys("${last_info}" keys_info)
if(NOT last_info MATCHES "^summary: " OR NOT keys_info STREQUAL keys_error)
  message(FATAL_ERROR "default level: the last line is not the summary of -log_level error "
                      "(keys${keys_error}):\n${last_info}")
endif()

# A refused option is still reported at -log_level error.
run(refused "" ${args} -log_level error -no_such_option 1)
if(NOT rc_refused EQUAL 2 OR NOT out_refused MATCHES "^summary: status=refused exit=2 error=invalid_argument\n$"
   OR NOT err_refused MATCHES "^error .invalid argument.: unknown option -no_such_option")
  message(FATAL_ERROR "refused option at -log_level error: exit ${rc_refused} (expected 2), stdout:\n${out_refused}"
                      "stderr:\n${err_refused}")
endif()

# -log_level debug lists the options read on stderr, also before refusing one.
run(debug "" ${args} -log_level debug -no_such_option 1)
if(NOT rc_debug EQUAL 2 OR NOT err_debug MATCHES "(^|\n)debug: option -[A-Za-z0-9_]+ = [^\n]* .command line, argument [0-9]+.")
  message(FATAL_ERROR "-log_level debug: exit ${rc_debug}, expected 2 and the options read on stderr:\n${err_debug}")
endif()
message("${n_info} lines at info, 1 at error and warn: ${out_error}")
