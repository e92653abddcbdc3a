# Installs the built Talus into a scratch prefix, configures and builds the
# Examples project against it (find_package(Talus)), and runs its tests
# (every example driver).  Arguments: TALUS_OUT_OF_TREE (the path of
# cmake/TalusOutOfTree.cmake), TALUS_BINARY_DIR, EXAMPLES_SOURCE_DIR,
# WORK_DIR, and optionally EXAMPLES_C_FLAGS (e.g. sanitizers) and
# EXAMPLES_WERROR.
include(${TALUS_OUT_OF_TREE})
talus_install_scratch(${TALUS_BINARY_DIR} ${WORK_DIR} prefix)
talus_run(${CMAKE_COMMAND} -S ${EXAMPLES_SOURCE_DIR} -B ${WORK_DIR}/build -DCMAKE_PREFIX_PATH=${prefix}
    -DCMAKE_BUILD_TYPE=Release "-DCMAKE_C_FLAGS=${EXAMPLES_C_FLAGS}" -DEXAMPLES_WERROR=${EXAMPLES_WERROR})
talus_run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
talus_run(${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${prefix}/lib OMP_NUM_THREADS=1
    ${CMAKE_CTEST_COMMAND} --test-dir ${WORK_DIR}/build --output-on-failure -V)
