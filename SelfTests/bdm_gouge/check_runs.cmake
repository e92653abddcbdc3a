# Runs DRIVER once per entry of RUNS ("name|arguments", the arguments
# appended to COMMON), reads each run's summary line, and
#  - compares the values named in BASELINE (lines "name.key value rel_tol
#    abs_tol": |x - value| <= abs_tol + rel_tol |value|, every value a
#    finite number) - or, with -DWRITE_BASELINE=ON, writes BASELINE from
#    these runs with the tolerances of TOLERANCES ("key rel abs;...", for
#    that key of every run);
#    BASELINE "none": no baseline, the invariants alone;
#  - checks INVARIANTS: awk conditions on the runs' values, named
#    name_key ("strong_both_noise < 0.02 * strong_none_noise;..."), which
#    must hold whatever the baseline says.
include(${CMAKE_CURRENT_LIST_DIR}/../check_values.cmake)
separate_arguments(common UNIX_COMMAND "${COMMON}")
set(prefixes "")
foreach(run IN LISTS RUNS)
  string(REGEX REPLACE "\\|.*" "" name "${run}")
  string(REGEX REPLACE "^[^|]*\\|" "" extra "${run}")
  separate_arguments(extra UNIX_COMMAND "${extra}")
  execute_process(COMMAND ${DRIVER} ${common} ${extra} -output_dir ${OUT}/${name} RESULT_VARIABLE rc
                  OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("[${name}] ${out}${err}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${DRIVER} failed on run ${name} (exit ${rc})")
  endif()
  talus_read_summary("${out}" val_${name}. "run ${name}")
  list(APPEND prefixes val_${name}.)
endforeach()
set(failed 0)
if(WRITE_BASELINE)
  # every tolerance line "key rel abs" for each run that printed the key
  set(tolerances "")
  foreach(p IN LISTS prefixes)
    string(REGEX REPLACE "^val_" "" name "${p}")
    foreach(line IN LISTS TOLERANCES)
      string(REGEX REPLACE " .*" "" k "${line}")
      if(DEFINED ${p}${k})
        list(APPEND tolerances "${name}${line}")
      endif()
    endforeach()
  endforeach()
  talus_write_baseline(${BASELINE} "# produced by: cmake -S . -B build -DTALUS_WRITE_BDM_GOUGE_BASELINE=ON && ctest --test-dir build -R ${TEST}\n# run.key value rel_tol abs_tol\n" val_ "${tolerances}")
elseif(NOT BASELINE STREQUAL "none") # "none": invariants only (the paper-scale runs)
  talus_check_baseline(${BASELINE} val_ ${AWK})
endif()
# Invariants across the runs (awk, variables name_key).
talus_check_invariants("${prefixes}" "${INVARIANTS}" ${AWK})
if(failed)
  message(FATAL_ERROR "${TEST}: some check failed")
endif()
