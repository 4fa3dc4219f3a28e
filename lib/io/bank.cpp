#include "io/bank.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "core/number.hpp"
#include "model/field.hpp"
#include "model/primaries.hpp"
#include "core/text.hpp"

namespace tp {

std::string pixel_text(long pad, int columns) {
  return "pixel (" + std::to_string(pad % columns) + ", " + std::to_string(pad / columns) + ")";
}

namespace {

double get_finite(const Json& j, const char* key, const std::string& where) {
  if (!j.is_object() || !j.contains(key)) bad_input(where + ": no " + key);
  return json_finite(j[key], where + "." + key);
}

// One primary's entry of a pixel (`w` names it in messages): its reason when the bank
// found no pattern, else its weights (one per pad, |w| at most 1, not all zero) and peak.
BankEntry bank_entry(const Json& e, const Setup& setup, std::size_t primary, const std::string& w) {
  BankEntry out;
  out.present = true;
  if (e.is_object() && e.contains("feasible") && !e["feasible"].is_boolean())
    bad_input(w + ".feasible: not true or false");
  if (e.is_object() && e.contains("feasible") && e["feasible"] == false) {
    out.reason = e.contains("reason") && e["reason"].is_string() ? e["reason"].get<std::string>()
                                                                 : "no pattern";
    return out;
  }
  out.feasible = true;
  const std::size_t pads = setup.array.size();
  if (!e.is_object() || !e.contains("weights") || !e["weights"].is_array() ||
      e["weights"].size() != pads)
    bad_input(w + ".weights: expected " + std::to_string(pads) + " values, one per pad");
  double peak = 0;
  for (std::size_t i = 0; i < pads; ++i) {
    const double v = json_finite(e["weights"][i], w + ".weights");
    if (std::abs(v) > 1 + 1e-9) bad_input(w + ".weights: |w| above 1");
    peak = std::max(peak, std::abs(v));
    out.weights.push_back(v);
  }
  if (!(peak > 0)) bad_input(w + ".weights: all zero");
  if (!e.contains("peak")) bad_input(w + ": no peak");
  out.peak_x_mm = get_finite(e["peak"], "x_mm", w + ".peak");
  out.peak_y_mm = get_finite(e["peak"], "y_mm", w + ".peak");
  out.peak_z_mm = get_finite(e["peak"], "z_mm", w + ".peak");
  receptor_index(setup, kPrimaries[primary]);  // the bank's receptors name it
  return out;
}

}  // namespace

std::array<double, 3> ModeRecruitment::fractions(double current_mA) const {
  std::array<double, 3> f{};
  for (std::size_t k = 0; k < 3; ++k) {
    const std::vector<double>& t = thresholds_mA[k];
    if (t.empty()) continue;
    const auto n = std::upper_bound(t.begin(), t.end(), current_mA) - t.begin();
    f[k] = static_cast<double>(n) / static_cast<double>(t.size());
  }
  return f;
}

Json recruitment_to_json(const BankRecruitment& r) {
  Json j;
  j["population"] = r.per_class;
  j["seed"] = r.seed;
  j["fibre_model"] = r.fibre_model;
  j["pulse"] = r.pulse;
  j["max_mA"] = r.max_mA;
  j["region"] = "the pitch around each mode's pixel";
  Json modes = Json::object();
  for (std::size_t m = 0; m < 3; ++m) {
    if (!r.mode[m]) continue;
    const ModeRecruitment& q = *r.mode[m];
    Json e;
    e["pad"] = q.pad;
    e["reference_mA"] = q.reference_mA;
    Json t = Json::object();
    for (std::size_t k = 0; k < 3; ++k) {
      Json list = Json::array();
      for (double v : q.thresholds_mA[k]) list.push_back(std::isfinite(v) ? Json(v) : Json());
      t[kPrimaries[k]] = list;
    }
    e["thresholds_mA"] = t;
    modes[kPrimaries[m]] = e;
  }
  j["modes"] = modes;
  return j;
}

namespace {

ModeRecruitment mode_recruitment(const Json& e, std::size_t pads, long population,
                                 double max_mA, const std::string& w) {
  ModeRecruitment q;
  if (!e.is_object()) bad_input(w + ": not an object (leave a mode out when it has none)");
  reject_unknown(e, {"pad", "reference_mA", "thresholds_mA"}, w);
  if (!e.contains("pad") || !e["pad"].is_number_integer() || e["pad"].get<long>() < 0 ||
      e["pad"].get<long>() >= static_cast<long>(pads))
    bad_input(w + ".pad: not a pad of the bank");
  q.pad = e["pad"].get<long>();
  q.reference_mA = get_finite(e, "reference_mA", w);
  if (!(q.reference_mA > 0 && q.reference_mA <= max_mA))
    bad_input(w + ".reference_mA: outside (0, max_mA = " + number_text(max_mA) + "]");
  if (!e.contains("thresholds_mA") || !e["thresholds_mA"].is_object())
    bad_input(w + ": no thresholds_mA");
  reject_unknown(e["thresholds_mA"], {kPrimaries.begin(), kPrimaries.end()}, w + ".thresholds_mA");
  for (std::size_t k = 0; k < 3; ++k) {
    const std::string wk = w + ".thresholds_mA." + kPrimaries[k];
    const Json& t = e["thresholds_mA"].contains(kPrimaries[k]) ? e["thresholds_mA"][kPrimaries[k]]
                                                               : Json();
    if (!t.is_array() || t.size() != static_cast<std::size_t>(population))
      bad_input(wk + ": expected " + std::to_string(population) +
                " thresholds (the population), ascending, null for none");
    for (const Json& v : t) {
      const double x = v.is_null() ? std::numeric_limits<double>::infinity() : json_finite(v, wk);
      if (!(x > 0)) bad_input(wk + ": a threshold not above 0");
      if (std::isfinite(x) && x > max_mA)
        bad_input(wk + ": a threshold above max_mA (" + number_text(max_mA) + "; null for none)");
      if (!q.thresholds_mA[k].empty() && x < q.thresholds_mA[k].back())
        bad_input(wk + ": not ascending");
      q.thresholds_mA[k].push_back(x);
    }
  }
  return q;
}

}  // namespace

BankRecruitment recruitment_from_json(const Json& j, std::size_t pads, const std::string& w) {
  if (!j.is_object()) bad_input(w + ": not an object");
  reject_unknown(j, {"population", "seed", "fibre_model", "pulse", "max_mA", "region", "modes"}, w);
  BankRecruitment r;
  if (!j.contains("population") || !j["population"].is_number_integer() ||
      j["population"].get<long>() < 1 || j["population"].get<long>() > 1000)
    bad_input(w + ".population: not a count from 1 to 1000");
  r.per_class = j["population"].get<long>();
  if (j.contains("seed")) {
    if (!j["seed"].is_number_unsigned()) bad_input(w + ".seed: not a whole number from 0");
    r.seed = j["seed"].get<std::uint64_t>();
  }
  if (j.contains("fibre_model")) {
    if (!j["fibre_model"].is_string()) bad_input(w + ".fibre_model: not a string");
    r.fibre_model = j["fibre_model"].get<std::string>();
  }
  // The pulse is read by the renderer (pulse_spec_from_json, a layer above this one).
  if (!j.contains("pulse") || !j["pulse"].is_object())
    bad_input(w + ".pulse: not a pulse object (the recruitment's: width_us, ... or phases)");
  r.pulse = j["pulse"];
  if (j.contains("region") && !j["region"].is_string()) bad_input(w + ".region: not a string");
  // Absent: the cap optimize-weights --bank --population searches to.
  r.max_mA = j.contains("max_mA") ? json_finite(j["max_mA"], w + ".max_mA") : 10.0;
  if (!(r.max_mA > 0 && r.max_mA <= 1000)) bad_input(w + ".max_mA: outside (0, 1000]");
  if (!j.contains("modes") || !j["modes"].is_object()) bad_input(w + ": no modes");
  reject_unknown(j["modes"], {kPrimaries.begin(), kPrimaries.end()}, w + ".modes");
  for (std::size_t m = 0; m < 3; ++m)
    if (j["modes"].contains(kPrimaries[m]))
      r.mode[m] = mode_recruitment(j["modes"][kPrimaries[m]], pads, r.per_class, r.max_mA,
                                   w + ".modes." + kPrimaries[m]);
  return r;
}

PixelBank pixel_bank_from_json(const Json& j) {
  if (!j.is_object() || !j.contains("bank") || !j.contains("pixels") || !j["pixels"].is_array())
    bad_input("bank: not a bank of pixels (optimize-weights --bank)");
  PixelBank b;
  b.doc = document_from_json(j);
  const ElectrodeArray& a = b.doc.setup.array;
  if (!a.grid()) bad_input("bank: its array is " + a.describe() + ", not a grid of pads");
  b.columns = a.columns;
  b.rows = a.rows;
  b.pad_area_mm2 = a.width_mm * a.length_mm;
  const Json& px = j["pixels"];
  if (px.size() != a.size())
    bad_input("bank: " + count_text(px.size(), "pixel") + " for " + count_text(a.size(), "pad") +
              " (render-tactile needs every pad's pixel: a bank without --at)");
  b.entry.resize(a.size());
  for (std::size_t k = 0; k < px.size(); ++k) {
    const Json& p = px[k];
    const std::string where = "bank: pixels[" + std::to_string(k) + "]";
    const double x = get_finite(p, "x_mm", where), z = get_finite(p, "z_mm", where);
    if (!p.contains("pad") || !p["pad"].is_number_integer() ||
        p["pad"].get<long>() != static_cast<long>(k) || std::abs(x - a.positions_mm[k]) > 1e-6 ||
        std::abs(z - a.z_mm[k]) > 1e-6)
      bad_input(where + ": not pad " + std::to_string(k) + "'s centre");
    if (!p.contains("patterns") || !p["patterns"].is_object()) bad_input(where + ": no patterns");
    for (std::size_t m = 0; m < kPrimaries.size(); ++m)
      if (p["patterns"].contains(kPrimaries[m]))
        b.entry[k][m] = bank_entry(p["patterns"][kPrimaries[m]], b.doc.setup, m,
                                   where + ".patterns." + kPrimaries[m]);
  }
  if (j.contains("recruitment"))
    b.recruitment = recruitment_from_json(j["recruitment"], a.size(), "bank: recruitment");
  return b;
}

}  // namespace tp
