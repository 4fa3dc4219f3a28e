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
