// Skin files read into an emulator's skin scenario (skin_file.hpp).

#include "host/skin_file.hpp"

#include <cmath>
#include <initializer_list>
#include <memory>
#include <set>
#include <utility>

#include "core/error.hpp"
#include "core/number.hpp"
#include "core/ranges.hpp"

namespace tp::host {

namespace {

using device::SkinField;

constexpr const char* kFormat = "tactile-primaries/skin/1";

struct FieldSpec {
  const char* key;
  SkinField field;
  ranges::Range range;
};
// j_half_mA_mm2 may also be 0 (Rp constant), checked apart.
constexpr FieldSpec kFields[] = {
    {"rs_kohm", SkinField::rs_kohm, {0.01, 1000, "kOhm"}},
    {"rp_kohm", SkinField::rp_kohm, {0.1, 10000, "kOhm"}},
    {"cp_nf", SkinField::cp_nf, {0.01, 10000, "nF"}},
    {"j_half_mA_mm2", SkinField::j_half_mA_mm2, {0.001, 1000, "mA/mm^2"}},
    {"contact", SkinField::contact, {0, 1, ""}},
};

// The interface's keys, and those given.
std::set<std::string> field_keys(std::initializer_list<const char*> more) {
  std::set<std::string> keys(more.begin(), more.end());
  for (const FieldSpec& f : kFields) keys.insert(f.key);
  return keys;
}

// A list of objects, each checked for its keys and given to `each` with its name.
template <class Each>
void for_each_object(const Json& list, const std::set<std::string>& keys,
                     const std::string& where, Each&& each) {
  if (!list.is_array()) bad_input(where + ": expected a list");
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string at = where + "[" + std::to_string(k) + "]";
    if (!list[k].is_object()) bad_input(at + ": expected an object");
    reject_unknown(list[k], keys, at);
    each(list[k], at);
  }
}

double field_value(const Json& j, const FieldSpec& f, const std::string& where) {
  const double v = json_finite(j[f.key], where + "." + f.key);
  if (f.field == SkinField::j_half_mA_mm2 && v == 0) return v;
  ranges::check(v, f.range, where + "." + f.key);
  return v;
}

// The channels a list names: an array of channel indices, or "all".
std::uint64_t channel_set(const Json& j, std::size_t channels, const std::string& where) {
  if (j.is_string() && j.get<std::string>() == "all")
    return channels >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << channels) - 1;
  if (!j.is_array() || j.empty())
    bad_input(where + ": expected a list of channel indices, or \"all\"");
  std::uint64_t set = 0;
  for (const Json& c : j) {
    if (!c.is_number_integer() || c.get<long>() < 0 ||
        c.get<long>() >= static_cast<long>(channels))
      bad_input(where + ": " + c.dump() + " is not a channel (0 to " +
                std::to_string(channels - 1) + ")");
    set |= std::uint64_t{1} << c.get<long>();
  }
  return set;
}

device::SkinInterface electrode_of(const Json& j, const std::string& where) {
  device::SkinInterface s;
  if (!j.is_object()) bad_input(where + ": expected an object");
  reject_unknown(j, field_keys({"area_mm2", "note"}), where);
  for (const FieldSpec& f : kFields)
    if (j.contains(f.key)) device::set_skin_field(s, f.field, field_value(j, f, where));
  if (j.contains("area_mm2")) {
    s.area_mm2 = json_finite(j["area_mm2"], where + ".area_mm2");
    ranges::check(s.area_mm2, {0.01, 10000, "mm^2"}, where + ".area_mm2");
  }
  return s;
}

double seconds(const Json& j, const char* key, const std::string& where) {
  const double v = json_finite(j[key], where + "." + key);
  ranges::check(v, {0, skin_file_ranges::max_time_s, "s"}, where + "." + key);
  return v;
}

void add_overrides(const Json& list, std::size_t channels, device::SkinScenario& s,
                   const std::string& where) {
  for_each_object(list, field_keys({"channels", "note"}), where, [&](const Json& o,
                                                                     const std::string& at) {
    if (!o.contains("channels")) bad_input(at + ": no channels");
    const std::uint64_t set = channel_set(o["channels"], channels, at + ".channels");
    for (const FieldSpec& f : kFields) {
      if (!o.contains(f.key)) continue;
      const double v = field_value(o, f, at);
      for (std::size_t c = 0; c < channels; ++c)
        if (set >> c & 1u) s.set_override(c, f.field, v);
    }
  });
}

