tp_cli_smoke(make-pulse)
set(W ${CMAKE_CURRENT_SOURCE_DIR}/inputs/sai-weights.json)

tp_cli_test(make-pulse refuses-missing-amplitude refuses 2 --stdin ${W} --says "give --amplitude MA, or --intensity V with --profile" -- make-pulse)
tp_cli_test(make-pulse refuses-amplitude-above-limit refuses 2 --stdin ${W} --says "--amplitude: 2.5 mA outside (0, 2" -- make-pulse --amplitude 2.5)
tp_cli_test(make-pulse refuses-unbalanced-weights refuses 2
  --stdin ${CMAKE_CURRENT_SOURCE_DIR}/inputs/unbalanced-weights.json --says "channel currents sum to 0.1 mA, not 0" -- make-pulse --amplitude 1)
tp_cli_test(make-pulse refuses-no-weights refuses 2
  --stdin ${CMAKE_CURRENT_SOURCE_DIR}/inputs/no-weights.json --says "weights document: no 'weights'" -- make-pulse --amplitude 1)
tp_cli_test(make-pulse refuses-malformed-json refuses 2
  --stdin ${CMAKE_CURRENT_SOURCE_DIR}/inputs/malformed.json --says "weights document: malformed JSON in stdin: parse error" -- make-pulse --amplitude 1)
tp_cli_test(make-pulse refuses-narrow-pulse refuses 2 --stdin ${W} --says "pulse width 5 us outside [10, 1000] us" -- make-pulse --amplitude 1 --width 5)
tp_cli_test(make-pulse refuses-high-rate refuses 2 --stdin ${W} --says "frequency 5000 Hz outside [0.1, 1000] Hz" -- make-pulse --amplitude 1 --frequency 5000)
tp_cli_test(make-pulse refuses-zero-rate refuses 2 --stdin ${W} --says "--frequency: must be > 0 Hz" -- make-pulse --amplitude 1 --frequency 0)
tp_cli_test(make-pulse refuses-short-balance refuses 2 --stdin ${W} --says "balance width 100 us outside [200, 8000] us" -- make-pulse --amplitude 1 --balance-width 100)
tp_cli_test(make-pulse refuses-pulse-longer-than-period refuses 2 --stdin ${W} --says "pulse of 9000 us does not fit its period of 5000 us" --
  make-pulse --amplitude 1 --width 1000 --balance-width 8000 --frequency 200)
tp_cli_test(make-pulse refuses-duration-and-count refuses 2 --stdin ${W} --says "--duration excludes --count" -- make-pulse --amplitude 1 --duration 1 --count 3)
tp_cli_test(make-pulse refuses-nan-amplitude refuses 2 --stdin ${W} --says "--amplitude: non-finite number 'nan'" -- make-pulse --amplitude nan)

tp_cli_test(make-pulse golden-json golden make-pulse/sai-1mA-200Hz.json --stdin ${W} --
  make-pulse --amplitude 1 --frequency 200 --duration 1)
tp_cli_test(make-pulse golden-asymmetric-csv golden make-pulse/sai-asymmetric.csv --stdin ${W} --
  make-pulse --amplitude 1.5 --frequency 100 --width 200 --balance-width 800 --interphase 50 --count 2 --format csv)
tp_cli_test(make-pulse plot script ${CMAKE_CURRENT_SOURCE_DIR}/make-pulse/plot.sh)

# A stimulator drives at most 64 channels: a 2-D design with more pads is refused.
tp_cli_test(make-pulse refuses-more-than-64-pads refuses 2
  --stdin ${CMAKE_CURRENT_SOURCE_DIR}/inputs/grid-9x8.json --says "a 9 x 8 grid of pads, 72 channels" -- make-pulse --amplitude 1)
