// Skin scenarios (device/skin_scenario.hpp) and the skin files an emulator reads
// (host/skin_file.hpp, issue 41 item 2): the issue's own example, read and evaluated over
// time (overrides, a lifted pad, a quarter contact, a sweat ramp on every channel), ramps
// that overlap, and each bad field refused by name.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/json.hpp"
#include "device/skin_block.hpp"
#include "host/skin_file.hpp"
#include "model/skin.hpp"

using namespace tp;
using device::SkinField;

namespace {
const char* kExample = R"({"format": "tactile-primaries/skin/1",
  "electrode": {"rs_kohm": 1.0, "rp_kohm": 50.0, "cp_nf": 30.0},
  "overrides": [{"channels": [2], "rp_kohm": 80.0}],
  "events": [{"t_s": 0.5, "channels": [3], "contact": 0.0},
             {"t_s": 0.2, "channels": [5], "contact": 0.25},
             {"t_s": 0.0, "channels": "all", "rp_kohm": 10.0, "ramp_s": 2.0}]})";

std::uint64_t us(double s) { return static_cast<std::uint64_t>(s * 1e6); }

std::string refusal(const std::string& text, std::size_t channels = 8) {
  try {
    host::skin_scenario_from_json(parse_json_strict(text, "skin"), channels, "--skin s.json");
  } catch (const Error& e) {
    return e.what();
  }
  return "(accepted)";
}
}  // namespace

TEST_CASE("skin files: the issue's example over time", "[host][skin]") {
  const device::SkinScenario s =
      host::skin_scenario_from_json(parse_json_strict(kExample, "skin"), 8, "--skin s.json");
  CHECK(s.events() == 3);
  CHECK(s.at(0, 0).rs_kohm == 1.0);
  CHECK(s.at(0, 0).cp_nf == 30.0);
  CHECK(s.at(0, 0).rp_kohm == 50.0);
  CHECK(s.at(2, 0).rp_kohm == 80.0);                     // the override
  CHECK(s.at(0, us(1.0)).rp_kohm == Approx(30.0));        // sweat: halfway from 50 to 10
  CHECK(s.at(2, us(1.0)).rp_kohm == Approx(45.0));        // from its own 80
  CHECK(s.at(7, us(2.5)).rp_kohm == 10.0);                // and there after the ramp
  CHECK(s.at(3, us(0.499999)).contact == 1.0);
  CHECK(s.at(3, us(0.5)).contact == 0.0);                 // lifted at once
  CHECK(s.at(5, us(0.3)).contact == 0.25);
  CHECK(s.at(4, us(9.0)).contact == 1.0);
}

TEST_CASE("skin scenarios: a later event starts from where an earlier ramp has got to",
          "[device][skin]") {
  device::SkinScenario s;
  device::SkinEvent sweat{0, us(2.0), 1u, SkinField::rp_kohm, 10.0};
  device::SkinEvent dry{us(1.0), us(1.0), 1u, SkinField::rp_kohm, 90.0};
  REQUIRE(s.add_event(dry));  // added out of order: taken by time
  REQUIRE(s.add_event(sweat));
  CHECK(s.at(0, us(0.5)).rp_kohm == Approx(40.0));
  CHECK(s.at(0, us(1.0)).rp_kohm == Approx(30.0));   // the second starts here...
  CHECK(s.at(0, us(1.5)).rp_kohm == Approx(60.0));   // ...and takes over: 30 to 90
  CHECK(s.at(0, us(5.0)).rp_kohm == Approx(90.0));
  CHECK(s.at(1, us(5.0)).rp_kohm == 50.0);           // another channel: untouched
  for (std::size_t k = 2; k < device::SkinScenario::kMaxEvents; ++k) REQUIRE(s.add_event(sweat));
  CHECK(!s.add_event(sweat));
  CHECK(s.events() == device::SkinScenario::kMaxEvents);
}

