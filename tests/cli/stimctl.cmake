tp_cli_smoke(stimctl)
tp_cli_smoke(stim-emu)
set(IN ${CMAKE_CURRENT_SOURCE_DIR}/inputs)

# Refused before anything is started (the pty scripts check that nothing is delivered).
# rms-as-quantised: RMS 0.99999999 mA in mA, 1.0003 mA as the DAC makes it (1448 codes of
# 977 nA): the device would refuse it, so the host does first.
tp_cli_test(stimctl refuses-malformed-json refuses 2 --stdin ${IN}/malformed.json --says "stimulus: malformed JSON in stdin: parse error" -- stimctl --port emu)
tp_cli_test(stimctl refuses-weights-document refuses 2 --stdin ${IN}/sai-weights.json --says "(make-pulse's output) or \"tactile-primaries/stimulus/2\" (mix-stimuli's)" -- stimctl --port emu)
tp_cli_test(stimctl refuses-over-limit refuses 2 --stdin ${IN}/stimulus-over-limit.json --says "channel 2: current 2.5 mA exceeds the limit of 2 mA" -- stimctl --port emu)
tp_cli_test(stimctl refuses-unbalanced refuses 2 --stdin ${IN}/stimulus-unbalanced.json --says "channel currents sum to 0.1 mA, not 0" -- stimctl --port emu)
tp_cli_test(stimctl refuses-rms-as-quantised refuses 2 --stdin ${IN}/stimulus-rms-as-quantised.json --says "as the DAC makes them" -- stimctl --port emu)
tp_cli_test(stimctl refuses-live-without-stimulus refuses 2 --says "--live: give the stimulus with --stimulus FILE" -- stimctl --port emu --live)
tp_cli_test(stimctl refuses-missing-port refuses 2 --stdin ${IN}/stimulus-ok.json --says "--port: no serial port '/dev/tp-no-such-port'" -- stimctl --port /dev/tp-no-such-port)
tp_cli_test(stimctl refuses-bad-duration refuses 2 --stdin ${IN}/stimulus-ok.json --says "--duration: -1 s outside (0, 3600" -- stimctl --port emu --duration -1)
tp_cli_test(stim-emu refuses-bad-fraction refuses 2 --says "--drop: 2 outside [0, 1]" -- stim-emu --drop 2)
# The device's limits are compile-time bounds that configuration can lower, never raise.
tp_cli_test(stim-emu refuses-current-above-bound refuses 2 --says "--max-current: 30 mA outside [0.001, 2] mA" -- stim-emu --max-current 30)
tp_cli_test(stim-emu refuses-current-just-above-bound refuses 2 --says "--max-current: 2.001 mA outside [0.001, 2] mA" -- stim-emu --max-current 2.001)
tp_cli_test(stim-emu refuses-65-channels refuses 2 --says "--channels: 65 outside [1, 64]" -- stim-emu --channels 65)
tp_cli_test(stim-emu refuses-long-watchdog refuses 2 --says "--watchdog-ms: 5000 outside [10, 1000]" -- stim-emu --watchdog-ms 5000)
tp_cli_test(stim-emu refuses-bad-reply-delay refuses 2 --says "--reply-delay-ms: -1 outside [0, 1000] ms" -- stim-emu --reply-delay-ms -1)
# Durations: checked against the 3600 s limit before any conversion, in live mode too.
set(S ${IN}/stimulus-ok.json)
tp_cli_test(stimctl refuses-duration-over-limit refuses 2 --stdin ${S} --says "--duration: 3601 s outside (0, 3600" -- stimctl --port emu --duration 3601)
tp_cli_test(stimctl refuses-duration-huge refuses 2 --stdin ${S} --says "--duration: 1e300 s outside (0, 3600" -- stimctl --port emu --duration 1e300)
tp_cli_test(stimctl refuses-duration-wrapping refuses 2 --stdin ${S} --says "--duration: 21474837 s outside (0, 3600" -- stimctl --port emu --duration 21474837)
tp_cli_test(stimctl refuses-live-duration-over-limit refuses 2 --stdin /dev/null --says "--duration: 3601 s outside (0, 3600" --
  stimctl --port emu --live --stimulus ${S} --duration 3601)
tp_cli_test(stimctl refuses-live-duration-huge refuses 2 --stdin /dev/null --says "--duration: 1e300 s outside (0, 3600" --
  stimctl --port emu --live --stimulus ${S} --duration 1e300)
