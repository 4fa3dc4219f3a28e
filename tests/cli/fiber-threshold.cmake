tp_cli_smoke(fiber-threshold)
set(IN ${CMAKE_CURRENT_SOURCE_DIR}/inputs)

# Bad input: one line on stderr, exit 2, nothing on stdout.
tp_cli_test(fiber-threshold refuses-unknown-model refuses 2 --stdin ${IN}/sai-weights.json --says "--model: unknown fibre model 'hh'" -- fiber-threshold --model hh)
tp_cli_test(fiber-threshold refuses-too-thin refuses 2 --says "receptor RA: diameter 1.5 um outside mrg's range [2, 16] um" -- fiber-threshold --config ${IN}/fibre-too-thin.json)
tp_cli_test(fiber-threshold refuses-unmyelinated refuses 2 --says "receptor SAI: the fibre models are myelinated" -- fiber-threshold --config ${IN}/fibre-unmyelinated.json)
tp_cli_test(fiber-threshold refuses-no-weights refuses 2 --says "weights: the document has none" -- fiber-threshold --config ${IN}/no-weights.json)
tp_cli_test(fiber-threshold refuses-zero-weights refuses 2 --says "weights: every weight is zero" -- fiber-threshold --electrodes 2 --weights 0,0)
tp_cli_test(fiber-threshold refuses-weight-count refuses 2 --says "weights: expected 8 values (one per electrode), got 2" -- fiber-threshold --weights 1,-1)
tp_cli_test(fiber-threshold refuses-empty-stdin refuses 2 --says "--config: stdin is empty" -- fiber-threshold)
tp_cli_test(fiber-threshold refuses-stimulus-over-limit refuses 2 --says "channel 2: current 2.5 mA exceeds the limit of 2 mA" -- fiber-threshold --config ${IN}/sai-weights.json --stimulus ${IN}/stimulus-over-limit.json)
tp_cli_test(fiber-threshold refuses-stimulus-unbalanced refuses 2 --says "channel currents sum to 0.1 mA, not 0" -- fiber-threshold --config ${IN}/sai-weights.json --stimulus ${IN}/stimulus-unbalanced.json)
tp_cli_test(fiber-threshold refuses-stimulus-other-weights refuses 2 --says "--stimulus: its currents are not the weights times one amplitude" -- fiber-threshold --config ${IN}/sai-optimum.json --stimulus ${IN}/sai-stimulus.json)
tp_cli_test(fiber-threshold refuses-stimulus-and-width refuses 2 --says "--stimulus excludes --width" -- fiber-threshold --config ${IN}/sai-weights.json --stimulus ${IN}/sai-stimulus.json --width 100)
tp_cli_test(fiber-threshold refuses-zero-width refuses 2 --says "--width: 0 us outside [1, 10000] us" -- fiber-threshold --config ${IN}/sai-weights.json --width 0)
tp_cli_test(fiber-threshold refuses-huge-width refuses 2 --says "--width: 1000000 us outside [1, 10000] us" -- fiber-threshold --config ${IN}/sai-weights.json --width 1e6)
tp_cli_test(fiber-threshold refuses-nan-gap refuses 2 --says "--interphase: non-finite number 'nan'" -- fiber-threshold --config ${IN}/sai-weights.json --interphase nan)
tp_cli_test(fiber-threshold refuses-tolerance refuses 2 --says "--tolerance: 0.5 outside [0.0001, 0.1]" -- fiber-threshold --config ${IN}/sai-weights.json --tolerance 0.5)
# The text as given, not the number it reads as (lib/requests/fibre_options: tolerance_text).
tp_cli_test(fiber-threshold refuses-tolerance-as-given refuses 2 --says "--tolerance: 0.50 outside [0.0001, 0.1]" -- fiber-threshold --config ${IN}/sai-weights.json --tolerance 0.50)
tp_cli_test(fiber-threshold refuses-offsets refuses 2 --says "--offsets: 0 outside [1, 64]" -- fiber-threshold --config ${IN}/sai-weights.json --offsets 0)
tp_cli_test(fiber-threshold refuses-threads refuses 2 --says "--threads: 0 outside [1, 256]" -- fiber-threshold --config ${IN}/sai-weights.json --threads 0)
tp_cli_test(fiber-threshold refuses-widths-alone refuses 2 --says "--widths: applies to --strength-duration only" -- fiber-threshold --config ${IN}/sai-weights.json --widths 100)
tp_cli_test(fiber-threshold refuses-bad-widths refuses 2 --says "--widths: 0 us outside [1, 10000] us" -- fiber-threshold --config ${IN}/sai-weights.json --strength-duration --widths 100,0)
tp_cli_test(fiber-threshold refuses-layered-too-deep refuses 2 --says "receptor PC: depth 6 mm is below the skin model's validity" -- fiber-threshold --config ${IN}/layered-receptor-too-deep.json)
tp_cli_test(fiber-threshold refuses-skin-without-layered refuses 2 --says "--skin: applies to the layered model only" -- fiber-threshold --config ${IN}/sai-weights.json --skin fingertip)
tp_cli_test(fiber-threshold refuses-fibre-too-long refuses 2 --says "receptor SAI: its fibre would need 4787 nodes (at most 2000)" -- fiber-threshold --config ${IN}/fibre-too-long.json)
tp_cli_test(fiber-threshold refuses-derived-balance refuses 2 --says "--widths: 2000 us gives a balancing phase of 20000 us, outside [1, 10000] us" -- fiber-threshold --config ${IN}/sai-weights.json --strength-duration --width 100 --balance-width 1000)
tp_cli_test(fiber-threshold refuses-stdin-twice refuses 2 --stdin ${IN}/sai-stimulus.json --says "the weights document (no --config) and --stimulus - both read stdin" -- fiber-threshold --stimulus -)

