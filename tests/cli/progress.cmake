# Progress on a terminal (issue 38, finding 11; label progress): optimize-weights --bank and
# --objective threshold, fiber-threshold --population and --strength-duration, through a
# pseudo-terminal; nothing more than the summary when stderr is not one.
tp_cli_test(progress terminal script ${CMAKE_CURRENT_SOURCE_DIR}/progress/terminal.sh)
set_tests_properties(progress.terminal PROPERTIES LABELS
  "cli;progress;optimize-weights;fiber-threshold" PROCESSORS 2)
