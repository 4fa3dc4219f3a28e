tp_cli_smoke(af-field)

# Bad input: one line on stderr, exit 2, nothing on stdout.
tp_cli_test(af-field refuses-unknown-flag refuses 2 --says "The following argument was not expected: --bogus" -- af-field --bogus)
tp_cli_test(af-field refuses-bad-number refuses 2 --says "--pitch: not a number '1x'" -- af-field --pitch 1x)
tp_cli_test(af-field refuses-nan-pitch refuses 2 --says "--pitch: non-finite number 'nan'" -- af-field --pitch nan)
tp_cli_test(af-field refuses-inf-weight refuses 2 --says "--weights item 2: non-finite number 'inf'" -- af-field --electrodes 2 --weights 1,inf)
tp_cli_test(af-field refuses-weight-count refuses 2 --says "--weights: expected 3 values (one per electrode), got 2" -- af-field --electrodes 3 --weights 1,-1)
tp_cli_test(af-field refuses-zero-pitch refuses 2 --says "--pitch: 0 mm outside [0.01, 100] mm" -- af-field --pitch 0)
tp_cli_test(af-field refuses-negative-pitch refuses 2 --says "--pitch: -1 mm outside [0.01, 100] mm" -- af-field --pitch -1)
tp_cli_test(af-field refuses-fractional-count refuses 2 --says "--electrodes: not a whole number '2.5'" -- af-field --electrodes 2.5)
tp_cli_test(af-field refuses-zero-electrodes refuses 2 --says "--electrodes: need at least 1, got 0" -- af-field --electrodes 0 --weights 1)
tp_cli_test(af-field refuses-empty-grid refuses 2 --says "--x: empty grid (MAX < MIN)" -- af-field --x 1:0:0.1)
tp_cli_test(af-field refuses-zero-step refuses 2 --says "--x: STEP must be > 0" -- af-field --x 0:1:0)
tp_cli_test(af-field refuses-bad-grid refuses 2 --says "--y: expected MIN:MAX:STEP, got '0.5:2'" -- af-field --y 0.5:2)
tp_cli_test(af-field refuses-surface-depth refuses 2 --says "--y: depths must be > 0 mm" -- af-field --y 0:1:0.1)
tp_cli_test(af-field refuses-negative-depth refuses 2 --says "--y: depths must be > 0 mm" -- af-field --y -1:1:0.1)
tp_cli_test(af-field refuses-missing-config refuses 2 --says "--config: cannot open '/nonexistent.json'" -- af-field --config /nonexistent.json)
tp_cli_test(af-field refuses-malformed-json refuses 2 --stdin ${CMAKE_CURRENT_SOURCE_DIR}/inputs/malformed.json --says "--config: malformed JSON in stdin: parse error" -- af-field --config -)
tp_cli_test(af-field refuses-empty-stdin refuses 2 --says "--config: stdin is empty" -- af-field --config -)
tp_cli_test(af-field refuses-config-weight-count refuses 2 --stdin ${CMAKE_CURRENT_SOURCE_DIR}/inputs/wrong-weight-count.json --says "weights: expected 4 values, got 3" -- af-field --config -)
tp_cli_test(af-field refuses-config-and-flags refuses 2 --says "--config excludes --pitch" -- af-field --config - --pitch 1)
tp_cli_test(af-field refuses-unknown-model refuses 2 --says "--model: unknown conductor model 'foo'" -- af-field --model foo)
tp_cli_test(af-field refuses-range-plane-z refuses 2 --says "--z: 1000000 mm outside [-500, 500] mm" -- af-field --model rect3d --z 1e6)
tp_cli_test(af-field refuses-nan-plane-z refuses 2 --says "--z: non-finite number 'nan'" -- af-field --model rect3d --z nan)
tp_cli_test(af-field refuses-config-plane-z refuses 2 --stdin ${CMAKE_CURRENT_SOURCE_DIR}/inputs/range-plane-z.json --says "model.plane_z_mm: 1000000 mm outside [-500, 500] mm" -- af-field --config -)
tp_cli_test(af-field refuses-source-among-fibres refuses 2 --stdin ${CMAKE_CURRENT_SOURCE_DIR}/inputs/point3d-source-among-fibres.json --says "model.source_depth_mm: 1 mm is 0 mm from receptor RA's fibres" -- af-field --config - --summary)
tp_cli_test(af-field refuses-rect3d-zero-width refuses 2 --stdin ${CMAKE_CURRENT_SOURCE_DIR}/inputs/rect3d-zero-width.json --says "rect3d: array.width_mm must be > 0" -- af-field --config - --summary)
tp_cli_test(af-field refuses-summary-with-grid refuses 2 --says "--summary: --x, --y and --plane-depth do not apply" -- af-field --summary --x 0:1:1)
# The layered model: bad skin files, a skin without the model, depths below its validity,
# overlapping electrodes.
set(says_zero-thickness "layers[0].thickness_mm: must be > 0, got 0")
set(says_negative-resistivity "layers[0].resistivity_ohm_m: must be > 0, got -1500")
set(says_no-layers "'layers' must be a non-empty array (no layers given)")
foreach(bad zero-thickness negative-resistivity no-layers)
  tp_cli_test(af-field refuses-skin-${bad} refuses 2 --says "${says_${bad}}" --
    af-field --model layered --skin ${CMAKE_CURRENT_SOURCE_DIR}/inputs/skin-${bad}.json --summary)
