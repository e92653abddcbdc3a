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

# Reads the key=value pairs of the "summary:" line of a driver's output out
# into ${prefix}<key> in the caller's scope, and the list of keys into
# ${prefix}__keys; a missing summary line is fatal (what names the run in
# the message).
function(talus_read_summary out prefix what)
  string(REGEX MATCH "summary:[^\n]*" summary "${out}")
  if(summary STREQUAL "")
    message(FATAL_ERROR "${what}: no summary line in the driver's output")
  endif()
  string(REGEX MATCHALL "[A-Za-z_][A-Za-z0-9_]*=[^ \n]+" pairs "${summary}")
  set(keys "")
  foreach(p IN LISTS pairs)
    string(REGEX REPLACE "=.*" "" k "${p}")
    string(REGEX REPLACE "^[^=]*=" "" v "${p}")
    set(${prefix}${k} "${v}" PARENT_SCOPE)
    list(APPEND keys ${k})
  endforeach()
  set(${prefix}__keys "${keys}" PARENT_SCOPE)
endfunction()

# Checks the awk conditions of the list conditions ("n_small + n_large == n")
# on the summaries read by talus_read_summary under each prefix of the list
# prefixes; in awk a value ${prefix}<key> is named so without a leading
# "val_" and with its dots made underscores (val_A_E and val_A.E are A_E).  A condition that does not hold sets `failed` in
# the caller's scope.
function(talus_check_invariants prefixes conditions awk)
  set(vars "")
  foreach(p IN LISTS prefixes)
    foreach(k IN LISTS ${p}__keys)
      if("${${p}${k}}" MATCHES "${number_re}")
        string(REGEX REPLACE "^val_" "" name "${p}${k}")
        string(REPLACE "." "_" name "${name}")
        list(APPEND vars -v "${name}=${${p}${k}}")
      endif()
    endforeach()
  endforeach()
  foreach(cond IN LISTS conditions)
    execute_process(COMMAND ${awk} ${vars} "BEGIN { exit !(${cond}) }" RESULT_VARIABLE bad)
    if(bad EQUAL 0)
      message("  invariant ${cond}: holds")
    else()
      message(SEND_ERROR "  invariant ${cond}: violated")
      set(failed 1 PARENT_SCOPE)
    endif()
  endforeach()
endfunction()

# Writes baseline from this run: header (the comment lines, each ending in a
# newline), then "key value rel_tol abs_tol" for each "key rel abs" of the
# list tolerances, value ${prefix}<key> of the caller.
function(talus_write_baseline baseline header prefix tolerances)
  set(text "${header}")
  foreach(line IN LISTS tolerances)
    string(REPLACE " " ";" f "${line}")
    list(GET f 0 k)
    list(GET f 1 rt)
    list(GET f 2 at)
    string(APPEND text "${k} ${${prefix}${k}} ${rt} ${at}\n")
  endforeach()
  file(WRITE ${baseline} "${text}")
  message("wrote ${baseline}")
endfunction()

# Checks each line "key value rel_tol abs_tol" of baseline against the
# caller's ${prefix}<key> with talus_check_value; a missing or empty baseline
# is fatal, a value off its baseline sets `failed` in the caller's scope.
function(talus_check_baseline baseline prefix awk)
  if(NOT EXISTS ${baseline})
    message(FATAL_ERROR "regression baseline ${baseline} is missing")
  endif()
  file(STRINGS ${baseline} lines REGEX "^[^#]")
  list(LENGTH lines n)
  if(n EQUAL 0)
    message(FATAL_ERROR "regression baseline ${baseline} is empty")
  endif()
  foreach(line IN LISTS lines)
    string(REGEX REPLACE " +" ";" f "${line}")
    list(GET f 0 k)
    list(GET f 1 ref)
    list(GET f 2 rt)
    list(GET f 3 at)
    talus_check_value(${prefix}${k} "${${prefix}${k}}" ${ref} ${rt} ${at} ${awk})
  endforeach()
  if(failed)
    set(failed 1 PARENT_SCOPE)
  endif()
endfunction()