# docs/safety.md's bounds on a single stimulus, each alone: Shannon's k (2 mA for 1000 us on
# 5 mm2: k = 1.90 > 1.85; 800 us, k = 1.71, passes: stimctl.mix-emu's heavy pattern), and the
# mean current (1.2 mA, 340 + 340 us at 1 kHz: 0.816 mA mean, above 0.8, while its RMS,
# 0.99 mA, is within 1 mA).
tp_cli_test(make-pulse refuses-shannon-k refuses 2 --stdin ${W} --says "Shannon's k 1.903 above 1.85"
  -- make-pulse --amplitude 2 --width 1000 --balance-width 1000 --frequency 10)
tp_cli_test(make-pulse refuses-mean-current refuses 2 --stdin ${W} --says "mean current 0.816 mA"
  -- make-pulse --amplitude 1.2 --width 340 --balance-width 340 --frequency 1000)
# and the RMS current alone: 2 mA, 200 + 200 us at 1 kHz is 1.26 mA RMS (its mean, 0.8 mA,
# is at the bound).  The limits before issue 22 let it through (docs/safety.md).
tp_cli_test(make-pulse refuses-rms-current refuses 2 --stdin ${W} --says "RMS current 1.264911064 mA"
  -- make-pulse --amplitude 2 --frequency 1000)

# Shaped pulses (--phases, issue 40): the document and the waveform's corners as goldens, the
# weights document's own pulse as the default, and each limit on a shape refused by name.
tp_cli_test(make-pulse golden-shaped-json golden make-pulse/sai-shaped.json --stdin ${W} --
  make-pulse --amplitude 1 --frequency 100 --count 3 --phases 500:0.1,200:1,50:0,500:-0.5)
tp_cli_test(make-pulse golden-shaped-csv golden make-pulse/sai-shaped.csv --stdin ${W} --
  make-pulse --amplitude 1 --frequency 100 --count 2 --format csv --phases 500:0.1,200:1,50:0,500:-0.5)
tp_cli_test(make-pulse uses-document-pulse script ${CMAKE_CURRENT_SOURCE_DIR}/make-pulse/document-pulse.sh)
tp_cli_test(make-pulse refuses-uncharged-shape refuses 2 --stdin ${W}
  --says "not charge balanced: the sum of level x duration is -1 us, not 0" -- make-pulse --amplitude 1 --phases 200:1,201:-1)
tp_cli_test(make-pulse refuses-short-phase refuses 2 --stdin ${W}
  --says "phase 2: duration 9 us outside" -- make-pulse --amplitude 1 --phases 200:1,9:0,200:-1)
tp_cli_test(make-pulse refuses-17-phases refuses 2 --stdin ${W} --says "--phases: more than 16 phases" --
  make-pulse --amplitude 1 --phases 20:1,20:-1,20:1,20:-1,20:1,20:-1,20:1,20:-1,20:1,20:-1,20:1,20:-1,20:1,20:-1,20:1,20:-1,20:1)
tp_cli_test(make-pulse refuses-shape-shannon-k refuses 2 --stdin ${W} --says "Shannon's k 1.903 above 1.85" --
  make-pulse --amplitude 2 --frequency 10 --phases 500:1,500:1,1000:-1)
tp_cli_test(make-pulse refuses-shape-peak refuses 2 --stdin ${W}
  --says "channel 3: current 1.5 mA at level 1.5 is 2.25 mA, above the limit of 2 mA" --
  make-pulse --amplitude 1.5 --phases 100:1.5,150:-1)
tp_cli_test(make-pulse refuses-shape-rms refuses 2 --stdin ${W} --says "RMS current 1.341640786 mA" --
  make-pulse --amplitude 1.5 --frequency 1000 --phases 400:1,400:-1)
tp_cli_test(make-pulse refuses-phases-and-width refuses 2 --stdin ${W} --says "--width excludes --phases" --
  make-pulse --amplitude 1 --phases 200:1,200:-1 --width 100)
tp_cli_test(make-pulse refuses-fine-level refuses 2 --stdin ${W} --says "levels must be multiples of 1/U for some U up to 64" --
  make-pulse --amplitude 1 --phases 130:1,1000:-0.13)