endforeach()
tp_cli_test(af-field refuses-missing-skin refuses 2 --says "--skin: cannot open '/nonexistent.json'" -- af-field --model layered --skin /nonexistent.json)
tp_cli_test(af-field refuses-unknown-skin refuses 2 --says "--skin: 'palm' is neither a built-in skin" -- af-field --model layered --skin palm)
tp_cli_test(af-field refuses-skin-without-layered refuses 2 --says "--skin: applies to the layered model only" -- af-field --skin fingertip-dry)
tp_cli_test(af-field refuses-layered-receptor-too-deep refuses 2 --stdin ${CMAKE_CURRENT_SOURCE_DIR}/inputs/layered-receptor-too-deep.json --says "receptor PC: depth 6 mm is below the skin model's validity" -- af-field --config - --summary)
tp_cli_test(af-field refuses-layered-grid-too-deep refuses 2 --says "--y: the deepest row, 6 mm is below the skin model's validity" -- af-field --model layered --y 0.2:6:0.1)
tp_cli_test(af-field refuses-layered-overlap refuses 2 --says "array: electrodes overlap" -- af-field --model layered --pitch 0.3)

# Golden files (scripts/regen-golden rewrites them).
tp_cli_test(af-field golden-one-cathode-csv golden af-field/one-cathode.csv --
  af-field --electrodes 8 --pitch 1 --weights 0,0,0,1,0,0,0,0 --x -5:5:0.5 --y 0.25:3:0.25)
tp_cli_test(af-field golden-sai-pattern-csv golden af-field/sai-pattern.csv --
  af-field --electrodes 8 --pitch 1 --weights 0,0,-0.5,1,-0.5,0,0,0 --x -4:4:0.2 --y 0.5:2.5:0.5)
# Peak positions are found to ~1e-8 mm (the AF is flat at a maximum): --rtol 1e-6, and
# --atol 1e-6 where one lies at 0.
tp_cli_test(af-field golden-default-summary golden af-field/default-summary.json --rtol 1e-6 --
  af-field --summary)
tp_cli_test(af-field golden-config-summary golden af-field/config-summary.json --rtol 1e-6 --atol 1e-6
  --stdin ${CMAKE_CURRENT_SOURCE_DIR}/inputs/pc-pattern.json -- af-field --config - --summary)
tp_cli_test(af-field golden-strip2d-summary golden af-field/strip2d-summary.json --rtol 1e-6 --atol 1e-6 --
  af-field --model strip2d --weights -1,-1,1,1,1,1,-1,-1 --summary)
foreach(model rect3d point3d)
  tp_cli_test(af-field golden-${model}-csv golden af-field/${model}-sai.csv --
    af-field --model ${model} --weights 0,0,-0.5,1,-0.5,0,0,0 --x -4:4:0.5 --y 0.5:2.5:0.5)
  tp_cli_test(af-field golden-${model}-summary golden af-field/${model}-summary.json --rtol 1e-6 --
    af-field --model ${model} --z 1 --weights 0.3,-0.9,1.2,0.4,-1.5,0.8,-0.6,0.3 --summary)
endforeach()

