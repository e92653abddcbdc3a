# Installs the built Talus into a scratch prefix, configures and builds the
# Examples project against it (find_package(Talus)), and runs its tests
# (every example driver).  Arguments: TALUS_BINARY_DIR, EXAMPLES_SOURCE_DIR,
# WORK_DIR, and optionally EXAMPLES_C_FLAGS (e.g. sanitizers) and
# EXAMPLES_WERROR.
file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  message(STATUS "${out}")
endfunction()

run(${CMAKE_COMMAND} --install ${TALUS_BINARY_DIR} --prefix ${prefix})
run(${CMAKE_COMMAND} -S ${EXAMPLES_SOURCE_DIR} -B ${WORK_DIR}/build -DCMAKE_PREFIX_PATH=${prefix}
    -DCMAKE_BUILD_TYPE=Release "-DCMAKE_C_FLAGS=${EXAMPLES_C_FLAGS}" -DEXAMPLES_WERROR=${EXAMPLES_WERROR})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run(${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${prefix}/lib OMP_NUM_THREADS=1
    ${CMAKE_CTEST_COMMAND} --test-dir ${WORK_DIR}/build --output-on-failure -V)
