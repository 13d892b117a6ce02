# The same run on 1 and on 2 ranks must give the same E_eff to 1e-6
# (relative): the partition changes only the order of the sums and the
# multigrid hierarchy, not the solution beyond the solver tolerance.
#   -DRUN1="mpiexec -n 1 prog" -DRUN2="mpiexec -n 2 prog" -DARGS="..." -DDIR=<dir>
include(${CMAKE_CURRENT_LIST_DIR}/check_values.cmake)
separate_arguments(ARGS UNIX_COMMAND "${ARGS}")
foreach(n 1 2)
  separate_arguments(run UNIX_COMMAND "${RUN${n}}")
  file(REMOVE_RECURSE ${DIR}/np${n})
  execute_process(COMMAND ${run} ${ARGS} -output_fields false -output_dir ${DIR}/np${n}
                  RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "run on ${n} rank(s) failed (${status}):\n${out}\n${err}")
  endif()
  file(READ ${DIR}/np${n}/summary.json json)
  # Present, finite and positive (tests/drivers/check_values.cmake).
  lem_summary_number(e${n} "${json}" E_eff 1e-300 1e300 np${n}/summary.json)
endforeach()
# CMake has no floating-point arithmetic: let awk compare.
execute_process(COMMAND awk "BEGIN { d = (${e1} - ${e2}) / ${e1}; if (d < 0) d = -d; print d; exit !(d <= 1e-6) }"
                RESULT_VARIABLE differs OUTPUT_VARIABLE rel OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT differs EQUAL 0)
  message(FATAL_ERROR "E_eff differs between 1 rank (${e1}) and 2 ranks (${e2}): relative ${rel}")
endif()
message(STATUS "E_eff 1 rank ${e1}, 2 ranks ${e2}, relative difference ${rel}")
