#include "psych/profile.hpp"

#include "core/ranges.hpp"

#include "core/error.hpp"
#include "core/number.hpp"
#include "core/text.hpp"

namespace tp {

const PrimaryRange& Profile::range(int p, long pad) const {
  const auto it = pixel.find(pad);
  if (it != pixel.end() && it->second[static_cast<std::size_t>(p)])
    return *it->second[static_cast<std::size_t>(p)];
  if (!primary[static_cast<std::size_t>(p)])
    bad_input(std::string("profile: no range for ") + kPrimaries[static_cast<std::size_t>(p)]);
  return *primary[static_cast<std::size_t>(p)];
}

double Profile::current_mA(int p, long pad, double v) const {
  if (!(v > 0)) return 0.0;
  const PrimaryRange& r = range(p, pad);
  if (v >= 1) return r.comfort_mA;  // exactly, not to a rounding
  return r.threshold_mA + v * (r.comfort_mA - r.threshold_mA);
}

double profile_amplitude_mA(const Profile& p, const std::string& mode, double v,
                            const std::string& what) {
  if (!(v > 0 && v <= 1))
    bad_input(what + ": intensity " + number_beside(v, 0, 1) + " outside (0, 1]");
  const int k = primary_index(mode, what + ": the stimulus's mode");
  if (!p.primary[static_cast<std::size_t>(k)])
    bad_input(what + ": the profile has no range for " + mode);
  return p.current_mA(k, -1, v);
}

namespace {

PrimaryRange range_from_json(const Json& j, const std::string& where, double max_mA) {
  if (!j.is_object()) bad_input(where + ": expected an object");
  for (const auto& [key, value] : j.items())
    if (key != "threshold_mA" && key != "comfort_mA" && key != "trials" &&
        key != "threshold_spread_mA" && key != "comfort_spread_mA" &&
        key != "model_threshold_mA" && key != "colour" && key != "impedance_kohm")
      bad_input(where + ": unknown key '" + key +
                "' (a range has threshold_mA, comfort_mA, trials, threshold_spread_mA, "
                "comfort_spread_mA, model_threshold_mA, colour and impedance_kohm)");
  for (const char* key : {"threshold_mA", "comfort_mA"})
    if (!j.contains(key)) bad_input(where + ": no " + key);
  PrimaryRange r;
  r.threshold_mA = json_finite(j["threshold_mA"], where + ".threshold_mA");
  r.comfort_mA = json_finite(j["comfort_mA"], where + ".comfort_mA");
  if (!(r.threshold_mA >= kMinProfile_mA && r.threshold_mA <= max_mA))
    bad_input(where + ".threshold_mA: " + number_beside(r.threshold_mA, kMinProfile_mA, max_mA) +
              " mA outside [" + number_text(kMinProfile_mA) + ", " + number_text(max_mA) + "] mA");
  if (r.comfort_mA > max_mA)
    bad_input(where + ".comfort_mA: " + number_beside(r.comfort_mA, max_mA) +
              " mA is above the current limit, " + number_text(max_mA) + " mA");
  if (r.comfort_mA < r.threshold_mA)
    bad_input(where + ".comfort_mA: " + number_beside(r.comfort_mA, r.threshold_mA) +
              " mA is below its threshold, " + number_text(r.threshold_mA) + " mA");
  if (j.contains("trials")) {
    r.trials = json_int(j["trials"], where + ".trials");
    if (r.trials < 0) bad_input(where + ".trials: negative");
  }
  for (const auto& [key, field] : {std::pair{"threshold_spread_mA", &r.threshold_spread_mA},
                                   std::pair{"comfort_spread_mA", &r.comfort_spread_mA}})
    if (j.contains(key)) {
      *field = json_finite(j[key], where + "." + key);
      if (*field < 0) bad_input(where + "." + key + ": negative");
    }
  if (j.contains("model_threshold_mA")) {
    r.model_threshold_mA = json_finite(j["model_threshold_mA"], where + ".model_threshold_mA");
    if (!(r.model_threshold_mA > 0 && r.model_threshold_mA <= 1000))
      bad_input(where + ".model_threshold_mA: " + number_beside(r.model_threshold_mA, 0, 1000) +
                " mA outside (0, 1000] mA");
  }
  if (j.contains("colour")) {
    const Json& c = j["colour"];
    if (!c.is_array() || c.size() != 3)
      bad_input(where + ".colour: expected 3 fractions (RA, SAI, PC)");
    std::array<double, 3> f{};
    for (std::size_t k = 0; k < 3; ++k) {
      f[k] = json_finite(c[k], where + ".colour");
      if (!(f[k] >= 0 && f[k] <= 1))
        bad_input(where + ".colour: " + number_beside(f[k], 0, 1) + " outside [0, 1]");
    }
    r.colour = f;
  }
  if (j.contains("impedance_kohm")) {
    const Json& z = j["impedance_kohm"];
    if (!z.is_array() || z.empty() || z.size() > static_cast<std::size_t>(ranges::max_channels))
      bad_input(where + ".impedance_kohm: expected one impedance (kOhm, or null) per pad");
    for (std::size_t c = 0; c < z.size(); ++c) {
      const std::string what = where + ".impedance_kohm[" + std::to_string(c) + "]";
      r.impedance_kohm.push_back(z[c].is_null() ? 0.0 : json_finite(z[c], what));
      if (!z[c].is_null()) ranges::check(r.impedance_kohm.back(), ranges::impedance_kohm, what);
    }
  }
  return r;
}

Json range_to_json(const PrimaryRange& r) {
  Json j = {{"threshold_mA", r.threshold_mA}, {"comfort_mA", r.comfort_mA}};
  if (r.trials > 0) {
    j["trials"] = r.trials;
    j["threshold_spread_mA"] = r.threshold_spread_mA;
    j["comfort_spread_mA"] = r.comfort_spread_mA;
  }
  if (r.model_threshold_mA > 0) j["model_threshold_mA"] = r.model_threshold_mA;
  if (r.colour) j["colour"] = Json::array({(*r.colour)[0], (*r.colour)[1], (*r.colour)[2]});
  if (!r.impedance_kohm.empty()) {
    Json z = Json::array();
    for (double v : r.impedance_kohm) z.push_back(v > 0 ? Json(v) : Json(nullptr));
    j["impedance_kohm"] = z;
  }
  return j;
}

std::array<std::optional<PrimaryRange>, 3> ranges_from_json(const Json& j, const std::string& where,
                                                            double max_mA, bool pixel) {
  std::array<std::optional<PrimaryRange>, 3> out;
  for (const auto& [key, value] : j.items()) {
    if (pixel && key == "pad") continue;
    const int p = primary_index(key, where);
    out[static_cast<std::size_t>(p)] = range_from_json(value, where + "." + key, max_mA);
  }
  return out;
}

}  // namespace

void check_profile_fits(const Profile& p, std::size_t pads,
                        const std::optional<std::pair<int, int>>& grid, const std::string& theirs) {
  if (!p.carried.contains("array")) return;
  const Json& a = p.carried["array"];
  bool same = a.is_object() && a.contains("columns") && a.contains("rows") &&
              a["columns"].is_number_integer() && a["rows"].is_number_integer();
  if (same) {
    const long columns = a["columns"].get<long>(), rows = a["rows"].get<long>();
    same = columns > 0 && rows > 0 && static_cast<std::size_t>(columns * rows) == pads &&
           (!grid || (columns == grid->first && rows == grid->second));
  }
  if (!same) bad_input("profile: calibrated on an array of " + a.dump() + ", " + theirs);
}

Profile profile_from_json(const Json& j, double max_mA, long pads) {
  if (!j.is_object()) bad_input("profile: expected a JSON object");
  if (!j.contains("format") || j["format"] != kProfileFormat)
    bad_input(std::string("profile: format is not \"") + kProfileFormat + "\"");
  if (!j.contains("primaries") || !j["primaries"].is_object())
    bad_input("profile: no \"primaries\" object");
  Profile p;
  p.primary = ranges_from_json(j["primaries"], "profile: primaries", max_mA, false);
  if (j.contains("pixels")) {
    if (!j["pixels"].is_array()) bad_input("profile: pixels: expected an array");
    for (std::size_t k = 0; k < j["pixels"].size(); ++k) {
      const Json& e = j["pixels"][k];
      const std::string where = "profile: pixels[" + std::to_string(k) + "]";
      if (!e.is_object() || !e.contains("pad")) bad_input(where + ": no pad");
      const long pad = json_int(e["pad"], where + ".pad");
      if (pad < 0 || pad >= pads)
        bad_input(where + ".pad: " + std::to_string(pad) + " is not one of the array's " +
                  count_text(static_cast<std::size_t>(pads), "pad"));
      if (p.pixel.count(pad)) bad_input(where + ".pad: " + std::to_string(pad) + " given twice");
      p.pixel[pad] = ranges_from_json(e, where, max_mA, true);
    }
  }
  for (const auto& [key, value] : j.items())
    if (key != "format" && key != "primaries" && key != "pixels") p.carried[key] = value;
  return p;
}

Json profile_to_json(const Profile& p) {
  Json j = {{"format", kProfileFormat}};
  Json prim = Json::object();
  for (std::size_t i = 0; i < 3; ++i)
    if (p.primary[i]) prim[kPrimaries[i]] = range_to_json(*p.primary[i]);
  j["primaries"] = prim;
  if (!p.pixel.empty()) {
    Json px = Json::array();
    for (const auto& [pad, r] : p.pixel) {
      Json e = {{"pad", pad}};
      for (std::size_t i = 0; i < 3; ++i)
        if (r[i]) e[kPrimaries[i]] = range_to_json(*r[i]);
      px.push_back(e);
    }
    j["pixels"] = px;
  }
  for (const auto& [key, value] : p.carried.items()) j[key] = value;
  return j;
}

}  // namespace tp
