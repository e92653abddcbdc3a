# bar_wave labels the pulse's peak as what it is: v_y = v0 (cos(omega t) - 1)
# peaks at 2 v0, and the line once printed 2 v0 as "v0 = ...".  Passes when
# the summary's pulse_peak is 2 x v0, the printed line names "2 v0 = <that>",
# and both stations' peaks lie within 5 % of it (a pulse that travels
# undistorted between them).
execute_process(COMMAND ${DRIVER} -v0 0.03 -output_dir ${OUT} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "bar_wave failed (exit ${rc}):\n${out}${err}")
endif()
set(num "[0-9.eE+-]+")
if(NOT out MATCHES "summary: .* v0=(${num}) pulse_peak=(${num}) peak_station1=(${num}) peak_station2=(${num})")
  message(FATAL_ERROR "no v0, pulse_peak and station peaks in the summary:\n${out}")
endif()
set(v0 ${CMAKE_MATCH_1})
set(peak ${CMAKE_MATCH_2})
set(p1 ${CMAKE_MATCH_3})
set(p2 ${CMAKE_MATCH_4})
if(NOT out MATCHES "2 v0 = ${peak} m/s")
  message(FATAL_ERROR "the printed line does not label the peak ${peak} m/s as 2 v0:\n${out}")
endif()
execute_process(COMMAND ${AWK} "BEGIN { exit !(${peak} == 2 * ${v0} && ${p1} > 0.95 * ${peak} && ${p1} < 1.05 * ${peak} && ${p2} > 0.95 * ${peak} && ${p2} < 1.05 * ${peak}) }"
                RESULT_VARIABLE bad)
if(NOT bad EQUAL 0)
  message(FATAL_ERROR "v0 ${v0}, pulse peak ${peak}, station peaks ${p1} and ${p2}: expected 2 v0 and within 5 %")
endif()
message("v0 = ${v0} m/s, pulse peak 2 v0 = ${peak} m/s, stations ${p1} and ${p2} m/s")
