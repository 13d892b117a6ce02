# lem_stiffness on a small sample (27 particles, 4·10⁴ bonds) at 2 ranks,
# six of the paper's eight matrix fractions (0.06 ... 0.28).  Checks
# the files and the physics the paper reports (sect. 3, figs. 5, 11; app. D):
#   - the matrix is calibrated (rho^m within 1 % of the request) and the node
#     volume fractions sum to 1; particles and contacts do not change with
#     rho^m (same p and pp bonds, same rho^p), matrix bonds grow, void bonds
#     shrink, the bond count is constant;
#   - E_eff grows with rho^m, adhesive contacts are stiffer than bare ones,
#     both stay below E^[p] and below the appendix-D adhesive estimate (with
#     C^0 = C^[p] it is the Hashin-Shtrikman upper bound);
#   - E_eff is linear in rho^m: largest fit residual < 4.5 % of the rise
#     (3.8 % bare, 2.5 % adhesive at this revision; on these six fractions
#     E ~ rho^2, sqrt(rho), rho^1.5, log(rho) give 9.0, 5.8, 5.0, 12 %, so
#     only a clearly curved law is caught, not a slight curvature); the
#     bare-contact line passes near 0 at rho^m = 0 (|intercept| <= 0.03 E^[p])
#     while adhesive contacts keep a stiff contact network there (intercept
#     >= 0.05 E^[p]);
#   - S^pm/S^p grows with rho^m and stays below 1; 0 < nu < 0.5.
#   -DRUN="mpiexec ... lem_stiffness" -DDIR=<output dir> [-DARGS="<extra options>"]
file(REMOVE_RECURSE ${DIR})
separate_arguments(RUN UNIX_COMMAND "${RUN}")
separate_arguments(ARGS UNIX_COMMAND "${ARGS}")
execute_process(COMMAND ${RUN} -sample_particles 27 -pack_particles 100 -lattice_bonds 40000
                        -stiffness_fractions 0.06,0.1,0.13,0.17,0.22,0.28 -output_dir ${DIR}
                        ${ARGS}
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "lem_stiffness failed (${status}):\n${out}\n${err}")
endif()
foreach(f stiffness.csv fits.csv summary.json)
  if(NOT EXISTS ${DIR}/${f})
    message(FATAL_ERROR "missing result file ${DIR}/${f}")
  endif()
endforeach()

# CMake compares decimals but computes with integers only: the arithmetic
# below is in micro-units (x 10^6, truncated).
function(to_micro out value)
  if(value MATCHES "^-?[0-9.]+[eE]-[0-9]+$")  # %g prints |x| < 1e-4 so
    set(${out} 0 PARENT_SCOPE)
    return()
  endif()
  if(NOT value MATCHES "^(-?)([0-9]*)\\.?([0-9]*)$")
    message(FATAL_ERROR "not a number: '${value}'")
  endif()
  set(sign "${CMAKE_MATCH_1}")
  set(int "${CMAKE_MATCH_2}")
  string(SUBSTRING "${CMAKE_MATCH_3}000000" 0 6 frac)
  if(int STREQUAL "")
    set(int 0)
  endif()
  math(EXPR v "${sign}(${int} * 1000000 + ${frac})")
  set(${out} ${v} PARENT_SCOPE)
endfunction()
function(check condition_text)
  if(NOT (${ARGN}))
    message(FATAL_ERROR "${condition_text}\n${out}")
  endif()
endfunction()

