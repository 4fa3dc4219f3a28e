# Bad input, as classes of fault, for every program that reads it: exit 2, one line on
# stderr, nothing on stdout (and, for stimctl, nothing sent).
set(IN ${CMAKE_CURRENT_SOURCE_DIR}/inputs)
set(W ${IN}/sai-weights.json)

# Numbers beyond a double (1e999), directories, a document that never ends (/dev/zero).
tp_cli_test(af-field refuses-huge-number refuses 2 --stdin ${IN}/huge-number.json --says "--config: malformed JSON in stdin: number overflow parsing '1e999'" -- af-field --config -)
tp_cli_test(optimize-weights refuses-huge-number refuses 2 --stdin ${IN}/huge-number.json --says "--config: malformed JSON in stdin: number overflow parsing '1e999'" -- optimize-weights --mode SAI --config -)
tp_cli_test(make-pulse refuses-huge-number refuses 2 --stdin ${IN}/huge-weight.json --says "number overflow parsing '1e999'" -- make-pulse --amplitude 1)
tp_cli_test(stimctl refuses-huge-number refuses 2 --stdin ${IN}/stimulus-huge-count.json --says "stimulus: malformed JSON in stdin: number overflow parsing '1e999'" -- stimctl --port emu)
tp_cli_test(af-field refuses-directory refuses 2 --says "is a directory, not a JSON file" -- af-field --config ${IN})
tp_cli_test(optimize-weights refuses-directory refuses 2 --says "is a directory, not a JSON file" -- optimize-weights --mode SAI --config ${IN})
tp_cli_test(make-pulse refuses-directory refuses 2 --says "is a directory, not a JSON file" -- make-pulse --amplitude 1 --input ${IN})
tp_cli_test(stimctl refuses-directory refuses 2 --says "is a directory, not a JSON file" -- stimctl --port emu --stimulus ${IN})
tp_cli_test(af-field refuses-endless-document refuses 2 --says "--config: '/dev/zero' is larger than 64 MiB" -- af-field --config /dev/zero)
tp_cli_test(make-pulse refuses-endless-stdin refuses 2 --stdin /dev/zero --says "weights document: stdin is larger than 64 MiB" -- make-pulse --amplitude 1)

# Every physical parameter has a documented range (docs/document-format.md).
set(says_resistivity "model.resistivity_ohm_m: 1e+250 ohm m outside [0.01, 10000000] ohm m")
set(says_margin "model.lateral_margin_mm: 1e+300 mm outside [0, 50] mm")
set(says_margin-1e4 "model.lateral_margin_mm: 10000 mm outside [0, 50] mm")
set(says_diameter "receptor SAI diameter_um: 1e+200 um outside [0.1, 30] um")
set(says_depth "receptor SAI depth_mm: 1e-07 mm outside [0.01, 20] mm")
set(says_length "array.length_mm: 0 mm outside [0.01, 1000] mm")
set(says_positions "array.positions_mm[0]: -10000 mm outside [-500, 500] mm")
set(says_max-current "max_current_mA: 5 mA outside [0.001, 2] mA")
foreach(case resistivity margin margin-1e4 diameter depth length positions max-current)
  tp_cli_test(af-field refuses-range-${case} refuses 2 --stdin ${IN}/range-${case}.json --says "${says_${case}}" -- af-field --config - --summary)
  tp_cli_test(optimize-weights refuses-range-${case} refuses 2 --stdin ${IN}/range-${case}.json --says "${says_${case}}" --
    optimize-weights --mode SAI --config -)