void add_events(const Json& list, std::size_t channels, device::SkinScenario& s,
                const std::string& where) {
  for_each_object(list, field_keys({"t_s", "ramp_s", "channels", "stop_input", "note"}), where,
                  [&](const Json& e, const std::string& at) {
    if (!e.contains("t_s")) bad_input(at + ": no t_s");
    if (e.contains("stop_input")) {  // the board's stop input, pressed at t_s
      if (!e["stop_input"].is_boolean() || !e["stop_input"].get<bool>())
        bad_input(at + ".stop_input: expected true");
      for (const auto& [key, value] : e.items())
        if (key != "t_s" && key != "stop_input" && key != "note")
          bad_input(at + ": a stop input has only t_s (found '" + key + "')");
      if (!s.add_stop_input(
              static_cast<std::uint64_t>(std::llround(seconds(e, "t_s", at) * 1e6))))
        bad_input(at + ": more than " + std::to_string(device::SkinScenario::kMaxStopInputs) +
                  " stop inputs");
      return;
    }
    if (!e.contains("channels")) bad_input(at + ": no channels");
    device::SkinEvent ev;
    ev.t_us = static_cast<std::uint64_t>(std::llround(seconds(e, "t_s", at) * 1e6));
    ev.ramp_us = e.contains("ramp_s")
                     ? static_cast<std::uint64_t>(std::llround(seconds(e, "ramp_s", at) * 1e6))
                     : 0;
    ev.channels = channel_set(e["channels"], channels, at + ".channels");
    bool any = false;
    for (const FieldSpec& f : kFields) {
      if (!e.contains(f.key)) continue;
      any = true;
      ev.field = f.field;
      ev.target = field_value(e, f, at);
      if (!s.add_event(ev))
        bad_input(at + ": more than " + std::to_string(device::SkinScenario::kMaxEvents) +
                  " changes in the events");
    }
    if (!any)
      bad_input(at + ": changes nothing (give contact, rp_kohm, rs_kohm, cp_nf or j_half_mA_mm2)");
  });
}

}  // namespace

device::SkinScenario skin_scenario_from_json(const Json& j, std::size_t channels,
                                             const std::string& where) {
  if (channels < 1 || channels > device::kMaxChannels)
    bad_input(where + ": " + std::to_string(channels) + " channels outside [1, 64]");
  if (!j.is_object()) bad_input(where + ": expected a JSON object");
  reject_unknown(j, {"format", "name", "description", "note", "valid_to_mm", "layers",
                     "electrode", "overrides", "events"},
                 where);
  if (!j.contains("format") || !j["format"].is_string() ||
      j["format"].get<std::string>() != kFormat)
    bad_input(where + ": 'format' must be \"" + std::string(kFormat) + "\"");
  if (!j.contains("electrode"))
    bad_input(where + ": no electrode (the interface: rs_kohm, rp_kohm, cp_nf)");
  device::SkinScenario s(electrode_of(j["electrode"], where + ": electrode"));
  if (j.contains("overrides")) add_overrides(j["overrides"], channels, s, where + ": overrides");
  if (j.contains("events")) add_events(j["events"], channels, s, where + ": events");
  return s;
}

EmulatorSkin emulator_skin(const std::string& path, std::optional<double> compliance_V,
                           std::size_t channels, const std::string& skin_flag,
                           const std::string& compliance_flag) {
  EmulatorSkin skin;
  if (path.empty()) {
    if (compliance_V)
      bad_input(compliance_flag + ": applies with " + skin_flag +
                " (an ideal load needs no voltage)");
    return skin;
  }
  if (compliance_V) {
    ranges::check(*compliance_V, {1, 1000, "V"}, compliance_flag);
    skin.compliance_V = *compliance_V;
  }
  skin.scenario = std::make_shared<const device::SkinScenario>(
      skin_scenario_from_json(read_json(path, "skin"), channels, skin_flag + " " + path));
  return skin;
}

}  // namespace tp::host