TEST_CASE("skin files: bad fields refused by name", "[host][skin]") {
  const std::string head = R"({"format": "tactile-primaries/skin/1", )";
  CHECK(refusal(R"({"electrode": {}})") ==
        "--skin s.json: 'format' must be \"tactile-primaries/skin/1\"");
  CHECK(refusal(head + R"("layers": []})") ==
        "--skin s.json: no electrode (the interface: rs_kohm, rp_kohm, cp_nf)");
  CHECK(refusal(head + R"("electrode": {"rp": 5}})") ==
        "--skin s.json: electrode: unknown key 'rp'");
  CHECK(refusal(head + R"("electrode": {"cp_nf": 0}})") ==
        "--skin s.json: electrode.cp_nf: 0 nF outside [0.01, 10000] nF");
  CHECK(refusal(head + R"("electrode": {}, "events": [{"t_s": 1, "channels": [8], "contact": 0}]})") ==
        "--skin s.json: events[0].channels: 8 is not a channel (0 to 7)");
  CHECK(refusal(head + R"("electrode": {}, "events": [{"t_s": 1, "channels": "all", "contact": 1.5}]})") ==
        "--skin s.json: events[0].contact: 1.5 outside [0, 1]");
  CHECK(refusal(head + R"("electrode": {}, "events": [{"t_s": -1, "channels": [0], "contact": 0}]})") ==
        "--skin s.json: events[0].t_s: -1 s outside [0, 86400] s");
  CHECK(refusal(head + R"("electrode": {}, "events": [{"t_s": 1, "channels": [0]}]})") ==
        "--skin s.json: events[0]: changes nothing (give contact, rp_kohm, rs_kohm, cp_nf or "
        "j_half_mA_mm2)");
  CHECK(refusal(head + R"("electrode": {}, "overrides": [{"rp_kohm": 3}]})") ==
        "--skin s.json: overrides[0]: no channels");
  CHECK(refusal(head + R"("electrode": {}, "overrides": [{"channels": [], "rp_kohm": 3}]})") ==
        "--skin s.json: overrides[0].channels: expected a list of channel indices, or \"all\"");
  CHECK(refusal(head + R"("electrode": {}, "wind": 1})") == "--skin s.json: unknown key 'wind'");
  CHECK(refusal(head + R"("electrode": {"j_half_mA_mm2": 0}})") == "(accepted)");
  std::string many = head + R"("electrode": {}, "events": [)";
  for (int k = 0; k < 513; ++k) many += std::string(k ? "," : "") + R"({"t_s": 1, "channels": [0], "contact": 1})";
  CHECK(refusal(many + "]}") == "--skin s.json: events[512]: more than 512 changes in the events");
  // One file may carry the conductor's layers and the emulator's interface: each reads its own.
  Json both = parse_json_strict(kExample, "skin");
  both["valid_to_mm"] = 4.0;
  both["layers"] = Json::array({Json{{"thickness_mm", 0.35}, {"resistivity_ohm_m", 1500.0}},
                                Json{{"resistivity_ohm_m", 2.3}}});
  CHECK(skin_from_json(both, "--skin both.json").layers.size() == 2);
  CHECK(host::skin_scenario_from_json(both, 8, "--skin both.json").events() == 3);
}

TEST_CASE("skin files: the stop input pressed, and its refusals", "[host][skin]") {
  const std::string head = R"({"format": "tactile-primaries/skin/1", "electrode": {}, "events": )";
  const device::SkinScenario s = host::skin_scenario_from_json(
      parse_json_strict(head + R"([{"t_s": 0.7, "stop_input": true}, {"t_s": 0.35, "stop_input": true}]})", "skin"),
      8, "--skin s.json");
  std::uint64_t t = 0;
  REQUIRE(s.first_stop_input(t));
  CHECK(t == us(0.35));
  CHECK(s.stop_inputs() == 2);
  CHECK(s.events() == 0);
  CHECK(refusal(head + R"([{"t_s": 1, "stop_input": false}]})") ==
        "--skin s.json: events[0].stop_input: expected true");
  CHECK(refusal(head + R"([{"t_s": 1, "stop_input": true, "channels": [0]}]})") ==
        "--skin s.json: events[0]: a stop input has only t_s (found 'channels')");
  CHECK(refusal(head + R"([{"stop_input": true}]})") == "--skin s.json: events[0]: no t_s");
  std::string many = head + "[";
  for (int k = 0; k < 17; ++k) many += std::string(k ? "," : "") + R"({"t_s": 1, "stop_input": true})";
  CHECK(refusal(many + "]}") == "--skin s.json: events[16]: more than 16 stop inputs");
}

