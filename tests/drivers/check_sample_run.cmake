# lem_sample builds a small sample and writes the sample file, its XDMF and
# the summaries; lem_tension (2 ranks) then runs on that file.
#   -DSAMPLE="mpiexec -n 1 lem_sample" -DTENSION="mpiexec -n 2 lem_tension" -DDIR=<dir>
#   [-DSAMPLE_ARGS=... -DTENSION_ARGS=...] (more options of each)
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
string(JSON rho_m GET ${json} rho_m)
string(JSON bonds GET ${json} bonds)
# The calibration is limited by single nodes on so small a lattice.
if(rho_m LESS 0.098 OR rho_m GREATER 0.102 OR bonds LESS 15000)
  message(FATAL_ERROR "implausible sample: rho_m=${rho_m} bonds=${bonds}")
endif()
execute_process(COMMAND ${TENSION} -sample_file ${DIR}/sample/sample.h5 -phase_E_p 2
                        -output_dir ${DIR}/tension
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "lem_tension on the new sample failed (${status}):\n${out}\n${err}")
endif()
file(READ ${DIR}/tension/summary.json json)
string(JSON e GET ${json} E_eff)
string(JSON ep GET ${json} E_eff_over_E_p)
message(STATUS "sample rho_m=${rho_m}, ${bonds} bonds; E_eff=${e}, E_eff/E^p=${ep}")
