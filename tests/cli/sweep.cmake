# sweep-spacing and its engines (label sweep).
tp_cli_test(sweep local script ${CMAKE_CURRENT_SOURCE_DIR}/sweep/local.sh)
tp_cli_test(sweep engines script ${CMAKE_CURRENT_SOURCE_DIR}/sweep/engines.sh)
set_tests_properties(sweep.engines PROPERTIES TIMEOUT 300)
# A real single-node Slurm (slurmctld, slurmd and munged started and stopped by the test):
# skipped (77) where it cannot start, except with TP_REQUIRE_SLURM=1 (CI).  The plain build
# only: it runs the same programs as sweep.engines.
if(NOT TP_SANITIZE)
  tp_cli_test(sweep slurm script ${CMAKE_CURRENT_SOURCE_DIR}/sweep/slurm.sh)
  set_tests_properties(sweep.slurm PROPERTIES LABELS "cli;sweep;slurm" RUN_SERIAL TRUE TIMEOUT 600
    SKIP_RETURN_CODE 77)
endif()
