# Shared by the cmake -P scripts of the tests that build an outside project
# against the INSTALLED library (UnitTests/consumer/run_consumer.cmake,
# Examples/run_examples.cmake): include()d by them, never installed.

# Runs a command; stops the script with its output when it fails.
function(talus_run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  message(STATUS "${out}")
endfunction()

# Empties work_dir and installs the Talus built in binary_dir into the
# scratch prefix work_dir/prefix, whose path it sets in prefix_var.
function(talus_install_scratch binary_dir work_dir prefix_var)
  file(REMOVE_RECURSE ${work_dir})
  talus_run(${CMAKE_COMMAND} --install ${binary_dir} --prefix ${work_dir}/prefix)
  set(${prefix_var} ${work_dir}/prefix PARENT_SCOPE)
endfunction()
