# A document on stdin describes the same thing as the equivalent flags.
af-field --electrodes 8 --pitch 1 --weights -0.5,-0.5,0.5,0.5,0.5,0.5,-0.5,-0.5 --summary > flags.json
af-field --config - --summary < "$TP_INPUTS/pc-pattern.json" > config.json
golden-diff flags.json config.json || fail "config and flags disagree"
af-field --electrodes 8 --pitch 1 --weights -0.5,-0.5,0.5,0.5,0.5,0.5,-0.5,-0.5 --x -2:2:0.5 --y 1:2:0.5 > flags.csv
af-field --config "$TP_INPUTS/pc-pattern.json" --x -2:2:0.5 --y 1:2:0.5 > config.csv
cmp flags.csv config.csv || fail "CSV from config and flags differ"
echo "ok"
