# Shared by the self-tests' check scripts: a value printed by a driver
# against its baseline.  CMake has no floating point, so awk evaluates
# |x - ref| <= at + rt |ref|; a value that is not a finite number (nan, inf,
# a word) fails before it reaches awk, where it would read as 0.
set(number_re "^[-+]?([0-9]+[.]?[0-9]*|[.][0-9]+)([eE][-+]?[0-9]+)?$")

# Sets `failed` in the caller's scope when key's value x is not a number or
# is off the baseline ref by more than at + rt |ref|.
function(talus_check_value key x ref rt at awk)
  if(NOT x MATCHES "${number_re}")
    message(SEND_ERROR "  ${key} = '${x}' is not a finite number")
    set(failed 1 PARENT_SCOPE)
    return()
  endif()
  execute_process(COMMAND ${awk} "BEGIN { d = ${x} - (${ref}); if (d < 0) d = -d; r = (${ref}); if (r < 0) r = -r; exit !(d <= ${at} + ${rt} * r) }"
                  RESULT_VARIABLE bad)
  if(bad EQUAL 0)
    message("  ${key}: ${x} (baseline ${ref}, tolerance ${at} + ${rt} |ref|) ok")
  else()
    message(SEND_ERROR "  ${key}: ${x} differs from the baseline ${ref} beyond ${at} + ${rt} |ref|")
    set(failed 1 PARENT_SCOPE)
  endif()
endfunction()
