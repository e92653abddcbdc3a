# Installs the built Talus into a scratch prefix, then builds and runs an
# outside program against it twice: through find_package(Talus) and through
# pkg-config.  Arguments: TALUS_OUT_OF_TREE (the path of
# cmake/TalusOutOfTree.cmake), TALUS_BINARY_DIR, CONSUMER_SOURCE_DIR, WORK_DIR.
include(${TALUS_OUT_OF_TREE})
talus_install_scratch(${TALUS_BINARY_DIR} ${WORK_DIR} prefix)

# find_package
talus_run(${CMAKE_COMMAND} -S ${CONSUMER_SOURCE_DIR} -B ${WORK_DIR}/cmake-build -DCMAKE_PREFIX_PATH=${prefix})
talus_run(${CMAKE_COMMAND} --build ${WORK_DIR}/cmake-build)
talus_run(${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${prefix}/lib ${WORK_DIR}/cmake-build/consumer -radius 0.25)

# pkg-config
find_program(PKG_CONFIG pkg-config REQUIRED)
find_program(CC NAMES cc gcc REQUIRED)
set(ENV{PKG_CONFIG_PATH} ${prefix}/lib/pkgconfig)
execute_process(COMMAND ${PKG_CONFIG} --cflags --libs talus OUTPUT_VARIABLE flags RESULT_VARIABLE rc
                OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "pkg-config does not find talus in ${prefix}/lib/pkgconfig")
endif()
separate_arguments(flags UNIX_COMMAND "${flags}")
talus_run(${CC} ${CONSUMER_SOURCE_DIR}/consumer.c -o ${WORK_DIR}/consumer-pc ${flags})
talus_run(${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${prefix}/lib ${WORK_DIR}/consumer-pc -radius 0.25)
