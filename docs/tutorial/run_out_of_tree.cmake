# The tutorial as its README tells a newcomer to build it: against the
# INSTALLED library, through find_package(Talus) and through pkg-config.
# Installs the built Talus into a scratch prefix, builds and runs tutorial 1
# and the C++ header check both ways.  Arguments: TALUS_OUT_OF_TREE,
# TALUS_BINARY_DIR, TUTORIAL_SOURCE_DIR, WORK_DIR.
include(${TALUS_OUT_OF_TREE})
talus_install_scratch(${TALUS_BINARY_DIR} ${WORK_DIR} prefix)

# find_package
talus_run(${CMAKE_COMMAND} -S ${TUTORIAL_SOURCE_DIR} -B ${WORK_DIR}/build -DCMAKE_PREFIX_PATH=${prefix})
talus_run(${CMAKE_COMMAND} --build ${WORK_DIR}/build --target tutorial_collision tutorial_header_cxx)
talus_run(${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${prefix}/lib ${WORK_DIR}/build/tutorial_collision ${WORK_DIR}/out)
talus_run(${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${prefix}/lib ${WORK_DIR}/build/tutorial_header_cxx)

# pkg-config (talus.pc carries -lm: talus.h's inline vector functions call libm)
find_program(PKG_CONFIG pkg-config REQUIRED)
find_program(CC NAMES cc gcc REQUIRED)
set(ENV{PKG_CONFIG_PATH} ${prefix}/lib/pkgconfig)
execute_process(COMMAND ${PKG_CONFIG} --cflags --libs talus OUTPUT_VARIABLE flags RESULT_VARIABLE rc
                OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "pkg-config does not find talus in ${prefix}/lib/pkgconfig")
endif()
separate_arguments(flags UNIX_COMMAND "${flags}")
talus_run(${CC} ${TUTORIAL_SOURCE_DIR}/01_collision.c -o ${WORK_DIR}/collision-pc ${flags})
talus_run(${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${prefix}/lib ${WORK_DIR}/collision-pc ${WORK_DIR}/out-pc)