tp_cli_test(af-field golden-layered-csv golden af-field/layered-sai.csv --
  af-field --model layered --weights 0,0,-0.5,1,-0.5,0,0,0 --x -4:4:0.5 --y 0.5:2.5:0.5)
tp_cli_test(af-field golden-layered-dry-summary golden af-field/layered-dry-summary.json --rtol 1e-6 --
  af-field --model layered --skin fingertip-dry --z 1 --weights 0.3,-0.9,1.2,0.4,-1.5,0.8,-0.6,0.3 --summary)
tp_cli_test(af-field golden-layered-inline-skin golden af-field/layered-inline-skin.json --rtol 1e-6
  --stdin ${CMAKE_CURRENT_SOURCE_DIR}/inputs/layered-inline-skin.json -- af-field --config - --summary)

# Scripted checks.
tp_cli_test(af-field eq23-single-electrode script ${CMAKE_CURRENT_SOURCE_DIR}/af-field/eq23.sh)
tp_cli_test(af-field deterministic script ${CMAKE_CURRENT_SOURCE_DIR}/af-field/deterministic.sh)
tp_cli_test(af-field config-equals-flags script ${CMAKE_CURRENT_SOURCE_DIR}/af-field/config-equals-flags.sh)
tp_cli_test(af-field plot-field script ${CMAKE_CURRENT_SOURCE_DIR}/af-field/plot.sh)

# Issue 20: no non-finite value and no half-written grid.  A grid row through a buried
# point3d source is refused, naming the point (item 5); a 5 um top layer far from the
# electrodes works, and what the Hankel rule cannot evaluate is refused before the first row
# (item 6, the script).
tp_cli_test(af-field refuses-grid-through-source refuses 2 --says "grid point (-1, 3) mm is 0 mm from a point source" --
  af-field --config ${CMAKE_CURRENT_SOURCE_DIR}/inputs/point3d-source-below-receptors.json --x -2:2:1 --y 3:3:1)
tp_cli_test(af-field thin-layer script ${CMAKE_CURRENT_SOURCE_DIR}/af-field/thin-layer.sh)
# The fibre regions af-field --summary evaluates, the same way (fiber-threshold.cmake).
tp_cli_test(af-field refuses-summary-layered-far-shallow refuses 2 --says "receptor SAI's fibres at depth 0.02 mm" --
  af-field --summary --config ${CMAKE_CURRENT_SOURCE_DIR}/inputs/layered-far-shallow.json
  --skin ${CMAKE_CURRENT_SOURCE_DIR}/inputs/skin-thin-5um.json)
# A buried source keeps the smallest depth (0.01 mm) from every receptor's fibres and every
# grid point (in the plane, or out of it by --z), not only 1e-9 mm.
tp_cli_test(af-field refuses-source-near-fibres refuses 2 --says "0.005 mm from receptor SAI's fibres" --
  af-field --summary --config ${CMAKE_CURRENT_SOURCE_DIR}/inputs/point3d-source-near-sai.json)
tp_cli_test(af-field refuses-grid-near-source refuses 2 --says "grid point (-1, 2.995) mm is 0.005 mm from a point source" --
  af-field --config ${CMAKE_CURRENT_SOURCE_DIR}/inputs/point3d-source-below-receptors.json --x -2:2:1 --y 2.995:2.995:1)
tp_cli_test(af-field refuses-grid-near-source-off-plane refuses 2 --says "is 0.005 mm from a point source" --
  af-field --config ${CMAKE_CURRENT_SOURCE_DIR}/inputs/point3d-source-below-receptors.json --z 0.005 --x -2:2:1 --y 3:3:1)

# 2-D arrays (issue 21): a grid's summary and its plane map; the 2-D models and bad layouts
# refused.
tp_cli_test(af-field golden-grid-summary golden af-field/grid-summary.json --rtol 1e-6 --
  af-field --grid 4x3 --pitch 2 --row-pitch 1.5 --pad 1x1
  --weights 0.3,-1,0.2,0.5,0.1,1,-0.7,0.4,-0.2,0.6,-0.9,0.8 --summary)
tp_cli_test(af-field golden-grid-plane golden af-field/grid-plane.csv --
  af-field --config ${CMAKE_CURRENT_SOURCE_DIR}/inputs/pads-point3d.json --plane-depth 0.9
  --x -3:3:0.5 --z-grid -2:2:0.5)
