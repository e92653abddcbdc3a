# settle's snapshot cadence, its report on an unsettled packing, and a rerun
# into the same folder (selftest, ~3 s):
#  1. -n 300 -t_end 0.1 -snapshot_dt 0.01: 11 snapshot files and 11 steps in
#     particles.xmf (t = 0, 0.01, ..., 0.1; the count cadence wrote 12 for
#     -snapshots 10); the grains are still falling at 0.1 s, so the run says
#     "not settled", the summary carries settled=false, and nothing prints
#     "-0.0000";
#  2. the same folder again with -snapshot_dt 0.05: 3 files, none of run 1's
#     left beside them;
#  3. the same folder again with snapshots off (-snapshot_dt 0): no
#     particles.xmf, walls.xmf or particles_*.h5 of the earlier runs left.
set(common -n 300 -t_end 0.1 -table_rows 20 -output_dir ${OUT})
file(REMOVE_RECURSE "${OUT}")
foreach(run "0.01;11" "0.05;3")
  list(GET run 0 dt)
  list(GET run 1 expected)
  execute_process(COMMAND ${DRIVER} ${common} -snapshot_dt ${dt} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "settle -snapshot_dt ${dt} failed (exit ${rc}):\n${out}${err}")
  endif()
  file(GLOB files ${OUT}/particles_*.h5)
  list(LENGTH files n)
  file(READ ${OUT}/particles.xmf xmf)
  string(REGEX MATCHALL "<Time Value=" steps "${xmf}")
  list(LENGTH steps ns)
  if(NOT n EQUAL ${expected} OR NOT ns EQUAL ${expected})
    message(FATAL_ERROR "-t_end 0.1 -snapshot_dt ${dt}: ${n} snapshot files and ${ns} steps in particles.xmf, expected ${expected}")
  endif()
  message("-snapshot_dt ${dt}: ${n} files, ${ns} steps")
endforeach()
if(NOT out MATCHES "not settled at t = 0.1 s" OR NOT out MATCHES "summary: .*settled=false")
  message(FATAL_ERROR "an unsettled packing not reported as such:\n${out}")
endif()
if(out MATCHES "-0\\.0000")
  message(FATAL_ERROR "a negative zero printed:\n${out}")
endif()
message("unsettled packing reported: settled=false")
execute_process(COMMAND ${DRIVER} ${common} -snapshot_dt 0 RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "settle -snapshot_dt 0 failed (exit ${rc}):\n${out}${err}")
endif()
file(GLOB left ${OUT}/particles*.h5 ${OUT}/particles.xmf ${OUT}/walls*.h5 ${OUT}/walls.xmf)
if(left)
  message(FATAL_ERROR "a rerun with snapshots off left the earlier series: ${left}")
endif()
message("-snapshot_dt 0: no earlier series left")