TEST_CASE("skin blocks: the firmware's simulated board reads back the scenario exactly",
          "[host][skin][device]") {
  device::SkinScenario s =
      host::skin_scenario_from_json(parse_json_strict(kExample, "skin"), 8, "--skin s.json");
  REQUIRE(s.add_stop_input(us(0.75)));
  std::vector<std::uint8_t> block(device::kSkinBlockMaxSize);
  const std::size_t n = device::encode_skin_block(s, 8, 20.0, block.data());
  // Header 23, 8 channels x 5 values, 3 counts, 3 events, 1 stop input, the CRC.
  CHECK(n == 23 + 8 * 5 * 8 + 3 + 3 * device::kSkinEventSize + 8 + 2);
  device::SkinScenario back;
  double compliance = 0;
  REQUIRE(device::decode_skin_block(block.data(), block.size(), back, compliance));
  CHECK(compliance == 20.0);
  CHECK(back.events() == 3);
  std::uint64_t t = 0;
  REQUIRE(back.first_stop_input(t));
  CHECK(t == us(0.75));
  for (std::size_t c = 0; c < 8; ++c)
    for (double ts : {0.0, 0.1, 0.2, 0.5, 1.0, 3.0}) {
      const device::SkinInterface a = s.at(c, us(ts)), b = back.at(c, us(ts));
      CHECK(a.rs_kohm == b.rs_kohm);
      CHECK(a.rp_kohm == b.rp_kohm);
      CHECK(a.cp_nf == b.cp_nf);
      CHECK(a.contact == b.contact);
      CHECK(a.area_mm2 == b.area_mm2);
    }
  // Every single corrupted byte is refused (the CRC, or a field's check), and a refused block
  // leaves the scenario as it was; so does erased flash.
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<std::uint8_t> bad(block.begin(), block.begin() + static_cast<long>(n));
    bad[i] ^= 0x10;
    device::SkinScenario kept;
    REQUIRE(kept.add_stop_input(5));
    double v = 7;
    CHECK_FALSE(device::decode_skin_block(bad.data(), bad.size(), kept, v));
    CHECK(kept.stop_inputs() == 1);
    CHECK(v == 7);
  }
  const std::vector<std::uint8_t> erased(device::kSkinBlockMaxSize, 0xFF);
  CHECK_FALSE(device::decode_skin_block(erased.data(), erased.size(), back, compliance));
  // A block cut short is refused; nor can one be written without channels or compliance.
  CHECK_FALSE(device::decode_skin_block(block.data(), n - 1, back, compliance));
  CHECK(device::encode_skin_block(s, 0, 20.0, block.data()) == 0);
  CHECK(device::encode_skin_block(s, 8, 0.5, block.data()) == 0);
  CHECK(device::encode_skin_block(s, 8, 1000.5, block.data()) == 0);
  // A value no skin file could hold (a zero Rp, a contact above 1) is refused even under a
  // good CRC.
  for (const auto& [field, value] : {std::pair{SkinField::rp_kohm, 0.0},
                                     std::pair{SkinField::contact, 1.5},
                                     std::pair{SkinField::cp_nf, 20000.0}}) {
    device::SkinScenario odd = s;
    odd.set_override(3, field, value);
    const std::size_t m = device::encode_skin_block(odd, 8, 20.0, block.data());
    REQUIRE(m > 0);
    CHECK_FALSE(device::decode_skin_block(block.data(), m, back, compliance));
  }
}
