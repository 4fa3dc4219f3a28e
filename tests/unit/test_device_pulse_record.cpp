// A delivered pulse as a JSON line, the same in the emulator and the firmware
// (lib/device/pulse_record).
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <random>

#include <nlohmann/json.hpp>
#include "core/error.hpp"
#include "device/config_block.hpp"
#include "device/device_core.hpp"
#include "device/pulse_record.hpp"
#include "device_support.hpp"
#include "host/session.hpp"
#include "host/stimulator.hpp"
#include "pulse/stimulus.hpp"

using namespace tp;
using namespace tp::device;


TEST_CASE("a pulse record is the JSON line the emulator and the firmware write",
          "[device][record]") {
  PulseRecord r;
  r.t_us = 1234567;
  r.channels = 3;
  r.main[0] = 1024;
  r.main[1] = -512;
  r.main[2] = -512;
  balance_codes(CodeSpan{r.main, 3}, 200, 800, r.balance);
  r.step_nA = 977;
  r.width_us = 200;
  r.balance_width_us = 800;
  char line[kMaxRecordLine];
  const std::string s(line, format_record(r, line));
  CHECK(s ==
        "{\"pattern\": 0, \"t_s\": 1.234567, \"slip_us\": 0, \"width_us\": 200, "
        "\"interphase_us\": 0, \"balance_width_us\": 800, "
        "\"currents_mA\": [1.000448, -0.500224, -0.500224], \"net_charge_nC\": [0, 0, 0]}\n");
  r.t_us = 5000;
  r.pattern = 255;
  r.slip_us = 350;
  CHECK(std::string(line, format_record(r, line))
            .rfind("{\"pattern\": 255, \"t_s\": 0.005, \"slip_us\": 350, ", 0) == 0);
  r.main[0] = 1023;
  r.main[2] = -511;
  balance_codes(CodeSpan{r.main, 3}, 200, 800, r.balance);  // 1023/4: a remainder
  r.measured = true;
  r.start_us = 1234569;
  r.measured_width_us = 200;
  r.measured_balance_us = 801;
  r.dropped_before = 2;
  const std::string m(line, format_record(r, line));
  const auto j = nlohmann::json::parse(m);
  CHECK(j["currents_mA"][0].get<double>() == Approx(1023 * 977e-6));
  // 1023 x 200 - 256 x 800 = -200 code-us: -0.1954 nC, as the DAC delivers it
  CHECK(j["net_charge_nC"][0].get<double>() == Approx(-200 * 977e-6).margin(1e-6));
  CHECK(j["start_us"] == 1234569);
  CHECK(j["balance_width_us"] == 801);
  CHECK(j["dropped_before"] == 2);
  // The widest record fits.
  PulseRecord big;
  big.t_us = UINT64_MAX / 2;
  big.pattern = UINT16_MAX;
  big.slip_us = UINT32_MAX;
  big.channels = kMaxChannels;
  for (auto& c : big.main) c = -32767;
  for (auto& c : big.balance) c = -32767;
  big.step_nA = 65535;
  big.width_us = big.balance_width_us = 65535;
  big.measured = true;
  big.start_us = UINT64_MAX;
  big.measured_width_us = big.measured_interphase_us = big.measured_balance_us = UINT32_MAX;
  big.dropped_before = UINT32_MAX;
  const std::size_t len = format_record(big, line);
  CHECK(len <= kMaxRecordLine);
  // Exactly, digit for digit, past 32 bits (the 64-bit paths of the formatter).
  const std::string b(line, len);
  CHECK(b.find("\"t_s\": 9223372036854.775807,") != std::string::npos);
  CHECK(b.find("\"slip_us\": 4294967295,") != std::string::npos);
  CHECK(b.find("\"currents_mA\": [-2147.385345, ") != std::string::npos);  // -32767 x 65535 nA
  // -32767 x 65535 nA x 65535 us, twice: -281457797169150 fC, no trailing zero
  CHECK(b.find("\"net_charge_nC\": [-281457797.16915, ") != std::string::npos);
  CHECK(b.find("\"start_us\": 18446744073709551615,") != std::string::npos);
  CHECK(b.find("\"dropped_before\": 4294967295}") != std::string::npos);
  CHECK_NOTHROW(nlohmann::json::parse(b));
  big.start_us = 1000000000;  // nine zeros after the leading digits
  CHECK(std::string(line, format_record(big, line)).find("\"start_us\": 1000000000,") !=
        std::string::npos);
  big.start_us = 4294967296;  // 2^32
  CHECK(std::string(line, format_record(big, line)).find("\"start_us\": 4294967296,") !=
        std::string::npos);
}
