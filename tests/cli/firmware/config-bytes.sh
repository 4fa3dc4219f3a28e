# scripts/firmware-config writes the block the firmware parses (lib/device/config_block.cpp;
# the unit test "the firmware's configuration block" parses these same bytes): its bash
# CRC-16 agrees with the C++ one.  Current limits round down to whole microamperes.
"$TP_SOURCE/scripts/firmware-config" --max-current 1 > a.bin || fail "firmware-config"
[[ $(od -An -tx1 a.bin | tr -d ' \n') == 5450434601001000080ce8032c015647 ]] \
  || fail "bytes: $(od -An -tx1 a.bin | tr -d '\n')"
"$TP_SOURCE/scripts/firmware-config" --max-current 0.0019999 --channels 3 --dac-bits 16 --watchdog-ms 100 > b.bin
[[ $(od -An -tx1 -j8 -N6 b.bin | tr -d ' \n') == 031001006400 ]] || fail "fields: $(od -An -tx1 b.bin)"
echo "ok: $(od -An -tx1 a.bin | tr -d '\n')"
