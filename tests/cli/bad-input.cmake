# Bad input, as classes of fault, for every program that reads it: exit 2, one line on
# stderr, nothing on stdout (and, for stimctl, nothing sent).
set(IN ${CMAKE_CURRENT_SOURCE_DIR}/inputs)
set(W ${IN}/sai-weights.json)

# Numbers beyond a double (1e999), directories, a document that never ends (/dev/zero).
tp_cli_test(af-field refuses-huge-number refuses 2 --stdin ${IN}/huge-number.json -- af-field --config -)
tp_cli_test(optimize-weights refuses-huge-number refuses 2 --stdin ${IN}/huge-number.json -- optimize-weights --mode SAI --config -)
tp_cli_test(make-pulse refuses-huge-number refuses 2 --stdin ${IN}/huge-weight.json -- make-pulse --amplitude 1)
tp_cli_test(stimctl refuses-huge-number refuses 2 --stdin ${IN}/stimulus-huge-count.json -- stimctl --port emu)
tp_cli_test(af-field refuses-directory refuses 2 -- af-field --config ${IN})
tp_cli_test(optimize-weights refuses-directory refuses 2 -- optimize-weights --mode SAI --config ${IN})
tp_cli_test(make-pulse refuses-directory refuses 2 -- make-pulse --amplitude 1 --input ${IN})
tp_cli_test(stimctl refuses-directory refuses 2 -- stimctl --port emu --stimulus ${IN})
tp_cli_test(af-field refuses-endless-document refuses 2 -- af-field --config /dev/zero)
tp_cli_test(make-pulse refuses-endless-stdin refuses 2 --stdin /dev/zero -- make-pulse --amplitude 1)

# Every physical parameter has a documented range (docs/document-format.md).
foreach(case resistivity margin margin-1e4 diameter depth length positions max-current)
  tp_cli_test(af-field refuses-range-${case} refuses 2 --stdin ${IN}/range-${case}.json -- af-field --config - --summary)
  tp_cli_test(optimize-weights refuses-range-${case} refuses 2 --stdin ${IN}/range-${case}.json --
    optimize-weights --mode SAI --config -)
endforeach()
tp_cli_test(af-field refuses-tiny-depth-grid refuses 2 -- af-field --y 1e-300:1e-300:1)
tp_cli_test(af-field refuses-far-grid refuses 2 -- af-field --x -1e4:0:1)
tp_cli_test(af-field refuses-huge-grid refuses 2 -- af-field --x -500:500:0.001 --y 0.1:10:0.001)
tp_cli_test(af-field refuses-huge-amplitude refuses 2 -- af-field --amplitude 1e300)
tp_cli_test(af-field refuses-huge-weight refuses 2 -- af-field --electrodes 2 --weights 1e300,-1e300)
tp_cli_test(af-field refuses-65-electrodes refuses 2 -- af-field --electrodes 65)
tp_cli_test(optimize-weights refuses-65-electrodes refuses 2 -- optimize-weights --mode SAI --electrodes 65)
tp_cli_test(optimize-weights refuses-4096-electrodes refuses 2 -- optimize-weights --mode SAI --electrodes 4096)
tp_cli_test(optimize-weights refuses-max-current-above-2 refuses 2 -- optimize-weights --mode SAI --max-current 5)
tp_cli_test(af-field refuses-positions-disagree-pitch refuses 2 --stdin ${IN}/positions-disagree-pitch.json -- af-field --config - --summary)

# Everything is checked before anything is printed; rates the device cannot make; counts
# and durations that would wrap.
tp_cli_test(make-pulse refuses-csv-pulses-zero refuses 2 --stdin ${W} -- make-pulse --amplitude 1 --format csv --csv-pulses 0)
tp_cli_test(make-pulse refuses-slow-rate refuses 2 --stdin ${W} -- make-pulse --amplitude 1 --frequency 0.05 --count 2)
tp_cli_test(make-pulse refuses-huge-count refuses 2 --stdin ${W} -- make-pulse --amplitude 1 --count 1e300)
tp_cli_test(make-pulse refuses-huge-duration refuses 2 --stdin ${W} -- make-pulse --amplitude 1 --duration 1e300)
tp_cli_test(make-pulse refuses-duration-over-limit refuses 2 --stdin ${W} -- make-pulse --amplitude 1 --duration 3601)
# Nesting: a 64 MiB "[[[[..." would build millions of nested values; 64 levels at most.
tp_cli_test(af-field refuses-deep-nesting refuses 2 --stdin ${IN}/nested-65.json -- af-field --config -)
# A receptor name is a mode name and a CSV column: a comma would break the CSV.
tp_cli_test(optimize-weights refuses-receptor-name-comma refuses 2 --stdin ${IN}/receptor-name-comma.json --
  optimize-weights --mode SAI --config - --format csv)
tp_cli_test(optimize-weights refuses-huge-min-af refuses 2 -- optimize-weights --mode SAI --min-target-af 1e300)

