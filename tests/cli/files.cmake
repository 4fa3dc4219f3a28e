# Files complete or absent (issue 38, finding 8; docs/programs.md, "Files"; label files):
# --output of every program that writes one document, fiber-threshold's --recruitment
# through SIGINT and SIGTERM, records and logs on a full device and after SIGKILL.
tp_cli_test(files output script ${CMAKE_CURRENT_SOURCE_DIR}/files/output.sh)
set_tests_properties(files.output PROPERTIES LABELS
  "cli;files;af-field;optimize-weights;fiber-threshold;make-pulse;mix-stimuli;render-tactile")
tp_cli_test(files recruitment-signals script ${CMAKE_CURRENT_SOURCE_DIR}/files/recruitment-signals.sh)
set_tests_properties(files.recruitment-signals PROPERTIES LABELS "cli;files;fiber-threshold"
  PROCESSORS 2)
tp_cli_test(files records script ${CMAKE_CURRENT_SOURCE_DIR}/files/records.sh)
set_tests_properties(files.records PROPERTIES LABELS "cli;files;stimctl;stim-emu")
