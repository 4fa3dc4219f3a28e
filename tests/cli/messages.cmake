# Issue 38: what a new user and an adversarial test found in the messages and options.
set(IN ${CMAKE_CURRENT_SOURCE_DIR}/inputs)

# The harness itself: a refusal test without --says fails, naming the test (a misspelled
# flag's refusal would pass exit status, one line and empty stdout alone).
add_test(NAME check.refuses-requires-says COMMAND ${TP_CHECK} refuses 2 -- af-field --bogus)
set_tests_properties(check.refuses-requires-says PROPERTIES ENVIRONMENT "${TP_CLI_ENV}"
  LABELS "cli" PASS_REGULAR_EXPRESSION "FAIL: check.refuses-requires-says: refuses without --says")

# A refused value reads differently from the bound it breaks (not "2 mA outside [0.001, 2]").
tp_cli_test(optimize-weights refuses-max-current-just-above refuses 2
  --says "--max-current: 2.00000000001 mA outside [0.001, 2] mA" --
  optimize-weights --mode SAI --max-current 2.00000000001)
tp_cli_test(af-field refuses-depth-just-below refuses 2 --says "--y MIN: 0.0099999999999 mm outside" --
  af-field --y 0.0099999999999:1:0.1)
tp_cli_test(make-pulse refuses-amplitude-just-above refuses 2 --stdin ${IN}/sai-weights.json
  --says "--amplitude: 2.0000000001 mA outside (0, 2" -- make-pulse --amplitude 2.0000000001)
tp_cli_test(make-pulse refuses-current-just-above-document-limit refuses 2 --stdin ${IN}/sai-weights-0.8mA.json
  --says "channel 3: current 0.80000000001 mA exceeds the limit of 0.8 mA" --
  make-pulse --amplitude 0.80000000001)
tp_cli_test(fiber-threshold refuses-width-just-above refuses 2
  --says "--widths: 10000.0000001 us outside [1, 10000] us" --
  fiber-threshold --config ${IN}/sai-weights.json --strength-duration --widths 100,10000.0000001)

# Integer options: the text as given, never a value it was clamped to; decimal only.
tp_cli_test(fiber-threshold refuses-population-overflow refuses 2
  --says "--population: 99999999999999999999 outside [1, 10000]" --
  fiber-threshold --config ${IN}/sai-weights.json --population 99999999999999999999)
tp_cli_test(optimize-weights refuses-random-starts-overflow refuses 2
  --says "--random-starts: 99999999999999999999 outside [0, 1000]" --
  optimize-weights --mode SAI --random-starts 99999999999999999999)
tp_cli_test(stim-emu refuses-channels-overflow refuses 2
  --says "--channels: 99999999999999999999 outside [1, 64]" -- stim-emu --channels 99999999999999999999)
tp_cli_test(fiber-threshold refuses-hex-threads refuses 2 --says "--threads: not a number '0x10'" --
  fiber-threshold --config ${IN}/sai-weights.json --threads 0x10)
# Seeds: 0 to 2^64 - 1, exactly (fiber-threshold.population uses the largest).
tp_cli_test(fiber-threshold refuses-negative-seed refuses 2
  --says "--seed: -1 outside [0, 18446744073709551615]" --
  fiber-threshold --config ${IN}/sai-weights.json --population 1 --seed -1)
tp_cli_test(fiber-threshold refuses-seed-2-64 refuses 2
  --says "--seed: 18446744073709551616 outside [0, 18446744073709551615]" --
  fiber-threshold --config ${IN}/sai-weights.json --population 1 --seed 18446744073709551616)
tp_cli_test(stim-emu refuses-negative-seed refuses 2 --says "--seed: -1 outside [0, 18446744073709551615]" --
  stim-emu --seed -1)
tp_cli_test(stim-emu refuses-seed-2-64 refuses 2
  --says "--seed: 18446744073709551616 outside [0, 18446744073709551615]" -- stim-emu --seed 18446744073709551616)
# --population: the help states both bounds, the count's and the work's (about 7500 on the
# paper's array with a 200 us pulse), and 7600 there is refused before any work.
add_test(NAME fiber-threshold.help-population-bound COMMAND fiber-threshold --help)
set_tests_properties(fiber-threshold.help-population-bound PROPERTIES LABELS "cli;fiber-threshold"
  PASS_REGULAR_EXPRESSION "1 to 10000, and no more fibre simulation than the work bound[ \n]+allows")
tp_cli_test(fiber-threshold refuses-population-over-work-bound refuses 2
  --says "--population: an estimated" --
  fiber-threshold --config ${IN}/sai-weights.json --population 7600)

# max_current_mA, wherever a document gives it: in its range (not "exceeds the limit of -1").
tp_cli_test(fiber-threshold refuses-stimulus-negative-max-current refuses 2
  --says "max_current_mA: -1 mA outside [0.001, 2] mA" --
  fiber-threshold --config ${IN}/sai-weights.json --stimulus ${IN}/stimulus-negative-max-current.json)
tp_cli_test(stimctl refuses-negative-max-current refuses 2 --stdin ${IN}/stimulus-negative-max-current.json
  --says "max_current_mA: -1 mA outside [0.001, 2] mA" -- stimctl --port emu)
tp_cli_test(stimctl refuses-mix-negative-max-current refuses 2
  --says "max_current_mA: -1 mA outside [0.001, 2] mA" -- mix-stimuli ${IN}/stimulus-negative-max-current.json)
tp_cli_test(make-pulse refuses-negative-max-current refuses 2 --stdin ${IN}/weights-negative-max-current.json
  --says "max_current_mA: -1 mA outside [0.001, 2] mA" -- make-pulse --amplitude 1)

# An option given twice is refused, naming it and what was given (every program, option
# groups too).
tp_cli_test(fiber-threshold refuses-repeated-at refuses 2 --says "--at: given 2 times ('0,0', '1,1')" --
  fiber-threshold --grid 2x2 --weights 1,-1,0,0 --at 0,0 --at 1,1)
tp_cli_test(af-field refuses-repeated-pitch refuses 2 --says "--pitch: given 2 times ('1', '2')" --
  af-field --pitch 1 --pitch 2)
tp_cli_test(optimize-weights refuses-repeated-max-evaluations refuses 2
  --says "--max-evaluations: given 2 times ('10', '20')" --
  optimize-weights --mode SAI --objective threshold --max-evaluations 10 --max-evaluations 20)

# User text in a message: control characters and bytes that are not UTF-8 escaped, from argv
# and from files, in tp's messages and CLI11's.
tp_cli_test(af-field escaped-messages script ${CMAKE_CURRENT_SOURCE_DIR}/messages/escaped.sh)