endforeach()
tp_cli_test(af-field refuses-tiny-depth-grid refuses 2 --says "--y MIN: 1e-300 mm outside [0.01, 20] mm" -- af-field --y 1e-300:1e-300:1)
tp_cli_test(af-field refuses-far-grid refuses 2 --says "--x MIN: -10000 mm outside [-500, 500] mm" -- af-field --x -1e4:0:1)
tp_cli_test(af-field refuses-huge-grid refuses 2 --says "grid: 9901009901 points, more than 100000000" -- af-field --x -500:500:0.001 --y 0.1:10:0.001)
tp_cli_test(af-field refuses-huge-amplitude refuses 2 --says "--amplitude: 1e+300 mA outside [1e-06, 100] mA" -- af-field --amplitude 1e300)
tp_cli_test(af-field refuses-huge-weight refuses 2 --says "--weights item 1: 1e+300 outside [-1000, 1000]" -- af-field --electrodes 2 --weights 1e300,-1e300)
tp_cli_test(af-field refuses-65-electrodes refuses 2 --says "--electrodes: at most 64, got 65" -- af-field --electrodes 65)
tp_cli_test(optimize-weights refuses-65-electrodes refuses 2 --says "--electrodes: at most 64, got 65" -- optimize-weights --mode SAI --electrodes 65)
tp_cli_test(optimize-weights refuses-4096-electrodes refuses 2 --says "--electrodes: at most 64, got 4096" -- optimize-weights --mode SAI --electrodes 4096)
tp_cli_test(optimize-weights refuses-max-current-above-2 refuses 2 --says "--max-current: 5 mA outside [0.001, 2] mA" -- optimize-weights --mode SAI --max-current 5)
tp_cli_test(af-field refuses-positions-disagree-pitch refuses 2 --stdin ${IN}/positions-disagree-pitch.json --says "array: positions_mm[0] and [1] are 2 mm apart, not pitch_mm 1 mm" -- af-field --config - --summary)

# Everything is checked before anything is printed; rates the device cannot make; counts
# and durations that would wrap.
tp_cli_test(make-pulse refuses-csv-pulses-zero refuses 2 --stdin ${W} --says "--csv-pulses: 0 outside [1, 100000]" -- make-pulse --amplitude 1 --format csv --csv-pulses 0)
tp_cli_test(make-pulse refuses-slow-rate refuses 2 --stdin ${W} --says "frequency 0.05 Hz outside [0.1, 1000] Hz" -- make-pulse --amplitude 1 --frequency 0.05 --count 2)
tp_cli_test(make-pulse refuses-huge-count refuses 2 --stdin ${W} --says "--count: out of range '1e300'" -- make-pulse --amplitude 1 --count 1e300)
tp_cli_test(make-pulse refuses-huge-duration refuses 2 --stdin ${W} --says "--duration: 1e+300 s outside (0, 3600" -- make-pulse --amplitude 1 --duration 1e300)
tp_cli_test(make-pulse refuses-duration-over-limit refuses 2 --stdin ${W} --says "--duration: 3601 s outside (0, 3600" -- make-pulse --amplitude 1 --duration 3601)
# Nesting: a 64 MiB "[[[[..." would build millions of nested values; 64 levels at most.
tp_cli_test(af-field refuses-deep-nesting refuses 2 --stdin ${IN}/nested-65.json --says "--config: stdin nests deeper than 64 levels" -- af-field --config -)
# A receptor name is a mode name and a CSV column: a comma would break the CSV.
tp_cli_test(optimize-weights refuses-receptor-name-comma refuses 2 --stdin ${IN}/receptor-name-comma.json --says "receptors[0]: 'name' must be 1 to 32 of A-Z a-z 0-9 _ . -" --
  optimize-weights --mode SAI --config - --format csv)
tp_cli_test(optimize-weights refuses-huge-min-af refuses 2 --says "--min-target-af: 1e300 V/ms outside [0, 10000] V/ms" -- optimize-weights --mode SAI --min-target-af 1e300)

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
set(says_source-depth-rect3d "model.source_depth_mm: applies to the point3d model only")
set(says_source-depth-layered "model.source_depth_mm: applies to the point3d model only")
set(says_plane-z-line2d "model.plane_z_mm: applies to the 3-D models (point3d, rect3d, layered) only")
set(says_skin-line2d "model.skin: applies to the layered model only")
set(says_skin-default-model "model.skin: applies to the layered model only")
set(says_resistivity-layered "model.resistivity_ohm_m: applies to the uniform models")
foreach(case source-depth-rect3d source-depth-layered plane-z-line2d skin-line2d skin-default-model
             resistivity-layered)
  tp_cli_test(af-field refuses-setting-${case} refuses 2 --stdin ${IN}/setting-${case}.json --says "${says_${case}}" --
    af-field --config - --summary)
  tp_cli_test(optimize-weights refuses-setting-${case} refuses 2 --stdin ${IN}/setting-${case}.json --says "${says_${case}}" --
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
