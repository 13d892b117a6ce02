# Test tiers and groups (docs/testing.md, "Tiers").  Every test gets one
# tier label, `quick` or `long`, and one group label from its name.
#   quick  what `bash jobs/test.sh` runs after every change: every module and
#          every promise in at least one test, in about two minutes
#   long   the rest: the same promises on larger samples, every stop point,
#          every kill point; `bash jobs/test.sh --all` and CI run both tiers
# lem_label_tests() labels the tests of the directory it is called in (a
# test's properties can only be set there), so both CMakeLists.txt call it
# after their last add_test.

# Tests of the long tier: each costs ten seconds or more on an idle machine,
# and a quick test covers its promise on a smaller case (named after '#').
set(LEM_LONG_TESTS
  fracture_deflation              # test_particle_deflation_np1
  test_particle_deflation_np2     # test_particle_deflation_np1, the other MPI tests at 2 ranks
  fracture_fidelity_mini          # fracture_ranks_decision, FractureParts.DecidedBatch* (decided solves)
  fracture_fidelity_tiny          # the same
  fracture_ranks_mini             # fracture_ranks, fracture_gold_main (1 rank against a 2-rank gold)
  fracture_ranks_mini_decision    # fracture_ranks_decision
  outputs_commit_kill             # fracture_restart_kill, outputs_keep_finished
  outputs_disk_full_sizes         # outputs_disk_full, outputs_disk_full_overwrite
  outputs_overwrite_kill          # outputs_keep_finished, outputs_rerun
  outputs_overwrite_kill_renames  # outputs_keep_finished, outputs_rerun
  outputs_overwrite_stale         # outputs_concurrent
  signal_reference                # fracture_restart_signal (the fixture of the signal_* tests)
  signal_calibration              # fracture_restart_signal
  signal_after_calibration        # fracture_restart_signal
  signal_avalanche                # fracture_restart_signal
  signal_final_writes             # fracture_restart_signal
  signal_mpirun_term              # fracture_restart_signal, ranks_error_*
  signal_anytime                  # fracture_restart_signal
  fracture_warnings_mini          # fracture_warnings_default, _coarse
  study_bad_input                 # tests/python/test_study.py (study files refused)
)

# Group labels by the test's name, for the tests that have none yet (the
# GoogleTest programs get `unit` or `mpi` from lem_add_test): `ctest -L
# <group>` runs one group.
set(LEM_TEST_GROUPS
  "^(bad_input_|bad_samples_setup$|bad_checkpoint_crafted$|ranks_error_|help_):bad_input"
  "^outputs_:outputs"
  "^signal_:signals"
  "^fracture_warnings_:warnings"
  "^fracture_:fracture"
  "^(tension_|sample_driver$|stiffness_driver|results_readers$|study_):drivers"
  "^(layering|phase_names):layout")

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
    set_tests_properties(${test} PROPERTIES LABELS "${labels};${group}")
  endforeach()
  set_property(GLOBAL APPEND PROPERTY LEM_LABELLED_TESTS ${tests})
endfunction()

# Called once after both directories are labelled: every name of the long
# list is a real test.
function(lem_check_long_tests)
  get_property(labelled GLOBAL PROPERTY LEM_LABELLED_TESTS)
  foreach(test ${LEM_LONG_TESTS})
    if(NOT test IN_LIST labelled)
      message(FATAL_ERROR "tests/tiers.cmake: '${test}' of LEM_LONG_TESTS is not a test")
    endif()
  endforeach()
endfunction()
