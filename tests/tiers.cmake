# Test tiers and groups (docs/developer/testing.md, "Tiers").  Every test gets one
# tier label, `quick` or `long`, and one group label from its name.
#   quick  what `bash jobs/test.sh` runs after every change: every module and
#          every promise in at least one test, in a few minutes
#   long   the rest: the same promises on larger samples, every stop point,
#          every kill point; `bash jobs/test.sh --all` and CI run both tiers
# lem_label_tests() labels the tests of the directory it is called in (a
# test's properties can only be set there), so both CMakeLists.txt call it
# after their last add_test.

# Tests of the long tier: each costs ten seconds or more on an idle machine,
# and a quick test covers its promise on a smaller case (named after '#').
set(LEM_LONG_TESTS
  fracture_deflation              # test_particle_deflation_np2
  fracture_restart_sample_particle_deflation # test_particle_deflation_np2, fracture_restart_kill (3 runs of the mini sample)
  test_particle_deflation_np1     # test_particle_deflation_np2 (1 and 2 ranks in one test)
  test_elastic_np1                # test_elastic_np2 (compares with a serial reference itself)
  test_fracture_system_np1        # test_fracture_system_np2
  fracture_node_stress            # test_elastic_np2 (node stresses, eq. 1), results_readers
  fracture_bad_checkpoint         # bad_checkpoint_crafted
  fracture_restart_ranks_reference # fracture_restart_ranks, fracture_restart_kill_reference
  fracture_restart_kill_assembled # fracture_operators, fracture_ranks_assembled, fracture_restart_kill
  fracture_restart_ranks_assembled # fracture_operators, fracture_ranks_assembled, fracture_restart_ranks
  fracture_fidelity_tiny          # fracture_fidelity_mini
  fracture_restart_learnt_ritz    # test_checkpoint_file_np2 (the learnt columns kept), test_ritz_deflation_np2, fracture_ranks_ritz
  fracture_fidelity_mini_double_cycle # test_single_cycle_np2, fracture_ranks_double_cycle
  fracture_ranks_mini_double_cycle # test_single_cycle_np2, fracture_ranks_double_cycle
  fracture_decided_closing        # FractureParts.DecidedBatch*, SolveStoppedOnceDecided* (the certificate), fracture_fidelity_mini
  fracture_gold_main              # fracture_fidelity_mini, fracture_ranks_reference (1 rank: fracture_ranks)
  fracture_gold_main_np2          # fracture_fidelity_mini (the main job as run, against the same gold), fracture_ranks_reference
  fracture_gold_main_direct_tail  # test_direct_tail_np2 (the route's solves equal the multigrid's)
  fracture_reference_direct_tail  # test_direct_tail_np2
  fracture_ranks_mini             # fracture_ranks, fracture_fidelity_mini
  fracture_ranks_mini_reference   # fracture_ranks_reference
  fracture_ranks_sample_tiny      # fracture_certificate
  fracture_ranks_sample_mini      # fracture_certificate, fracture_ranks_mini
  fracture_damage_aggregates      # bad_input_damage_aggregates_wrapped (the option reaches GAMG; the split shows only after damage, 3 runs of the mini sample)
  fracture_no_whole_gathers       # test_checkpoint_file_np2, fracture_restart_ranks
  fracture_parallel_setup         # test_parallel_setup_np2, _np3
  fracture_spec_mini_parallel     # fracture_spec_mini, test_parallel_setup_np2 (ids and a of both set-ups)
  outputs_commit_kill             # fracture_restart_kill, outputs_keep_finished
  outputs_disk_full_sizes         # outputs_disk_full, outputs_disk_full_overwrite
  outputs_spectrum_probe_full_disk  # outputs_disk_full_sizes (a full disk, here in a diagnostic)
  outputs_overwrite_kill          # outputs_keep_finished, outputs_rerun
  outputs_overwrite_kill_renames  # outputs_keep_finished, outputs_rerun
  outputs_overwrite_stale         # outputs_concurrent
  signal_reference                # fracture_restart_signal (the fixture of the signal_* tests)
  signal_calibration              # fracture_restart_signal
  signal_calibration_kill         # fracture_restart_kill (kill -9, resumed), fracture_calibration_reuse
  signal_after_calibration        # fracture_restart_signal
  signal_avalanche                # fracture_restart_signal
  signal_final_writes             # fracture_restart_signal
  signal_mpirun_term              # fracture_restart_signal, ranks_error_*
  signal_anytime                  # fracture_restart_signal
  fracture_warnings_mini          # fracture_warnings_default, _coarse
  study_bad_input                 # tests/python/test_study.py (study files refused)
  study_data_resume               # tests/python/test_study_data.py (resumed from the data)
  fracture_identity               # Checkpoint.FingerprintDifferences*, fracture_calibration_reuse
)