# Ports that are not serial ports are usage errors; more channels than a frame carries.
tp_cli_test(stimctl refuses-dev-null-posix refuses 2 --stdin ${S} --says "--port: '/dev/null' is not a serial port (not a terminal)" -- stimctl --port /dev/null --backend posix)
tp_cli_test(stimctl refuses-dev-null-libserialport refuses 2 --stdin ${S} --says "--port: no serial port '/dev/null'" -- stimctl --port /dev/null --backend libserialport)
tp_cli_test(stimctl refuses-directory-port refuses 2 --stdin ${S} --says "--port: '/tmp' is not a serial port (not a character device)" -- stimctl --port /tmp)
tp_cli_test(stimctl refuses-65-channels refuses 2 --stdin ${IN}/stimulus-65-channels.json --says "stimulus: 65 channels, more than a stimulator drives (at most 64)" -- stimctl --port emu --emu-channels 64)

foreach(script pipeline-emu mix-emu mix-refusals pty-pipeline pty-libserialport pty-refusals pty-faults pty-watchdog pty-signals
               pty-live pty-lost-device list-ports pty-protocol pty-session pty-signal-before-start
               pty-device-bounds pty-live-limits pty-current-limit pty-replay-keepalive pty-rates
               pty-mix pty-table256 pty-intent progress shaped skin-emu guards-emu check-impedance contact-suspend hold-sensation guards-signals stop-input measured-1khz)
  tp_cli_test(stimctl ${script} script ${CMAKE_CURRENT_SOURCE_DIR}/stimctl/${script}.sh)
  set_tests_properties(stimctl.${script} PROPERTIES TIMEOUT 120)
endforeach()
# The 1 kHz status stream's timing: alone (RUN_SERIAL: another test on the same 2 cores
# deschedules the emulator), and in the plain build only (the sanitizers slow the emulator
# several-fold; the sanitizer build runs the same paths in skin-emu and guards-emu).
set_tests_properties(stimctl.measured-1khz PROPERTIES RUN_SERIAL TRUE)
if(TP_SANITIZE)
  set_tests_properties(stimctl.measured-1khz PROPERTIES DISABLED TRUE)
endif()
# Found by the adversarial review: a period that rounds to one the pulse does not fit
# (999.6 Hz: 1000 us for a 1000 us pulse) is refused before configuring; a DAC step the
# protocol cannot carry; an empty --duration; an unwritable latency log before the port.
tp_cli_test(stimctl refuses-rounded-period refuses 2 --stdin ${IN}/stimulus-period-rounds-short.json --says "us does not fit the device's period of 1000 us (999.6 Hz rounded to whole microseconds)" -- stimctl --port emu)
tp_cli_test(stim-emu refuses-dac-step-overflow refuses 2 --says "--dac-bits 4 at 2 mA needs a DAC step over 65535 nA" -- stim-emu --dac-bits 4)
tp_cli_test(stimctl refuses-empty-duration refuses 2 --stdin ${S} --says "--duration: empty value" -- stimctl --port emu --duration=)
tp_cli_test(stimctl refuses-unwritable-latency-log refuses 2 --stdin /dev/null --says "--latency-log: cannot open '/nonexistent/dir/log'" --
  stimctl --port emu --live --stimulus ${S} --latency-log /nonexistent/dir/log)

# Issue 38: settings that were ignored are refused, naming them; a live frame is told by its
# one key (an amplitude frame with another key, or "amplitudes" inside a string, is not one).
tp_cli_test(stimctl refuses-emu-channels-with-a-port refuses 2 --stdin ${S}
  --says "--emu-channels: only with --port emu" -- stimctl --port /dev/tp-no-such-port --emu-channels 16)
tp_cli_test(stimctl refuses-latency-log-without-live refuses 2 --stdin ${S}
  --says "--latency-log: only with --live" -- stimctl --port emu --latency-log /tmp/tp-latency.log)
tp_cli_test(stimctl refuses-amplitude-frame-with-another-key refuses 2 --stdin ${IN}/live-amplitude-extra-key.jsonl
  --says "input line 1: expected {\"currents_mA\": [...]} or {\"amplitudes\": [...]}, one key, got 2"
  -- stimctl --port emu --live --stimulus ${S})
tp_cli_test(stimctl refuses-amplitudes-in-a-string refuses 2 --stdin ${IN}/live-amplitudes-in-string.jsonl
  --says "input line 1: expected {\"currents_mA\": [...]} or {\"amplitudes\": [...]}, one key, got 2"
  -- stimctl --port emu --live --stimulus ${S})
tp_cli_test(stimctl refuses-pattern-with-another-format refuses 2 --stdin ${IN}/mix-pattern-wrong-format.json
  --says "pattern 1: 'format' \"tactile-primaries/weights/1\": a pattern is a stimulus" -- stimctl --port emu)
tp_cli_test(stim-emu refuses-zero-pulse-rate refuses 2 --says "--max-pulse-rate" -- stim-emu --max-pulse-rate 0)
