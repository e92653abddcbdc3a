# Static linking through pkg-config: install into a scratch prefix, build
# UnitTests/consumer/consumer.c with `pkg-config --cflags --libs talus-static`
# and pass when the program carries no libtalus.so (readelf's NEEDED list)
# and runs without LD_LIBRARY_PATH.  (`pkg-config --static talus` linked
# libtalus.so: -ltalus picks the shared library beside the archive whatever
# --static says; the check of that behaviour is the NEEDED list below.)
include(${TALUS_OUT_OF_TREE})
talus_install_scratch(${TALUS_BINARY_DIR} ${WORK_DIR} prefix)
find_program(PKG_CONFIG pkg-config REQUIRED)
find_program(CC NAMES cc gcc REQUIRED)
find_program(READELF readelf REQUIRED)
set(ENV{PKG_CONFIG_PATH} ${prefix}/lib/pkgconfig)
execute_process(COMMAND ${PKG_CONFIG} --cflags --libs talus-static OUTPUT_VARIABLE flags RESULT_VARIABLE rc
                OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "pkg-config does not find talus-static in ${prefix}/lib/pkgconfig")
endif()
message("pkg-config --cflags --libs talus-static: ${flags}")
separate_arguments(flags UNIX_COMMAND "${flags}")
talus_run(${CC} ${CONSUMER_SOURCE_DIR}/consumer.c -o ${WORK_DIR}/consumer-static ${flags})
execute_process(COMMAND ${READELF} -d ${WORK_DIR}/consumer-static OUTPUT_VARIABLE dyn)
if(dyn MATCHES "libtalus\\.so")
  message(FATAL_ERROR "the program linked through talus-static needs libtalus.so:\n${dyn}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=LD_LIBRARY_PATH ${WORK_DIR}/consumer-static -radius 0.25
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the statically linked program failed (exit ${rc}):\n${out}${err}")
endif()
message("linked without libtalus.so and ran: ${out}")
