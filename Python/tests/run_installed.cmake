# Installs the build into a scratch prefix and uses the Python package from
# there, with the library the install recorded (no TALUS_LIBRARY).
#   -DBINARY_DIR= -DWORK_DIR= -DPYTHON= -DPYDIR=(relative site dir) -DCHECK=(script)
file(REMOVE_RECURSE ${WORK_DIR})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BINARY_DIR} --prefix ${WORK_DIR}/prefix
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(rc)
  message(FATAL_ERROR "install into ${WORK_DIR}/prefix failed: ${rc}")
endif()
set(ENV{PYTHONPATH} ${WORK_DIR}/prefix/${PYDIR})
unset(ENV{TALUS_LIBRARY})
execute_process(COMMAND ${PYTHON} ${CHECK} ${WORK_DIR}/prefix WORKING_DIRECTORY ${WORK_DIR} RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "the installed package failed its check (${rc})")
endif()
