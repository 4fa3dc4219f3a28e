# The same input gives byte-identical output.
af-field --weights 0.3,-1,0.2,1,-0.7,0.1,0.5,-0.4 > a.csv
af-field --weights 0.3,-1,0.2,1,-0.7,0.1,0.5,-0.4 > b.csv
cmp a.csv b.csv || fail "CSV differs between runs"
af-field --weights 0.3,-1,0.2,1,-0.7,0.1,0.5,-0.4 --summary > a.json
af-field --weights 0.3,-1,0.2,1,-0.7,0.1,0.5,-0.4 --summary > b.json
cmp a.json b.json || fail "summary differs between runs"
echo "ok: byte-identical"
