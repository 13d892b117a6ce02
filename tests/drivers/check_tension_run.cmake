# A small elastic tension run at 2 ranks must finish and write every result
# file, with E and nu in the summary.
#   -DRUN="mpiexec ... lem_tension" -DDIR=<output dir>
#   optional: -DARGS="<sample options>" (default a 3000-node random lattice),
#   plausible ranges -DE_MIN/-DE_MAX/-DNU_MIN/-DNU_MAX; each value must be
#   present and finite (tests/drivers/check_values.cmake).
include(${CMAKE_CURRENT_LIST_DIR}/check_values.cmake)
foreach(v "ARGS;-lattice_nodes 3000" "E_MIN;1.0" "E_MAX;4.0" "NU_MIN;0.1" "NU_MAX;0.35")
  list(GET v 0 name)
  list(GET v 1 default)
  if(NOT DEFINED ${name})
    set(${name} "${default}")
  endif()
endforeach()
file(REMOVE_RECURSE ${DIR})
separate_arguments(RUN UNIX_COMMAND "${RUN}")
separate_arguments(ARGS UNIX_COMMAND "${ARGS}")
execute_process(COMMAND ${RUN} ${ARGS} -output_dir ${DIR}
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "lem_tension failed (${status}):\n${out}\n${err}")
endif()
foreach(f summary.json summary.csv fields.h5 fields.xmf)
  if(NOT EXISTS ${DIR}/${f})
    message(FATAL_ERROR "missing result file ${DIR}/${f}")
  endif()
endforeach()
file(READ ${DIR}/summary.json json)
lem_summary_number(e "${json}" E_eff ${E_MIN} ${E_MAX})
lem_summary_number(nu "${json}" nu ${NU_MIN} ${NU_MAX})
lem_summary_number(gap "${json}" energy_relative_gap 0 1e-6)
message(STATUS "E_eff=${e} nu=${nu} energy gap=${gap}")
