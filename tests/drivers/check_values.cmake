# Value checks of the driver checkers, in the positive style: a value passes
# only when it is present, a finite number and inside its range, so a null
# (summary.json's NaN or infinity), an empty string or a missing member fails.
# (CMake's comparisons are all false on a non-number, so "fail when outside"
# would let those through.)

# lem_require_number(<what> <value> <min> <max>): <value> is a decimal number
# with min <= value <= max.
function(lem_require_number what value min max)
  if(NOT value MATCHES "^[-+]?([0-9]+\\.?[0-9]*|\\.[0-9]+)([eE][-+]?[0-9]+)?$")
    message(FATAL_ERROR "${what} is not a finite number: '${value}'")
  endif()
  if(NOT (value GREATER_EQUAL min AND value LESS_EQUAL max))
    message(FATAL_ERROR "${what} = ${value} is outside its range [${min}, ${max}]")
  endif()
endfunction()

# lem_summary_number(<var> <json text> <member> <min> <max> [<file>]): reads a
# member of a summary, requires it to be a number in [min, max] and stores it
# in <var>.
function(lem_summary_number out json member min max)
  set(where "summary.json")
  if(ARGC GREATER 5)
    set(where "${ARGV5}")
  endif()
  string(JSON type ERROR_VARIABLE missing TYPE "${json}" ${member})
  if(missing)
    message(FATAL_ERROR "${where} has no member ${member}")
  endif()
  string(JSON value GET "${json}" ${member})
  if(type STREQUAL "NULL")
    message(FATAL_ERROR "${where}: ${member} is null (a NaN or an infinity when written)")
  elseif(NOT type STREQUAL "NUMBER")
    message(FATAL_ERROR "${where}: ${member} is ${type} '${value}', not a finite number")
  endif()
  lem_require_number("${where}: ${member}" "${value}" ${min} ${max})
  set(${out} "${value}" PARENT_SCOPE)
endfunction()
