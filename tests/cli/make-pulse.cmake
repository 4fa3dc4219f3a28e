tp_cli_smoke(make-pulse)
set(W ${CMAKE_CURRENT_SOURCE_DIR}/inputs/sai-weights.json)

tp_cli_test(make-pulse refuses-missing-amplitude refuses 2 --stdin ${W} -- make-pulse)
tp_cli_test(make-pulse refuses-amplitude-above-limit refuses 2 --stdin ${W} -- make-pulse --amplitude 2.5)
tp_cli_test(make-pulse refuses-unbalanced-weights refuses 2
  --stdin ${CMAKE_CURRENT_SOURCE_DIR}/inputs/unbalanced-weights.json -- make-pulse --amplitude 1)
tp_cli_test(make-pulse refuses-no-weights refuses 2
  --stdin ${CMAKE_CURRENT_SOURCE_DIR}/inputs/no-weights.json -- make-pulse --amplitude 1)
tp_cli_test(make-pulse refuses-malformed-json refuses 2
  --stdin ${CMAKE_CURRENT_SOURCE_DIR}/inputs/malformed.json -- make-pulse --amplitude 1)
tp_cli_test(make-pulse refuses-narrow-pulse refuses 2 --stdin ${W} -- make-pulse --amplitude 1 --width 5)
tp_cli_test(make-pulse refuses-high-rate refuses 2 --stdin ${W} -- make-pulse --amplitude 1 --frequency 5000)
tp_cli_test(make-pulse refuses-zero-rate refuses 2 --stdin ${W} -- make-pulse --amplitude 1 --frequency 0)
tp_cli_test(make-pulse refuses-short-balance refuses 2 --stdin ${W} -- make-pulse --amplitude 1 --balance-width 100)
tp_cli_test(make-pulse refuses-pulse-longer-than-period refuses 2 --stdin ${W} --
  make-pulse --amplitude 1 --width 1000 --balance-width 8000 --frequency 200)
tp_cli_test(make-pulse refuses-duration-and-count refuses 2 --stdin ${W} -- make-pulse --amplitude 1 --duration 1 --count 3)
tp_cli_test(make-pulse refuses-nan-amplitude refuses 2 --stdin ${W} -- make-pulse --amplitude nan)

tp_cli_test(make-pulse golden-json golden make-pulse/sai-1mA-200Hz.json --stdin ${W} --
  make-pulse --amplitude 1 --frequency 200 --duration 1)
tp_cli_test(make-pulse golden-asymmetric-csv golden make-pulse/sai-asymmetric.csv --stdin ${W} --
  make-pulse --amplitude 1.5 --frequency 100 --width 200 --balance-width 800 --interphase 50 --count 2 --format csv)
tp_cli_test(make-pulse plot script ${CMAKE_CURRENT_SOURCE_DIR}/make-pulse/plot.sh)

# A stimulator drives at most 64 channels: a 2-D design with more pads is refused.
tp_cli_test(make-pulse refuses-more-than-64-pads refuses 2 --says "at most 64"
  --stdin ${CMAKE_CURRENT_SOURCE_DIR}/inputs/grid-9x8.json -- make-pulse --amplitude 1)