# The bad_input group is long but for this sample: each driver, each class
# of bad value, each kind of damaged file and each way a rank ends the job
# once in the quick tier.  A new bad_input test is long until it is named here.
set(LEM_QUICK_BAD_INPUTS
  bad_input_negative_nodes bad_input_misspelt_option bad_input_unused_petsc_option
  bad_input_bad_choice bad_input_unwritable_output bad_input_sample_file_missing
  bad_input_sample_file_not_hdf5 bad_input_phase_without_sample
  bad_input_output_dir_dangling_link bad_samples_setup bad_input_sample_nan_coordinate
  bad_input_sample_duplicate_bond bad_input_sample_volumes_off bad_input_sample_damaged_2_ranks
  bad_input_sample_matrix_fraction bad_input_sample_misspelt_option
  bad_input_fracture_negative_threshold bad_input_fracture_increment_unresolved
  bad_input_fracture_bad_rule bad_input_calibration_no_peak help_stops_before_work
  bad_input_damage_aggregates_wrapped
  bad_input_integer_not_a_number bad_input_integer_wraps_32_bits bad_input_integer_with_fraction
  bad_input_flag_not_boolean bad_input_list_nan bad_input_ksp_type_typo bad_input_pc_option_typo
  bad_input_no_value_fracture bad_input_no_value_pack bad_input_no_value_stiffness
  bad_input_no_value_convergence bad_input_no_value_bench bad_input_petsc_real_not_a_number
  bad_input_fallback_preonly bad_input_options_file_missing bad_input_options_file_loop
  ranks_error_alone ranks_error_petsc ranks_error_petsc_in_solve bad_checkpoint_crafted bad_input_not_regular_files)

# The tests the sanitizer job (jobs/check-sanitizers.sh) runs, labelled
# `sanitized`: every GoogleTest program of the quick tier (test_*: the
# library's own checks) and the driver tests named here, which run each
# program and each path the units do not reach once: 1 against 2 ranks,
# checkpoints written, read and refused, a failed solve, the relaxation
# schemes, the results kept whole on a rerun, the readers of bad input
# (docs/developer/testing.md, "Sanitizers").  The other driver tests run
# the same code with other options or data; under the sanitizers each
# costs 3 to 10 times its time, and they cost most of the job.
# Only quick tests that are not GoogleTest programs may be named here.
set(LEM_SANITIZED_TESTS
  fracture_ranks fracture_restart_kill fracture_restart_ranks fracture_restart_kill_local
  fracture_solver_failure fracture_spec_mini fracture_fcc_np1 fracture_fcc_np2
  fracture_warnings_default bad_checkpoint_crafted outputs_rerun
  sample_driver sample_driver_cells tension_driver_np2 stiffness_driver_np2
  convergence_driver_np2 help_stops_before_work bad_input_misspelt_option
  bad_input_sample_file_not_hdf5 bad_input_sample_nan_coordinate
  bad_input_sample_damaged_2_ranks bad_input_options_file_loop ranks_error_petsc
)

# Group labels by the test's name, for the tests that have none yet (the
# GoogleTest programs get their module's name from lem_add_test, e.g.
# `system`): `ctest -L <group>` runs one group.
set(LEM_TEST_GROUPS
  "^(bad_input_|bad_samples_setup$|bad_checkpoint_crafted$|ranks_error_|help_):bad_input"
  "^outputs_:outputs"
  "^signal_:signals"
  "^fracture_warnings_:warnings"
  "^fracture_:fracture"
  "^(tension_|bench_driver_|sample_driver$|sample_driver_cells$|stiffness_driver|convergence_driver|results_readers$|study_|checker_):drivers"
  "^(layering|phase_names|options_reference|extension_|function_length):layout")

function(lem_label_tests)
  get_property(tests DIRECTORY PROPERTY TESTS)
  foreach(test ${tests})
    set(labels quick)
    if(test IN_LIST LEM_LONG_TESTS)
      set(labels long)
    endif()
    get_property(group TEST ${test} PROPERTY LABELS)
    foreach(rule ${LEM_TEST_GROUPS})
      string(REGEX REPLACE ":[a-z_]+$" "" pattern "${rule}")
      string(REGEX REPLACE "^.*:" "" name "${rule}")
      if("${group}" STREQUAL "" AND test MATCHES "${pattern}")
        set(group ${name})
      endif()
    endforeach()
    if("${group}" STREQUAL "")
      message(FATAL_ERROR "tests/tiers.cmake: test '${test}' matches no group of LEM_TEST_GROUPS")
    endif()
    if(group STREQUAL "bad_input" AND NOT test IN_LIST LEM_QUICK_BAD_INPUTS)
      set(labels long)
    endif()
    if(test IN_LIST LEM_SANITIZED_TESTS)
      if(NOT labels STREQUAL "quick" OR test MATCHES "^test_")
        message(FATAL_ERROR "tests/tiers.cmake: '${test}' of LEM_SANITIZED_TESTS is long or a "
                            "GoogleTest program: the sanitizer job runs quick tests only, and "
                            "every quick GoogleTest program without being named")
      endif()
      list(APPEND labels sanitized)
    elseif(labels STREQUAL "quick" AND test MATCHES "^test_")
      list(APPEND labels sanitized)
    endif()
    set_tests_properties(${test} PROPERTIES LABELS "${labels};${group}")
  endforeach()
  set_property(GLOBAL APPEND PROPERTY LEM_LABELLED_TESTS ${tests})
endfunction()

# Called once after both directories are labelled: every name of the three
# lists is a real test.
function(lem_check_long_tests)
  get_property(labelled GLOBAL PROPERTY LEM_LABELLED_TESTS)
  foreach(list LEM_LONG_TESTS LEM_QUICK_BAD_INPUTS LEM_SANITIZED_TESTS)
    foreach(test ${${list}})
      if(NOT test IN_LIST labelled)
        message(FATAL_ERROR "tests/tiers.cmake: '${test}' of ${list} is not a test")
      endif()
    endforeach()
  endforeach()
endfunction()