# Golden output: the paper's SAI optimum under MRG and SENN, and a strength-duration table.
tp_cli_test(fiber-threshold golden-sai-mrg golden fiber-threshold/sai-mrg.json --rtol 1e-9 --
  fiber-threshold --config ${IN}/sai-optimum.json)
tp_cli_test(fiber-threshold golden-sai-senn golden fiber-threshold/sai-senn.json --rtol 1e-9 --
  fiber-threshold --config ${IN}/sai-optimum.json --model senn --offsets 4)
tp_cli_test(fiber-threshold golden-sd golden fiber-threshold/sd.csv --rtol 1e-9 --
  fiber-threshold --config ${IN}/sai-weights.json --strength-duration --widths 50,200,1000 --monophasic --offsets 2)

# Scripted checks: determinism, threads, no threshold below 100 mA, the stimulus multiples.
foreach(script deterministic no-threshold primary stimulus shaped plot-sd)
  tp_cli_test(fiber-threshold ${script} script ${CMAKE_CURRENT_SOURCE_DIR}/fiber-threshold/${script}.sh)
endforeach()

# Issue 20.  A buried point3d source on a fibre's path (here the RA fibre's deepest node) is
# bad input, in fiber-threshold and in optimize-weights --objective threshold, not an abort
# in a worker thread (item 4; the worker's exceptions: unit test "[threads]").
tp_cli_test(fiber-threshold refuses-source-on-fibre-path refuses 2 --says "from receptor RA's vertical fibre"
  --stdin ${IN}/point3d-source-on-ra-tail.json -- fiber-threshold)
tp_cli_test(fiber-threshold refuses-objective-source-on-fibre-path refuses 2 --says "too near its path" --
  optimize-weights --mode SAI --objective threshold --config ${IN}/point3d-source-on-ra-tail-2.json)
# The whole work is estimated before any and bounded (item 7): the issue's 33-minute run,
# and a strength-duration table, refused at once.
tp_cli_test(fiber-threshold refuses-work-over-bound refuses 2 --says "compartment-steps of fibre simulation, more than the bound of 5e+10" --
  fiber-threshold --config ${IN}/fibre-work-over-bound.json --offsets 40 --tolerance 1e-4 --width 1 --balance-width 10000 --interphase 10000)
tp_cli_test(fiber-threshold refuses-sd-work-over-bound refuses 2 --says "--strength-duration (7 widths): an estimated" --
  fiber-threshold --config ${IN}/fibre-work-over-bound.json --strength-duration)
# stdin is read once: --config - with --stimulus - (or --skin -) is refused up front (item 10).
tp_cli_test(fiber-threshold refuses-config-and-stimulus-stdin refuses 2 --says "--config - and --stimulus - both read stdin"
  --stdin ${IN}/sai-stimulus.json -- fiber-threshold --config - --stimulus -)

