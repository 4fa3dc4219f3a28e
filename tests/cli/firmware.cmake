# The firmware (firmware/stm32f4): its configuration block, its emulator's refusals, and
# the pty suite of tests/cli/stimctl against it in QEMU.
set(FW_SCRIPTS ${PROJECT_SOURCE_DIR}/scripts)
tp_cli_test(firmware-config refuses-9-channels refuses 2 --says "--channels: 9 outside 1 to 8" -- ${FW_SCRIPTS}/firmware-config --channels 9)
tp_cli_test(firmware-config refuses-13-bits refuses 2 --says "--dac-bits: 13 is not 12, 14 or 16" -- ${FW_SCRIPTS}/firmware-config --dac-bits 13)
tp_cli_test(firmware-config refuses-over-current refuses 2 --says "--max-current: 2.001 mA outside [0.001, 2] mA" -- ${FW_SCRIPTS}/firmware-config --max-current 2.001)
tp_cli_test(firmware-config refuses-zero-current refuses 2 --says "--max-current: 0.0001 mA outside [0.001, 2] mA" -- ${FW_SCRIPTS}/firmware-config --max-current 0.0001)
tp_cli_test(firmware-config refuses-not-a-number refuses 2 --says "--max-current: '1e3' is not a number of mA" -- ${FW_SCRIPTS}/firmware-config --max-current 1e3)
tp_cli_test(firmware-config refuses-long-watchdog refuses 2 --says "--watchdog-ms: 1001 outside 10 to 1000 ms" -- ${FW_SCRIPTS}/firmware-config --watchdog-ms 1001)
tp_cli_test(firmware-config refuses-unknown-option refuses 2 --says "unknown option '--seed'" -- ${FW_SCRIPTS}/firmware-config --seed 3)
tp_cli_test(firmware-config bytes script ${CMAKE_CURRENT_SOURCE_DIR}/firmware/config-bytes.sh)
tp_cli_test(firmware-emu refuses-unknown-option refuses 2 --says "unknown option '--port'" -- ${FW_SCRIPTS}/firmware-emu --port x)
tp_cli_test(firmware-emu refuses-missing-firmware refuses 2 --says "no firmware at /nonexistent.elf" -- ${FW_SCRIPTS}/firmware-emu --firmware /nonexistent.elf)
tp_cli_test(stim-emu refuses-forward-with-device-options refuses 2 --says "--channels excludes --forward" -- stim-emu --forward /tmp/x.sock --channels 4)

# The same pty suite against the firmware, booted in QEMU (scripts/firmware-emu), plus the
# monitor's timing checks.  They run alone (RUN_SERIAL): the emulated board keeps to real
# time only with a core to itself.  Without the toolchain or QEMU they are skipped with a
# message, unless TP_REQUIRE_FIRMWARE=1 (CI) makes that a failure.  The sanitizer build
# does not build the firmware and does not repeat them (the host side runs the same suite
# against stim-emu there).
if(NOT TP_SANITIZE)
foreach(script pty-pipeline pty-libserialport pty-refusals pty-faults pty-watchdog pty-signals
               pty-live pty-lost-device pty-protocol pty-session pty-signal-before-start
               pty-device-bounds pty-live-limits pty-timing pty-current-limit pty-replay-keepalive
               pty-rates pty-mix pty-table256 pty-intent pty-gap shaped guards-emu stop-input
               contact-suspend hold-sensation)
  add_test(NAME firmware.${script} COMMAND ${TP_CHECK} script ${CMAKE_CURRENT_SOURCE_DIR}/stimctl/${script}.sh)
  set_tests_properties(firmware.${script} PROPERTIES
    ENVIRONMENT "${TP_CLI_ENV};TP_DEVICE=firmware;TP_FIRMWARE=${TP_FIRMWARE_ELF}"
    LABELS "firmware" RUN_SERIAL TRUE TIMEOUT 300 SKIP_RETURN_CODE 77)
endforeach()
# The device core's scheduling cost on the MCU, bounded (sched_bench.cpp, in QEMU).
add_test(NAME firmware.sched-bench COMMAND ${TP_CHECK} script ${CMAKE_CURRENT_SOURCE_DIR}/firmware/sched-bench.sh)
set_tests_properties(firmware.sched-bench PROPERTIES
  ENVIRONMENT "${TP_CLI_ENV};TP_DEVICE=firmware;TP_FIRMWARE=${TP_FIRMWARE_ELF}"
  LABELS "firmware" RUN_SERIAL TRUE TIMEOUT 120 SKIP_RETURN_CODE 77)
# The other board file builds too (a board is a file, not a fork).
if(TP_ARM_GXX)
  set(dir ${CMAKE_CURRENT_BINARY_DIR}/firmware-stm32f4discovery)
  add_test(NAME firmware.build-stm32f4discovery
    COMMAND bash -c "rm -rf '${dir}' && TP_FIRMWARE_BUILD_DIR='${dir}' '${PROJECT_SOURCE_DIR}/scripts/build-firmware' --board stm32f4discovery")
  set_tests_properties(firmware.build-stm32f4discovery PROPERTIES LABELS "firmware"
    PASS_REGULAR_EXPRESSION "firmware \\(stm32f4discovery\\): flash [0-9]+ bytes")
endif()
endif()

