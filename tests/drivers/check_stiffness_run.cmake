# lem_stiffness on a small sample at 2 ranks: the table has one row per
# fraction, and the physics the paper reports holds (sect. 3, figs. 5, 11):
# E_eff grows with rho^m, adhesive contacts are stiffer than bare ones, both
# stay below E^[p], the interface area grows, and the appendix-D estimates
# lie between 0 and E^[p].
#   -DRUN="mpiexec ... lem_stiffness" -DDIR=<output dir>
file(REMOVE_RECURSE ${DIR})
separate_arguments(RUN UNIX_COMMAND "${RUN}")
execute_process(COMMAND ${RUN} -sample_particles 27 -pack_particles 100 -lattice_bonds 40000
                        -stiffness_fractions 0.08,0.16,0.24 -output_dir ${DIR}
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "lem_stiffness failed (${status}):\n${out}\n${err}")
endif()
foreach(f stiffness.csv fits.csv summary.json)
  if(NOT EXISTS ${DIR}/${f})
    message(FATAL_ERROR "missing result file ${DIR}/${f}")
  endif()
endforeach()
file(STRINGS ${DIR}/stiffness.csv lines REGEX "^[0-9]")
list(LENGTH lines rows)
if(NOT rows EQUAL 3)
  message(FATAL_ERROR "expected 3 rows in stiffness.csv, found ${rows}")
endif()
set(last_bare 0)
set(last_cover 0)
foreach(line ${lines})
  string(REPLACE "," ";" v "${line}")
  list(GET v 1 rho)
  list(GET v 5 cover)
  list(GET v 13 bare)
  list(GET v 14 adhesive)
  list(GET v 15 hs_bare)
  list(GET v 16 hs_adhesive)
  if(NOT (bare GREATER last_bare AND adhesive GREATER bare AND adhesive LESS 1 AND
          cover GREATER last_cover AND hs_bare GREATER 0 AND hs_adhesive LESS 1))
    message(FATAL_ERROR "implausible row: rho_m=${rho} S_pm=${cover} E_bare=${bare} "
                        "E_adhesive=${adhesive} HS=${hs_bare},${hs_adhesive}\n${out}")
  endif()
  set(last_bare ${bare})
  set(last_cover ${cover})
  message(STATUS "rho_m=${rho} E_bare=${bare} E_adhesive=${adhesive} S_pm=${cover}")
endforeach()
