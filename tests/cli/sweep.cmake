# sweep-spacing and its engines (label sweep).
tp_cli_test(sweep local script ${CMAKE_CURRENT_SOURCE_DIR}/sweep/local.sh)
tp_cli_test(sweep grid script ${CMAKE_CURRENT_SOURCE_DIR}/sweep/grid.sh)
tp_cli_test(sweep engines script ${CMAKE_CURRENT_SOURCE_DIR}/sweep/engines.sh)
set_tests_properties(sweep.engines PROPERTIES TIMEOUT 300)
if(TP_SANITIZE)
  # Scripts over programs that the rest of the suite runs under the sanitizers; sweep.grid
  # and sweep.signals still run there (docs/testing.md, the sanitizer build).
  set_tests_properties(sweep.engines PROPERTIES DISABLED TRUE)
endif()
# Real daemons, started and stopped by the tests: a single-node Slurm (slurmctld, slurmd,
# munged) and an sshd on loopback as another host for GNU parallel.  Skipped (77) where they
# cannot start, except with TP_REQUIRE_CLUSTER=1 (CI).  The plain build only: they run the
# same programs as sweep.engines.
if(NOT TP_SANITIZE)
  tp_cli_test(sweep slurm script ${CMAKE_CURRENT_SOURCE_DIR}/sweep/slurm.sh)
  set_tests_properties(sweep.slurm PROPERTIES LABELS "cli;sweep;slurm" RUN_SERIAL TRUE TIMEOUT 600
    SKIP_RETURN_CODE 77)
  tp_cli_test(sweep ssh script ${CMAKE_CURRENT_SOURCE_DIR}/sweep/ssh.sh)
  set_tests_properties(sweep.ssh PROPERTIES TIMEOUT 300 SKIP_RETURN_CODE 77)
endif()
# Every terminating signal to the script stops its workers, leaves none, and frees --state.
tp_cli_test(sweep signals script ${CMAKE_CURRENT_SOURCE_DIR}/sweep/signals.sh)
set_tests_properties(sweep.signals PROPERTIES TIMEOUT 300)