tp_cli_test(af-field refuses-grid-line2d refuses 2 --says "takes no 2-D array" --
  af-field --grid 2x2 --model line2d --summary)
# A grid on the layered skin: the summary, and a plane map at SAI's depth (corner tables).
tp_cli_test(af-field golden-grid-layered-summary golden af-field/grid-layered-summary.json --rtol 1e-6 --
  af-field --grid 3x2 --pitch 2 --model layered --weights 1,-0.5,0,-0.5,0.2,-0.2 --summary)
tp_cli_test(af-field golden-grid-layered-plane golden af-field/grid-layered-plane.csv --
  af-field --grid 3x2 --pitch 2 --model layered --weights 1,-0.5,0,-0.5,0.2,-0.2
  --plane-depth 0.9 --x -4:4:1 --z-grid -3:3:1)
tp_cli_test(af-field refuses-grid-too-many refuses 2 --says "--grid: 272 pads, at most 256" -- af-field --grid 16x17)
tp_cli_test(af-field refuses-grid-form refuses 2 --says "--grid: expected COLUMNSxROWS, e.g. 8x8, got '8'" -- af-field --grid 8)
tp_cli_test(af-field refuses-grid-zero refuses 2 --says "--grid: 0 outside [1, 256]" -- af-field --grid 0x3)
tp_cli_test(af-field refuses-grid-and-electrodes refuses 2 --says "--electrodes excludes --grid" -- af-field --grid 2x2 --electrodes 4)
tp_cli_test(af-field refuses-grid-overlap refuses 2 --says "array: pads 0 (-0.5, -0.5) and 1 (0.5, -0.5) mm overlap" -- af-field --grid 2x2 --pad 1.5x0.5)
tp_cli_test(af-field refuses-pad-without-grid refuses 2 --says "--pad: applies to --grid only" -- af-field --pad 1x1)
tp_cli_test(af-field refuses-pads-overlap refuses 2
  --stdin ${CMAKE_CURRENT_SOURCE_DIR}/inputs/pads-overlap.json --says "array: pads 0 (0, 0) and 1 (0.5, 0.5) mm overlap" -- af-field --config - --summary)
tp_cli_test(af-field refuses-plane-under-line2d refuses 2 --says "--plane-depth: line2d does not evaluate points off the fibres' plane" -- af-field --plane-depth 0.9)
tp_cli_test(af-field refuses-plane-depth-range refuses 2 --says "--plane-depth: 0 mm outside [0.01, 20] mm" -- af-field --grid 2x2 --plane-depth 0)
tp_cli_test(af-field refuses-z-grid-alone refuses 2 --says "--z-grid: applies with --plane-depth only" -- af-field --grid 2x2 --z-grid 0:1:0.5)
tp_cli_test(af-field refuses-plane-with-summary refuses 2 --says "--summary: --x, --y and --plane-depth do not apply" -- af-field --grid 2x2 --plane-depth 1 --summary)
tp_cli_test(af-field refuses-plane-on-source refuses 2
  --stdin ${CMAKE_CURRENT_SOURCE_DIR}/inputs/pads-point3d.json --says "grid point (-1, 0) mm at depth 0.5 mm is 0 mm from a point source" -- af-field --config -
  --model point3d --plane-depth 0.5 --x -3:3:0.5 --z-grid -2:2:0.5)
tp_cli_test(af-field golden-grid-zero-weights golden af-field/grid-zero-summary.json --
  af-field --grid 8x1 --weights 0,0,0,0,0,0,0,0 --summary)
tp_cli_test(af-field refuses-z-with-grid-summary refuses 2 --says "--z: does not apply" --
  af-field --grid 2x2 --z 3 --summary)
tp_cli_test(af-field refuses-z-with-plane refuses 2 --says "--z: does not apply" --
  af-field --model rect3d --z 1 --plane-depth 1)
tp_cli_test(af-field refuses-grid-work refuses 2 --says "pad evaluations to find their largest AF, more than the bound of 2000000000" --
  af-field --grid 16x16 --pitch 18 --summary)
tp_cli_test(af-field refuses-plane-work refuses 2 --says "pad evaluations, more than 6400000000" --
  af-field --grid 16x16 --pitch 2 --plane-depth 1 --x -500:500:0.02 --z-grid -500:500:1)
