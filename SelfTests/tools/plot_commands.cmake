# The plot command a driver prints runs as printed, from any folder, and its
# plots say what they show:
#  1. particle_cantilever with a relative -output_dir, run in RUN_DIR: the
#     printed "plots:" line names /usr/bin/python3, the script and the folder
#     by absolute paths; run from another folder (/) with --describe, its
#     energy panel has the five terms of the total (the gravitational one
#     among them) and the total, each in a colour of its own;
#  2. tools/plot_timeseries.py on settle's energies.csv puts each unit on a
#     panel of its own (J, kg m/s, N and the dimensionless coordination).
# Without matplotlib in /usr/bin/python3 the plots are skipped ("SKIP: ").
cmake_minimum_required(VERSION 3.16) # IN_LIST
file(REMOVE_RECURSE ${RUN_DIR})
file(MAKE_DIRECTORY ${RUN_DIR})
execute_process(COMMAND ${PC} -t_end 0.02 -snapshot_dt 0 -output_dir pc_rel WORKING_DIRECTORY ${RUN_DIR}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "particle_cantilever failed (exit ${rc}):\n${out}${err}")
endif()
if(NOT out MATCHES "\nplots: (/usr/bin/python3) (/[^ \n]+/plot_particle_cantilever\\.py) (/[^ \n]+)\n")
  message(FATAL_ERROR "no plot command with absolute paths and /usr/bin/python3:\n${out}")
endif()
set(py ${CMAKE_MATCH_1})
set(script ${CMAKE_MATCH_2})
set(folder ${CMAKE_MATCH_3})
if(NOT folder STREQUAL "${RUN_DIR}/pc_rel")
  message(FATAL_ERROR "the plot command names the folder ${folder}, not ${RUN_DIR}/pc_rel")
endif()
message("printed: ${py} ${script} ${folder}")
execute_process(COMMAND ${py} -c "import matplotlib" RESULT_VARIABLE no_mpl OUTPUT_QUIET ERROR_QUIET)
if(NOT no_mpl EQUAL 0)
  message("SKIP: ${py} has no matplotlib (Debian's python3-matplotlib): the plot commands were not run")
  return()
endif()
execute_process(COMMAND ${py} ${script} ${folder} --describe WORKING_DIRECTORY /
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT EXISTS ${folder}/particle_cantilever.png)
  message(FATAL_ERROR "the printed plot command failed from / (exit ${rc}):\n${out}${err}")
endif()
string(REGEX MATCHALL "energy-line [^ \n]+ #[0-9a-f]+" lines "${out}")
set(labels "")
set(colours "")
foreach(l IN LISTS lines)
  string(REGEX REPLACE "energy-line ([^ ]+) (#[0-9a-f]+)" "\\1" lab "${l}")
  string(REGEX REPLACE "energy-line ([^ ]+) (#[0-9a-f]+)" "\\2" col "${l}")
  list(APPEND labels ${lab})
  if(col IN_LIST colours)
    message(FATAL_ERROR "two lines of the energy panel share the colour ${col}:\n${out}")
  endif()
  list(APPEND colours ${col})
endforeach()
foreach(want DEM_kinetic DEM_elastic FEM_kinetic FEM_strain total)
  if(NOT want IN_LIST labels)
    message(FATAL_ERROR "the energy panel has no '${want}' line:\n${out}")
  endif()
endforeach()
if(NOT labels MATCHES "gravitational")
  message(FATAL_ERROR "the energy panel leaves out the gravitational term:\n${out}")
endif()
message("energy panel: ${labels}")
execute_process(COMMAND ${SETTLE} -n 300 -t_end 0.01 -snapshot_dt 0 -output_dir ${RUN_DIR}/settle
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "settle failed (exit ${rc}):\n${out}${err}")
endif()
execute_process(COMMAND ${py} ${TOOLS}/plot_timeseries.py ${RUN_DIR}/settle/energies.csv --describe
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "plot_timeseries.py failed (exit ${rc}):\n${out}${err}")
endif()
string(REGEX MATCHALL "panel \\[[^]\n]*\\]" panels "${out}")
list(LENGTH panels np)
foreach(want "panel [J] kinetic" "panel [kg m/s] momentum_z" "panel [N] wall_force_z" "panel [] coordination")
  string(FIND "${out}" "${want}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "plot_timeseries.py: no '${want}' panel (one unit per panel):\n${out}")
  endif()
endforeach()
message("plot_timeseries.py: ${np} panels, one unit each")
