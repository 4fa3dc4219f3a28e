# docs/validation.md is regenerated: the model's numbers computed again (scripts/validate,
# two to three minutes) match data/validation.json within 1e-6 (golden-diff, which rewrites it
# with TP_REGEN=1), and the page is what that file gives.
TP_BIN="$TP_BUILD/tools" "$TP_SOURCE/scripts/validate" --json now.json --markdown now.md 2> err.txt \
  || fail "scripts/validate: $(cat err.txt)"
golden-diff --rtol 1e-6 --atol 1e-9 "$TP_SOURCE/data/validation.json" now.json \
  || fail "the model's numbers differ from data/validation.json (scripts/regen-golden, then review docs/validation.md)"
if [[ ${TP_REGEN:-0} == 1 ]]; then
  cp now.md "$TP_SOURCE/docs/validation.md"
fi
"$TP_SOURCE/scripts/validate" --render "$TP_SOURCE/data/validation.json" --markdown page.md \
  || fail "scripts/validate --render"
cmp -s page.md "$TP_SOURCE/docs/validation.md" \
  || fail "docs/validation.md is not what data/validation.json gives (scripts/validate --render data/validation.json)"
echo "ok: $(grep -c '^| ' page.md) table rows; $(grep -F 'In short' page.md | cut -c1-120)"
