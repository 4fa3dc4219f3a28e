# The install tree (cmake --install BUILD --prefix P) as a user gets it: the programs, the
# tp- scripts, data, docs, man pages and bash completion under P, no path into the source
# or build tree compiled in, and the README's main pipeline from P/bin alone.
: "${TP_BUILD:?}"
P=$PWD/P
cmake --install "$TP_BUILD" --prefix "$P" > install.log 2>&1 || fail "install: $(tail -3 install.log)"
for f in bin/af-field bin/optimize-weights bin/make-pulse bin/stimctl bin/stim-emu bin/fiber-threshold bin/mix-stimuli bin/render-tactile bin/calibrate \
         bin/tp-sweep-spacing bin/tp-compare-models bin/tp-plot-field bin/tp-plot-pulse bin/tp-plot-sweep bin/tp-plot-sd bin/tp-plot-render bin/tp-plot-recruitment bin/tp-plot-impedance share/tactile-primaries/images/face-8x8.png \
         share/tactile-primaries/receptors.json share/tactile-primaries/skin/fingertip.json \
         share/doc/tactile-primaries/README.md share/doc/tactile-primaries/docs/document-format.md \
         share/doc/tactile-primaries/docs/img/sai-layered.png share/doc/tactile-primaries/firmware/README.md \
         share/man/man1/af-field.1.gz share/man/man1/stimctl.1.gz share/man/man7/tactile-primaries.7.gz \
         share/man/man1/tp-sweep-spacing.1.gz share/man/man1/tp-plot-sd.1.gz share/bash-completion/completions/tp-sweep-spacing \
         share/bash-completion/completions/af-field share/bash-completion/completions/stimctl; do
  [[ -e $P/$f ]] || fail "not installed: $f"
done
# The documentation is installed as it lies in the source tree: its links work there too.
python3 "$TP_SOURCE/tests/docs/links.py" "$P/share/doc/tactile-primaries" > links.log ||
  fail "installed documentation: $(grep FAIL links.log | head -3)"
