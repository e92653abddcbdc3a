# docs/catalogue.md must be the catalogue program's output: run it into the
# build tree and compare (CATALOGUE, EXPECTED, OUTPUT).
execute_process(COMMAND ${CATALOGUE} -format markdown -output ${OUTPUT} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "talus_catalogue failed (exit ${rc})")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${EXPECTED} ${OUTPUT} RESULT_VARIABLE differs)
if(differs)
  message(FATAL_ERROR "docs/catalogue.md is stale: it differs from the registries' catalogue (${OUTPUT}). "
          "Regenerate it with: build/bin/talus_catalogue -output docs/catalogue.md")
endif()
message(STATUS "docs/catalogue.md matches the registries")
