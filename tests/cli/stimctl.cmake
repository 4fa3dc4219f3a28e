tp_cli_smoke(stimctl)
tp_cli_smoke(stim-emu)
set(IN ${CMAKE_CURRENT_SOURCE_DIR}/inputs)

# Refused before anything is started (the pty scripts check that nothing is delivered).
tp_cli_test(stimctl refuses-malformed-json refuses 2 --stdin ${IN}/malformed.json -- stimctl --port emu)
tp_cli_test(stimctl refuses-weights-document refuses 2 --stdin ${IN}/sai-weights.json -- stimctl --port emu)
tp_cli_test(stimctl refuses-over-limit refuses 2 --stdin ${IN}/stimulus-over-limit.json -- stimctl --port emu)
tp_cli_test(stimctl refuses-unbalanced refuses 2 --stdin ${IN}/stimulus-unbalanced.json -- stimctl --port emu)
tp_cli_test(stimctl refuses-live-without-stimulus refuses 2 -- stimctl --port emu --live)
tp_cli_test(stimctl refuses-missing-port refuses 2 --stdin ${IN}/stimulus-unbalanced.json -- stimctl --port /dev/tp-no-such-port)
tp_cli_test(stimctl refuses-bad-duration refuses 2 --stdin ${IN}/stimulus-unbalanced.json -- stimctl --port emu --duration -1)
tp_cli_test(stim-emu refuses-bad-fraction refuses 2 -- stim-emu --drop 2)

foreach(script pipeline-emu pty-pipeline pty-libserialport pty-refusals pty-faults pty-watchdog pty-signals
               pty-live pty-lost-device list-ports)
  tp_cli_test(stimctl ${script} script ${CMAKE_CURRENT_SOURCE_DIR}/stimctl/${script}.sh)
  set_tests_properties(stimctl.${script} PROPERTIES TIMEOUT 120)
endforeach()
