# render-tactile: still images on the emulators (and the firmware in QEMU), the pulse
# budget, sequences (the README's animation), the PNGs people make, refusals.  The scripts
# share one 8 x 8 bank, made once by a fixture.
tp_cli_smoke(render-tactile)
set(TP_RENDER_BANK ${CMAKE_CURRENT_BINARY_DIR}/render/bank8.json)
tp_cli_test(render-tactile bank script ${CMAKE_CURRENT_SOURCE_DIR}/render-tactile/make-bank.sh)
set_tests_properties(render-tactile.bank PROPERTIES
  ENVIRONMENT "${TP_CLI_ENV};TP_RENDER_BANK=${TP_RENDER_BANK}" FIXTURES_SETUP render-bank
  PROCESSORS 2)
foreach(script still budget sequence refusals profile-units model-profile pictures animation gamut)
  tp_cli_test(render-tactile ${script} script ${CMAKE_CURRENT_SOURCE_DIR}/render-tactile/${script}.sh)
  set_tests_properties(render-tactile.${script} PROPERTIES
    ENVIRONMENT "${TP_CLI_ENV};TP_RENDER_BANK=${TP_RENDER_BANK}" FIXTURES_REQUIRED render-bank
    TIMEOUT 300)
endforeach()
# The still image on the firmware in QEMU (its 8 channels: a 4 x 2 grid's bank).
if(NOT TP_SANITIZE)
  add_test(NAME firmware.render-still COMMAND ${TP_CHECK} script ${CMAKE_CURRENT_SOURCE_DIR}/render-tactile/still.sh)
  set_tests_properties(firmware.render-still PROPERTIES
    ENVIRONMENT "${TP_CLI_ENV};TP_DEVICE=firmware;TP_FIRMWARE=${TP_FIRMWARE_ELF}"
    LABELS "firmware" RUN_SERIAL TRUE TIMEOUT 300 SKIP_RETURN_CODE 77)
endif()