file(STRINGS ${DIR}/stiffness.csv lines REGEX "^[0-9]")
list(LENGTH lines rows)
check("expected 6 rows in stiffness.csv, found ${rows}" rows EQUAL 6)
set(first TRUE)
foreach(line ${lines})
  string(REPLACE "," ";" v "${line}")
  list(GET v 0 req)
  list(GET v 1 rho)
  list(GET v 2 rho_p)
  list(GET v 3 rho_v)
  list(GET v 5 cover)
  list(GET v 6 bridges)
  list(GET v 7 eligible)
  list(GET v 8 n_p)
  list(GET v 9 n_m)
  list(GET v 10 n_v)
  list(GET v 11 n_pp)
  list(GET v 12 n_pm)
  list(GET v 13 bare)
  list(GET v 14 adhesive)
  list(GET v 15 hs_bare)
  list(GET v 16 hs_adhesive)
  list(GET v 17 nu_bare)
  list(GET v 18 nu_adhesive)
  message(STATUS "rho_m=${rho} E_bare=${bare} E_adhesive=${adhesive} HS=${hs_bare},${hs_adhesive} "
                 "S_pm=${cover} bridges/particle=${bridges}")
  foreach(x req rho rho_p rho_v)
    to_micro(${x}_u ${${x}})
  endforeach()
  math(EXPR miss "${rho_u} - ${req_u}")
  math(EXPR sum "${rho_p_u} + ${rho_u} + ${rho_v_u} - 1000000")
  math(EXPR total "${n_p} + ${n_m} + ${n_v} + ${n_pp} + ${n_pm}")
  math(EXPR tol "${req_u} / 100")
  math(EXPR neg_tol "-${tol}")
  check("rho_m = ${rho} misses the requested ${req} by more than 1 %"
        miss LESS tol AND miss GREATER neg_tol)
  check("rho_p + rho_m + rho_v = 1 + ${sum}e-6" sum GREATER -4 AND sum LESS 4)
  check("bridges holding matrix (${bridges}) exceed the eligible pairs (${eligible}) per particle"
        bridges GREATER_EQUAL 0 AND bridges LESS_EQUAL eligible)
  check("E_adhesive=${adhesive} not above E_bare=${bare}, or not below E^[p]"
        adhesive GREATER bare AND adhesive LESS 1 AND bare GREATER 0)
  check("E_adhesive=${adhesive} above its HS upper bound ${hs_adhesive}"
        adhesive LESS hs_adhesive)
  check("appendix-D estimates ${hs_bare} (bare), ${hs_adhesive} (adhesive) not ordered in (0, 1)"
        hs_bare GREATER 0 AND hs_bare LESS hs_adhesive AND hs_adhesive LESS 1)
  check("S_pm/S_p = ${cover} not in (0, 1)" cover GREATER 0 AND cover LESS 1)
  check("Poisson ratios ${nu_bare}, ${nu_adhesive} not in (0, 0.5)"
        nu_bare GREATER 0 AND nu_bare LESS 0.5 AND nu_adhesive GREATER 0 AND nu_adhesive LESS 0.5)
  if(NOT first)
    set(msg "particles or contacts changed with rho_m: p ${last_n_p} -> ${n_p}, pp ")
    string(APPEND msg "${last_n_pp} -> ${n_pp}, rho_p ${last_rho_p} -> ${rho_p}, bonds ")
    string(APPEND msg "${last_total} -> ${total}")
    check("${msg}" n_p EQUAL last_n_p AND n_pp EQUAL last_n_pp AND rho_p STREQUAL last_rho_p
          AND total EQUAL last_total)
    set(msg "matrix bonds (${last_n_m} -> ${n_m}) must grow and void bonds ")
    string(APPEND msg "(${last_n_v} -> ${n_v}) shrink with rho_m")
    check("${msg}" n_m GREATER last_n_m AND n_v LESS last_n_v)
    set(msg "not increasing with rho_m: E_bare ${last_bare} -> ${bare}, E_adhesive ")
    string(APPEND msg "${last_adhesive} -> ${adhesive}, HS ${last_hs_bare} -> ${hs_bare}, ")
    string(APPEND msg "${last_hs_adhesive} -> ${hs_adhesive}, S_pm ${last_cover} -> ${cover}")
    check("${msg}"
          bare GREATER last_bare AND adhesive GREATER last_adhesive AND hs_bare GREATER last_hs_bare
          AND hs_adhesive GREATER last_hs_adhesive AND cover GREATER last_cover)
  else()
    set(bare_first ${bare})
    set(adhesive_first ${adhesive})
  endif()
  foreach(x n_p n_pp n_m n_v total rho_p bare adhesive hs_bare hs_adhesive cover)
    set(last_${x} ${${x}})
  endforeach()
  set(first FALSE)
endforeach()

# Linear fits: quantity,intercept,slope,max_residual.
file(STRINGS ${DIR}/fits.csv fits REGEX "^E_")
foreach(line ${fits})
  string(REPLACE "," ";" v "${line}")
  list(GET v 0 name)
  list(GET v 1 intercept)
  list(GET v 2 slope)
  list(GET v 3 residual)
  if(name STREQUAL "E_bare_over_Ep")
    set(lo ${bare_first})
    set(hi ${last_bare})
  else()
    set(lo ${adhesive_first})
    set(hi ${last_adhesive})
  endif()
  to_micro(lo_u ${lo})
  to_micro(hi_u ${hi})
  to_micro(res_u ${residual})
  math(EXPR rise "${hi_u} - ${lo_u}")
  math(EXPR res_permille "1000 * ${res_u}")
  math(EXPR limit "45 * ${rise}")
  math(EXPR permille "1000 * ${res_u} / ${rise}")
  math(EXPR pct_int "${permille} / 10")
  math(EXPR pct_dec "${permille} % 10")
  message(STATUS "${name}: ${intercept} + ${slope} rho_m, largest residual ${residual} "
                 "(${pct_int}.${pct_dec} % of the rise)")
  check("${name} is not linear in rho_m: residual ${residual} > 4.5 % of the rise ${lo} -> ${hi}"
        res_permille LESS limit AND slope GREATER 0)
  if(name STREQUAL "E_bare_over_Ep")
    check("bare contacts: E_eff does not vanish with rho_m (intercept ${intercept})"
          intercept GREATER -0.03 AND intercept LESS 0.03)
  else()
    check("adhesive contacts: no stiffness left at rho_m = 0 (intercept ${intercept})"
          intercept GREATER 0.05)
  endif()
endforeach()
list(LENGTH fits nfits)
check("fits.csv should hold the two E_eff fits, found ${nfits}" nfits EQUAL 2)