# An empty option value is refused, never taken as "not given" (issue 20, item 8): every
# program's options go through one check in the entry helper.
foreach(opt width tolerance z conductor skin widths)
  tp_cli_test(fiber-threshold refuses-empty-${opt} refuses 2 --stdin ${W} --says "--${opt}: empty value" --
    fiber-threshold --${opt}=)
endforeach()
foreach(opt amplitude weights z x)
  tp_cli_test(af-field refuses-empty-${opt} refuses 2 --says "--${opt}: empty value" -- af-field --${opt}=)
endforeach()
# (CMake drops an empty argument, so the tests above give --opt=; this one gives --opt ''.)
tp_cli_test(af-field refuses-empty-separate script ${CMAKE_CURRENT_SOURCE_DIR}/af-field/empty-values.sh)
foreach(opt max-current min-target-af electrodes)
  tp_cli_test(optimize-weights refuses-empty-${opt} refuses 2 --says "--${opt}: empty value" --
    optimize-weights --mode SAI --${opt}=)
endforeach()
tp_cli_test(optimize-weights refuses-empty-mode-value refuses 2 --says "--mode: empty value" -- optimize-weights --mode=)

# A setting the model does not use is refused, never silently ignored (item 9): the 3-D
# models' --z under a 2-D model, a document's model keys under a model that ignores them,
# and a document's setting left behind when --model changes the conductor.
tp_cli_test(af-field refuses-z-line2d refuses 2 --says "--z: applies to the 3-D models" -- af-field --z 1)
tp_cli_test(af-field refuses-z-strip2d refuses 2 --says "this model is strip2d (from --model)" --
  af-field --model strip2d --z 1)
tp_cli_test(optimize-weights refuses-z-line2d refuses 2 --says "--z: applies to the 3-D models" --
  optimize-weights --mode SAI --z 1)
tp_cli_test(fiber-threshold refuses-z-line2d refuses 2 --stdin ${W} --says "--z: applies to the 3-D models" --
  fiber-threshold --z 1)
foreach(case source-depth-rect3d source-depth-layered plane-z-line2d skin-line2d skin-default-model
             resistivity-layered)
  tp_cli_test(af-field refuses-setting-${case} refuses 2 --stdin ${IN}/setting-${case}.json --says "applies to" --
    af-field --config - --summary)
  tp_cli_test(optimize-weights refuses-setting-${case} refuses 2 --stdin ${IN}/setting-${case}.json --says "applies to" --
    optimize-weights --mode SAI --config -)
endforeach()
tp_cli_test(af-field refuses-setting-left-by-model refuses 2 --stdin ${IN}/setting-point3d-source-depth.json
  --says "this model is rect3d (from --model)" --
  af-field --config - --model rect3d --summary)
tp_cli_test(fiber-threshold refuses-setting-left-by-conductor refuses 2 --stdin ${IN}/setting-point3d-source-depth.json
  --says "this model is layered (from --conductor)" --
  fiber-threshold --conductor layered)
# A document carries only the settings its model uses, so it always reads back.
tp_cli_test(optimize-weights layered-document-reads-back script ${CMAKE_CURRENT_SOURCE_DIR}/optimize-weights/settings-round-trip.sh)

# Messages name the option the user typed (item 10).
tp_cli_test(optimize-weights refuses-unknown-fibre-model refuses 2 --says "--fibre-model: unknown fibre model 'x'" --
  optimize-weights --mode SAI --objective threshold --fibre-model x)
tp_cli_test(fiber-threshold refuses-unknown-fibre-model refuses 2 --stdin ${W} --says "--model: unknown fibre model 'x'" --
  fiber-threshold --model x)
tp_cli_test(af-field refuses-unknown-conductor refuses 2 --says "--model: unknown conductor model 'x'" --
  af-field --model x)

# A grid ending at a limit stays within it (item 11): the last row of 0.01:20:0.01 is 20, not
# 20.000000000000004, so neither the depth range nor a layered skin's valid_to_mm refuses it.
tp_cli_test(af-field grid-ends-at-limit script ${CMAKE_CURRENT_SOURCE_DIR}/af-field/grid-ends.sh)

# stdin is read once per process: a second reader is refused naming both, in every program
# (item 10), never "stdin is empty".
tp_cli_test(af-field refuses-two-stdin-readers refuses 2 --stdin ${IN}/sai-weights.json
  --says "--skin - and --config - both read stdin" -- af-field --config - --model layered --skin - --summary)
tp_cli_test(optimize-weights refuses-two-stdin-readers refuses 2 --stdin ${IN}/sai-weights.json
  --says "--skin - and --config - both read stdin" -- optimize-weights --mode SAI --config - --model layered --skin -)
tp_cli_test(optimize-weights refuses-two-stdin-readers-threshold refuses 2 --stdin ${IN}/sai-weights.json
  --says "--stimulus - and --config - both read stdin" --
  optimize-weights --mode SAI --objective threshold --config - --stimulus -)
