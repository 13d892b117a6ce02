# lem_sample builds a small sample and writes the sample file, its XDMF and
# the summaries; lem_tension (2 ranks) then runs on that file.
#   -DSAMPLE="mpiexec -n 1 lem_sample" -DTENSION="mpiexec -n 2 lem_tension" -DDIR=<dir>
#   [-DSAMPLE_ARGS=... -DTENSION_ARGS=...] (more options of each)
# Each value read must be present, finite and in its range
# (tests/drivers/check_values.cmake).
include(${CMAKE_CURRENT_LIST_DIR}/check_values.cmake)
file(REMOVE_RECURSE ${DIR})
separate_arguments(SAMPLE UNIX_COMMAND "${SAMPLE} ${SAMPLE_ARGS}")
separate_arguments(TENSION UNIX_COMMAND "${TENSION} ${TENSION_ARGS}")
execute_process(COMMAND ${SAMPLE} -sample_particles 20 -lattice_bonds 20000 -pack_seed 2
                        -matrix_fraction 0.1 -output_dir ${DIR}/sample
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "lem_sample failed (${status}):\n${out}\n${err}")
endif()
foreach(f sample.h5 sample.xmf summary.json summary.csv)
  if(NOT EXISTS ${DIR}/sample/${f})
    message(FATAL_ERROR "missing result file ${DIR}/sample/${f}")
  endif()
endforeach()
file(READ ${DIR}/sample/summary.json json)
# The calibration is limited by single nodes on so small a lattice.
lem_summary_number(rho_m "${json}" rho_m 0.098 0.102 sample/summary.json)
lem_summary_number(bonds "${json}" bonds 15000 25000 sample/summary.json)
execute_process(COMMAND ${TENSION} -sample_file ${DIR}/sample/sample.h5 -phase_E_p 2
                        -output_dir ${DIR}/tension
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "lem_tension on the new sample failed (${status}):\n${out}\n${err}")
endif()
file(READ ${DIR}/tension/summary.json json)
# A matrix fraction of 0.1 with adhesive contacts: E_eff is a large part of
# E^[p] = 2 (0.76 measured), and below it.
lem_summary_number(ep "${json}" E_eff_over_E_p 0.5 0.95 tension/summary.json)
lem_summary_number(e "${json}" E_eff 1.0 1.9 tension/summary.json)
message(STATUS "sample rho_m=${rho_m}, ${bonds} bonds; E_eff=${e}, E_eff/E^p=${ep}")