# Nothing refers to where it was built: the data are compiled in.  (Debug information
# names the sources by design, and so does AddressSanitizer's instrumentation: the
# sanitizer build skips the check.)
for exe in "$P"/bin/*; do
  grep -qaF __asan_init "$exe" && continue
  copy=$exe
  if [[ $(head -c 4 "$exe") == $'\x7fELF' ]]; then
    strip --strip-debug -o stripped "$exe" || fail "strip $exe"
    copy=stripped
  fi
  if grep -qaF -e "$TP_SOURCE" -e "$TP_BUILD" "$copy"; then fail "$exe names the source or build tree"; fi
done
# The tp- scripts run by absolute path with P not on PATH: they find their programs beside
# themselves (also through a link elsewhere), on every engine that runs here; --help needs
# nothing, and names the installed script, as the man pages made from it do.
bare=(env -u TP_BIN -u TP_BUILD_DIR PATH=/usr/bin:/bin)
"${bare[@]}" "$P/bin/optimize-weights" --mode SAI --electrodes 4 --pitch 1 --format csv 2> /dev/null > want.csv \
  || fail "optimize-weights by absolute path"
mkdir links && ln -s "$P/bin/tp-sweep-spacing" links/tp-sweep-spacing
for sweep in "$P/bin/tp-sweep-spacing" "links/tp-sweep-spacing" "$P/bin/tp-sweep-spacing --engine parallel"; do
  # shellcheck disable=SC2086  # $sweep is words by design
  "${bare[@]}" $sweep --electrodes 4 --pitch 1:1:1 --modes SAI > sweep.csv 2> err.txt || fail "$sweep: $(cat err.txt)"
  cmp -s want.csv sweep.csv || fail "$sweep: $(cat sweep.csv) differs from optimize-weights' $(cat want.csv)"
done
"${bare[@]}" "$P/bin/tp-compare-models" --models line2d --electrodes 4 > models.md 2> err.txt || fail "tp-compare-models: $(cat err.txt)"
grep -F '| line2d | ' models.md > /dev/null || fail "tp-compare-models: $(cat models.md)"
mkdir alone
for s in sweep-spacing compare-models plot-field plot-pulse plot-sweep plot-sd plot-render plot-recruitment plot-impedance; do
  cp "$P/bin/tp-$s" alone/  # without the programs: --help still works
  "${bare[@]}" TP_BIN=/nonexistent "alone/tp-$s" --help > help.txt 2> err.txt || fail "tp-$s --help alone: $(cat err.txt)"
  [[ ! -s err.txt ]] && head -1 help.txt | grep "^tp-$s: " > /dev/null || fail "tp-$s --help: $(head -1 help.txt) $(cat err.txt)"
  ! grep -F "scripts/" help.txt || fail "tp-$s --help names the source tree's scripts"
  page=$(zcat "$P/share/man/man1/tp-$s.1.gz")
  grep -F 'tp\-'"${s//-/\\-}"':' <<< "$page" > /dev/null || fail "tp-$s.1 does not name tp-$s: $(sed -n '/^.SH DESCRIPTION/,+3p' <<< "$page")"
  if grep -e "scripts/" -e "not found" <<< "$page"; then fail "tp-$s.1 names scripts/ or an error"; fi
done
zcat "$P/share/man/man1/tp-compare-models.1.gz" | grep -F 'tp\-compare\-models [\-\-models' > /dev/null || fail "tp-compare-models.1: no usage"
set +e; "${bare[@]}" alone/tp-compare-models > out.txt 2> err.txt; rc=$?; set -e
[[ $rc -eq 1 && ! -s out.txt && $(wc -l < err.txt) -eq 1 ]] && grep -F "optimize-weights not found" err.txt > /dev/null \
  || fail "tp-compare-models without its programs: exit $rc, $(cat err.txt)"
echo "ok: the tp- scripts by absolute path, PATH=/usr/bin:/bin: their programs found beside them; --help and man pages name tp-NAME"
# The programs from P/bin alone (the build's tools are not on this PATH).
export PATH=$P/bin:/usr/bin:/bin
[[ $(af-field --version) == "af-field "* ]] || fail "af-field --version: $(af-field --version)"
optimize-weights --mode SAI 2> /dev/null | make-pulse --amplitude 1.0 --frequency 200 2> /dev/null \
  | stimctl --port emu --duration 0.5 --record rec.jsonl 2> run.err || fail "pipeline: $(cat run.err)"
[[ $(wc -l < rec.jsonl) -eq 100 ]] || fail "pipeline: $(wc -l < rec.jsonl) pulses"
# Man pages: help2man's from --help, and the overview.
if command -v man > /dev/null; then
  MANPATH=$P/share/man man -w af-field | grep -F "$P/share/man/man1/af-field.1.gz" > /dev/null || fail "man -w af-field: $(MANPATH=$P/share/man man -w af-field 2>&1)"
  MANPATH=$P/share/man MANWIDTH=100 man af-field 2> /dev/null | grep -- "--electrodes" > /dev/null || fail "man af-field lacks --electrodes"
  MANPATH=$P/share/man MANWIDTH=100 man 7 tactile-primaries 2> /dev/null | grep "make-pulse --amplitude" > /dev/null || fail "man 7 tactile-primaries"
fi
zcat "$P/share/man/man1/af-field.1.gz" | grep '^\.TH AF-FIELD "1"' > /dev/null || fail "af-field.1 header"
# Bash completion: bash-completion's _longopt for options, and the values it cannot know.
bc=/usr/share/bash-completion/bash_completion
[[ -f $bc ]] || fail "bash-completion is not installed (scripts/setup installs it)"
source "$TP_SOURCE/tests/cli/install/helpers.sh"
complete_words() { complete_words_from "$P/share/bash-completion/completions" "$@"; }
bash -c "source $bc; source $P/share/bash-completion/completions/af-field; complete -p af-field" \
  | grep "complete -F _tactile_primaries" > /dev/null || fail "complete -p af-field"
[[ $(complete_words optimize-weights --mode "" | sort | tr '\n' ' ') == "PC RA SAI " ]] || fail "--mode: $(complete_words optimize-weights --mode "")"
[[ $(complete_words fiber-threshold --model "" | sort | tr '\n' ' ') == "mrg senn " ]] || fail "fiber-threshold --model"
complete_words af-field --ele | grep -x -- "--electrodes" > /dev/null || fail "af-field --ele: $(complete_words af-field --ele)"
complete_words stimctl --port "" | grep -x emu > /dev/null || fail "stimctl --port: $(complete_words stimctl --port "")"
[[ $(complete_words tp-sweep-spacing --engine "" | tr '\n' ' ') == "local parallel slurm " ]] \
  || fail "tp-sweep-spacing --engine: $(complete_words tp-sweep-spacing --engine "")"
complete_words tp-sweep-spacing --ssh | grep -x -- "--sshloginfile" > /dev/null || fail "tp-sweep-spacing --ssh"
echo "ok: installed under P; pipeline from P/bin: $(cat run.err)"
# The Python module from the install tree, outside the source and build trees, with only
# the prefix's directory on PYTHONPATH.
if [[ $TP_PYTHON_BUILT == ON ]]; then
  mkdir elsewhere
  san=()  # an instrumented module (the sanitizer build) needs its runtimes loaded first
  grep -qaF __asan_init "$P/$TP_PYTHON_DIR"/tactile_primaries/_core*.so \
    && san=(LD_PRELOAD="$TP_PYTHON_PRELOAD" ASAN_OPTIONS=detect_leaks=0)
  (cd elsewhere && "${bare[@]}" "${san[@]}" PYTHONPATH="$P/$TP_PYTHON_DIR" /usr/bin/python3 -c '
import tactile_primaries as tp
assert tp.__file__.startswith("'"$P"'/"), tp.__file__
doc = tp.optimize_weights(tp.Document.create(), "SAI")
with tp.Stimulator("emu") as s:
    r = s.deliver(tp.make_pulse(doc, 1.0, 200, duration_s=0.1))
print(tp.__version__, tp.__file__, r["pulses"], "pulses")' > ../py.txt 2> ../err.txt) || fail "the installed Python module: $(cat err.txt)"
  [[ -e $P/$TP_PYTHON_DIR/tactile_primaries/__init__.pyi && -e $P/$TP_PYTHON_DIR/tactile_primaries/py.typed ]] \
    || fail "the Python module's stubs are not installed"
  echo "ok: import tactile_primaries from $P/$TP_PYTHON_DIR: $(cat py.txt)"
fi
