tp_cli_smoke(optimize-weights)

tp_cli_test(optimize-weights refuses-missing-mode refuses 2 -- optimize-weights)
tp_cli_test(optimize-weights refuses-unknown-mode refuses 2 -- optimize-weights --mode XY)
tp_cli_test(optimize-weights refuses-one-electrode refuses 2 -- optimize-weights --mode SAI --electrodes 1)
tp_cli_test(optimize-weights refuses-zero-pitch refuses 2 -- optimize-weights --mode SAI --pitch 0)
tp_cli_test(optimize-weights refuses-nan-pitch refuses 2 -- optimize-weights --mode SAI --pitch nan)
tp_cli_test(optimize-weights refuses-inf-current refuses 2 -- optimize-weights --mode SAI --max-current inf)
tp_cli_test(optimize-weights refuses-zero-current refuses 2 -- optimize-weights --mode SAI --max-current 0)
tp_cli_test(optimize-weights refuses-negative-min-af refuses 2 -- optimize-weights --mode SAI --min-target-af -1)
tp_cli_test(optimize-weights refuses-unreachable-min-af refuses 2 -- optimize-weights --mode PC --min-target-af 100)
tp_cli_test(optimize-weights refuses-bad-format refuses 2 -- optimize-weights --mode PC --format xml)
tp_cli_test(optimize-weights refuses-malformed-config refuses 2 --stdin ${CMAKE_CURRENT_SOURCE_DIR}/inputs/malformed.json -- optimize-weights --mode SAI --config -)
tp_cli_test(optimize-weights refuses-one-electrode-config refuses 2 --stdin ${CMAKE_CURRENT_SOURCE_DIR}/inputs/one-electrode.json -- optimize-weights --mode SAI --config -)

foreach(mode RA SAI PC)
  tp_cli_test(optimize-weights golden-paper-${mode} golden optimize-weights/paper-${mode}.json --rtol 1e-6 --
    optimize-weights --mode ${mode})
endforeach()
tp_cli_test(optimize-weights golden-csv golden optimize-weights/pc-12x0.75.csv --rtol 1e-6 --
  optimize-weights --mode PC --electrodes 12 --pitch 0.75 --format csv)

tp_cli_test(optimize-weights paper-modes-certified script ${CMAKE_CURRENT_SOURCE_DIR}/optimize-weights/certified.sh)
tp_cli_test(optimize-weights deterministic script ${CMAKE_CURRENT_SOURCE_DIR}/optimize-weights/deterministic.sh)
tp_cli_test(optimize-weights efficiency script ${CMAKE_CURRENT_SOURCE_DIR}/optimize-weights/efficiency.sh)
tp_cli_test(optimize-weights sweep script ${CMAKE_CURRENT_SOURCE_DIR}/optimize-weights/sweep.sh)
tp_cli_test(optimize-weights large-array script ${CMAKE_CURRENT_SOURCE_DIR}/optimize-weights/large-array.sh)
set_tests_properties(optimize-weights.large-array PROPERTIES TIMEOUT 300)