# In-range layered input the Hankel rule cannot evaluate (a 5 um top layer, fibres 0.02 mm
# deep, up to 550 mm from an electrode) is refused before any work, in every program that
# evaluates fibres (issue 20, item 6, as a class): fiber-threshold's simulated fibres, the
# threshold search, the AF optimisation's samples (af-field: af-field.cmake).
set(FAR ${IN}/layered-far-shallow.json --skin ${IN}/skin-thin-5um.json)
tp_cli_test(fiber-threshold refuses-layered-far-shallow refuses 2 --says "receptor SAI's simulated fibre at depth 0.02 mm" --
  fiber-threshold --config ${FAR})
tp_cli_test(fiber-threshold refuses-objective-layered-far-shallow refuses 2 --says "receptor SAI's fibres at depth 0.02 mm" --
  optimize-weights --mode SAI --objective threshold --config ${FAR})
tp_cli_test(fiber-threshold refuses-optimize-layered-far-shallow refuses 2 --says "would need a Hankel rule" --
  optimize-weights --mode PC --config ${FAR})
# A buried point3d source nearer to a receptor's fibres than the smallest depth (0.01 mm) is
# refused by every program (the AF bound of docs/document-format.md holds everywhere); a
# simulated fibre keeps one internode (refuses-source-on-fibre-path).
tp_cli_test(fiber-threshold refuses-optimize-source-near-fibres refuses 2 --says "0.005 mm from receptor SAI's fibres" --
  optimize-weights --mode SAI --config ${IN}/point3d-source-near-sai.json)
tp_cli_test(fiber-threshold refuses-source-near-fibres refuses 2 --says "nearer than the smallest depth" --
  fiber-threshold --config ${IN}/point3d-source-near-sai.json)
# The threshold search's whole work is bounded too (1e12), before any simulation, and the
# message names the setting to lower first.
tp_cli_test(fiber-threshold refuses-search-work-over-bound refuses 2 --says "bound of 1e+12 (fewer --max-evaluations" --
  optimize-weights --mode SAI --objective threshold --max-evaluations 10000 --offsets 64)
# 2-D arrays: the fibres pass through a point, --at or the document's focus
# (optimize-weights --at); without one, or outside the pads and margin, refused.
tp_cli_test(fiber-threshold refuses-2d-array-without-point refuses 2 --says "is 2-D: give the point the fibres pass through" -- fiber-threshold --grid 2x2 --weights 1,-1,0,0)
tp_cli_test(fiber-threshold refuses-2d-point-outside refuses 2 --says "outside the pads plus the lateral margin" -- fiber-threshold --grid 2x2 --weights 1,-1,0,0 --at 0,20)
tp_cli_test(fiber-threshold refuses-at-on-1d-array refuses 2 --says "--at: applies to 2-D arrays only" -- fiber-threshold --weights 0,0,-1,1,0,0,0,0 --at 0,0)
tp_cli_test(fiber-threshold refuses-at-malformed refuses 2 --says "--at: expected X,Z" -- fiber-threshold --grid 2x2 --weights 1,-1,0,0 --at 1)
tp_cli_test(fiber-threshold pixel-2d script ${CMAKE_CURRENT_SOURCE_DIR}/fiber-threshold/pixel-2d.sh)
tp_cli_test(fiber-threshold population script ${CMAKE_CURRENT_SOURCE_DIR}/fiber-threshold/population.sh)
set_tests_properties(fiber-threshold.population PROPERTIES TIMEOUT 300 PROCESSORS 2)
# No threshold from a cut end (docs/fibres.md, "Cut ends"): one anodic pad, and a small
# population on the layered fingertip.
tp_cli_test(fiber-threshold cut-ends script ${CMAKE_CURRENT_SOURCE_DIR}/fiber-threshold/cut-ends.sh)
set_tests_properties(fiber-threshold.cut-ends PROPERTIES PROCESSORS 2)
# --geometry afferent (docs/fibres.md, "Afferent geometry"): what it cannot build.
tp_cli_test(fiber-threshold refuses-unknown-geometry refuses 2 --stdin ${IN}/sai-weights.json --says "--geometry: unknown fibre geometry 'bent'" -- fiber-threshold --geometry bent)
tp_cli_test(fiber-threshold refuses-afferent-senn refuses 2 --says "senn: no afferent geometry" --stdin ${IN}/sai-weights.json -- fiber-threshold --model senn --geometry afferent)
tp_cli_test(fiber-threshold refuses-afferent-short-range refuses 2 --says "cannot hold the ending" -- fiber-threshold --config ${IN}/ra-short-range.json --geometry afferent)
