# A kill during a checkpoint write, then a restart (selftest): one run of
# ARGS in one go, against a run of ARGS -checkpoint_every EVERY killed by
# SIGKILL while it writes its checkpoint number KILL_AT (default 2;
# TALUS_CHECKPOINT_KILL_AT, tl_checkpoint.h: the data are in the hidden
# temporary, the rename not done), then restarted from the checkpoint the
# kill left, in the same folder.  Passes when
#  - the killed run died by the signal, leaving checkpoint.h5 (the previous
#    one, whole: the restart loads it, checksums and all) and its hidden
#    temporary .checkpoint.h5.<pid>.<n>.tmp;
#  - the restart removes that temporary, says it restarted (its output
#    matches EXPECT_RESTART, default "restarted from [^\n]* at [a-z ]*step
#    <the first checkpoint's step>"; "none" for a driver that does not say) and
#    ends normally;
#  - every file of TABLES holds the same data as the run in one go (past
#    their provenance lines), and the summaries are equal but for the keys
#    of IGNORE (default: wall; a,b,c or a list).  An entry "a:b" of TABLES compares the last
#    data row of a (the run in one go) with that of b (the restarted run),
#    for a driver whose restart writes a table of its own.
foreach(v DRIVER ARGS EVERY OUT TABLES)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "kill.cmake: ${v} is required")
  endif()
endforeach()
if(NOT DEFINED KILL_AT)
  set(KILL_AT 2)
endif()
if(NOT DEFINED IGNORE)
  set(IGNORE wall)
endif()
string(REPLACE "," ";" IGNORE "${IGNORE}") # a list given as a,b,c
file(REMOVE_RECURSE "${OUT}")
separate_arguments(args UNIX_COMMAND "${ARGS}")
function(summary_of out var)
  string(REGEX MATCH "summary: [^\n]*" sum "${out}")
  foreach(k IN LISTS IGNORE)
    string(REGEX REPLACE " ${k}=[^ ]*" "" sum "${sum}")
  endforeach()
  set(${var} "${sum}" PARENT_SCOPE)
endfunction()

execute_process(COMMAND ${DRIVER} ${args} -output_dir ${OUT}/full RESULT_VARIABLE rc OUTPUT_VARIABLE full_out
                ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the run in one go failed (exit ${rc}):\n${full_out}${err}")
endif()
summary_of("${full_out}" full_summary)

find_program(ENV_PROGRAM env REQUIRED)
execute_process(COMMAND ${ENV_PROGRAM} TALUS_CHECKPOINT_KILL_AT=${KILL_AT} ${DRIVER} ${args} -checkpoint_every ${EVERY} -output_dir ${OUT}/run
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc MATCHES "[Kk]illed" OR NOT err MATCHES "killed while writing checkpoint ${KILL_AT}")
  message(FATAL_ERROR "the run was not killed in checkpoint ${KILL_AT} (exit ${rc}):\n${out}${err}")
endif()
file(GLOB temps ${OUT}/run/.checkpoint.h5.*.tmp)
if(NOT EXISTS ${OUT}/run/checkpoint.h5 OR NOT temps)
  file(GLOB left RELATIVE ${OUT}/run ${OUT}/run/* ${OUT}/run/.*)
  message(FATAL_ERROR "the kill left no checkpoint.h5 and hidden temporary in ${OUT}/run: ${left}")
endif()
message("killed (${rc}) in checkpoint ${KILL_AT}, leaving checkpoint.h5 and ${temps}")

execute_process(COMMAND ${DRIVER} ${args} -checkpoint_every ${EVERY} -restart ${OUT}/run/checkpoint.h5
                        -output_dir ${OUT}/run
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the restart after the kill failed (exit ${rc}):\n${out}${err}")
endif()
if(NOT DEFINED EXPECT_RESTART)
  set(EXPECT_RESTART "restarted from [^\n]* at [a-z ]*step ${EVERY}[^0-9]")
endif()
string(REGEX MATCH "restarted from [^\n]*" said "${out}")
if(NOT EXPECT_RESTART STREQUAL "none" AND NOT out MATCHES "${EXPECT_RESTART}")
  message(FATAL_ERROR "the restart did not say it restarted ('${EXPECT_RESTART}'):\n${out}")
endif()
foreach(t IN LISTS temps)
  if(EXISTS ${t})
    message(FATAL_ERROR "the restart left the killed write's temporary ${t}")
  endif()
endforeach()
include(${CMAKE_CURRENT_LIST_DIR}/../compare_data.cmake)
foreach(t IN LISTS TABLES)
  if(t MATCHES "^([^:]+):(.+)$")
    set(a ${OUT}/full/${CMAKE_MATCH_1})
    set(b ${OUT}/run/${CMAKE_MATCH_2})
    if(NOT EXISTS ${a} OR NOT EXISTS ${b})
      message(FATAL_ERROR "${a} or ${b} is missing")
    endif()
    file(STRINGS ${a} ra REGEX "^[^#]")
    file(STRINGS ${b} rb REGEX "^[^#]")
    list(LENGTH rb nb)
    if(nb LESS 2)
      message(FATAL_ERROR "${b} holds no data row")
    endif()
    list(GET ra -1 la)
    list(GET rb -1 lb)
    if(NOT la STREQUAL lb)
      message(FATAL_ERROR "the last rows differ after the kill and restart:\n  in one go: ${la}\n  restarted: ${lb}")
    endif()
    continue()
  endif()
  talus_compare_data(${OUT}/full/${t} ${OUT}/run/${t} diff)
  if(diff)
    message(FATAL_ERROR "${t} after the kill and restart differs from the run in one go: ${diff}")
  endif()
endforeach()
summary_of("${out}" run_summary)
if(NOT full_summary STREQUAL run_summary OR full_summary STREQUAL "")
  message(FATAL_ERROR "summaries differ:\n  in one go:           ${full_summary}\n  killed and restarted: ${run_summary}")
endif()
message("killed in checkpoint ${KILL_AT}, ${said}: ${TABLES} identical; ${full_summary}")
