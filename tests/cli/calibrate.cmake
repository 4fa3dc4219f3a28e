# calibrate: a real terminal (tmux) with a scripted observer reading the emulator's record;
# answers from a pipe (a coprocess observer); a device below the ceiling; its files;
# refusals.  On the render-tactile fixture's 8 x 8 bank.
tp_cli_smoke(calibrate)
foreach(script tmux responses device files)
  tp_cli_test(calibrate ${script} script ${CMAKE_CURRENT_SOURCE_DIR}/calibrate/${script}.sh)
  set_tests_properties(calibrate.${script} PROPERTIES
    ENVIRONMENT "${TP_CLI_ENV};TP_RENDER_BANK=${TP_RENDER_BANK}" FIXTURES_REQUIRED render-bank
    TIMEOUT 300)
endforeach()
# The observer's timing: alone, so that a loaded machine does not make it miss a prompt.
set_tests_properties(calibrate.tmux PROPERTIES RUN_SERIAL TRUE)
