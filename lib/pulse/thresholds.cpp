// The pulse of a threshold and the thresholds a document carries.

#include "pulse/thresholds.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.hpp"
#include "core/number.hpp"

namespace tp {

std::vector<Phase> PulseSpec::delivered() const {
  if (!phases.empty()) return phases;
  if (monophasic) return {{width_us, 1.0}};
  return shorthand_phases(width_us, interphase_us, balance_width_us);
}

bool PulseSpec::operator==(const PulseSpec& o) const {
  return same_phases(delivered(), o.delivered());
}

std::string PulseSpec::describe() const {
  if (!phases.empty()) return "shaped (" + describe_phases(phases) + ")";
  std::string s = number_text(width_us) + " us ";
  if (monophasic) return s + "monophasic";
  s += "biphasic";
  if (interphase_us > 0) s += ", " + number_text(interphase_us) + " us gap";
  if (balance_width_us != width_us) s += ", " + number_text(balance_width_us) + " us balance";
  return s;
}

PulseSpec pulse_of(const PulseShape& shape) {
  PulseSpec p;
  p.width_us = shape.width_us;
  p.interphase_us = shape.interphase_us;
  p.balance_width_us = shape.balance_width_us;
  p.phases = shape.phases;
  return p;
}

void check_pulse(const PulseSpec& p) {
  if (!p.phases.empty()) {
    check_simulated_phases(p.phases);
    return;
  }
  auto in = [](double v, double lo, double hi, const char* what) {
    if (!(v >= lo && v <= hi))
      bad_input(std::string(what) + ": " + number_beside(v, lo, hi) + " us outside [" +
                number_text(lo) + ", " + number_text(hi) + "] us");
  };
  in(p.width_us, 1.0, 10000.0, "--width");
  if (p.monophasic) return;
  in(p.interphase_us, 0.0, 10000.0, "--interphase");
  in(p.balance_width_us, 1.0, 10000.0, "--balance-width");
}

Json pulse_spec_to_json(const PulseSpec& p) {
  Json j = Json::object();
  if (!p.phases.empty()) {
    j["phases"] = phases_to_json(p.phases);
    return j;
  }
  j["width_us"] = p.width_us;
  if (p.monophasic) {
    j["monophasic"] = true;
  } else {
    j["interphase_us"] = p.interphase_us;
    j["balance_width_us"] = p.balance_width_us;
  }
  return j;
}

PulseSpec pulse_spec_from_json(const Json& p, const std::string& where) {
  auto bad = [&](const std::string& what) { bad_input(where + "." + what); };
  if (!p.is_object()) bad_input(where + ": not an object");
  PulseSpec c;
  if (p.contains("phases")) {
    for (const char* k : {"width_us", "interphase_us", "balance_width_us", "monophasic"})
      if (p.contains(k)) bad_input(where + ": give phases or " + k + ", not both");
    c.phases = phases_from_json(p["phases"], where + ".phases");
    return c;
  }
  auto num = [&](const char* key) {
    if (!p.contains(key) || !p[key].is_number()) bad(std::string(key) + " missing");
    const double v = p[key].get<double>();
    if (!std::isfinite(v)) bad(std::string(key) + " not finite");
    return v;
  };
  c.width_us = num("width_us");
  if (p.contains("monophasic") && !p["monophasic"].is_boolean())
    bad("monophasic must be true or false");
  c.monophasic = p.contains("monophasic") && p["monophasic"].get<bool>();
  if (!c.monophasic) {
    c.interphase_us = num("interphase_us");
    c.balance_width_us = num("balance_width_us");
  }
  return c;
}

std::optional<CarriedThresholds> carried_thresholds(const Json& doc) {
  if (!doc.is_object() || !doc.contains("thresholds")) return std::nullopt;
  const Json& t = doc["thresholds"];
  auto bad = [](const std::string& what) { bad_input("thresholds: " + what); };
  if (!t.is_object()) bad("not an object");
  CarriedThresholds c;
  if (!t.contains("fibre_model") || !t["fibre_model"].is_string()) bad("no fibre_model");
  c.model = t["fibre_model"].get<std::string>();
  if (!t.contains("pulse") || !t["pulse"].is_object()) bad("no pulse");
  c.pulse = pulse_spec_from_json(t["pulse"], "thresholds: pulse");
  if (t.contains("peak_weight")) {
    if (!t["peak_weight"].is_number() || !(t["peak_weight"].get<double>() >= 1e-12) ||
        !(t["peak_weight"].get<double>() <= 1000.0))
      bad("peak_weight must be a number from 1e-12 to 1000 (the largest |weight|)");
    c.peak_weight = t["peak_weight"].get<double>();
  }
  if (!t.contains("receptors") || !t["receptors"].is_object()) bad("no receptors");
  if (t["receptors"].empty()) bad("receptors is empty");
  for (const auto& [name, e] : t["receptors"].items()) {
    // Names are printed: printable ASCII, 1 to 32 characters.
    bool printable = !name.empty() && name.size() <= 32;
    for (unsigned char ch : name) printable = printable && ch >= 0x20 && ch < 0x7f;
    if (!printable) bad("a receptor name must be 1 to 32 printable ASCII characters");
    if (!e.is_object() || !e.contains("threshold_mA")) bad(name + ": no threshold_mA");
    const Json& v = e["threshold_mA"];
    if (v.is_null()) {
      c.threshold_mA.emplace_back(name, std::nullopt);
    } else if (v.is_number() && v.get<double>() >= 1e-15 && v.get<double>() <= 100.0) {
      c.threshold_mA.emplace_back(name, v.get<double>());
    } else {
      bad(name + ": threshold_mA must be a number from 1e-15 to 100 mA, or null");
    }
  }
  return c;
}

std::string threshold_multiples(const CarriedThresholds& t, double amplitude_mA) {
  std::vector<std::pair<double, std::string>> fired;
  std::string none;
  for (const auto& [name, th] : t.threshold_mA) {
    if (th)
      fired.emplace_back(*th, name);
    else
      none += (none.empty() ? "" : ", ") + name;
  }
  std::sort(fired.begin(), fired.end());
  std::string s = number_text(amplitude_mA) + " mA =";
  char buf[128];
  for (std::size_t k = 0; k < fired.size(); ++k) {
    std::snprintf(buf, sizeof buf, "%s %.3g x %s%s", k ? "," : "", amplitude_mA / fired[k].first,
                  fired[k].second.c_str(), k ? "" : " threshold");
    s += buf;
  }
  if (!none.empty()) s += (fired.empty() ? " no threshold for " : "; no threshold for ") + none;
  return s;
}

std::optional<std::string> stimulus_against_thresholds(const Json& doc, const PulseSpec& pulse,
                                                       double peak_current_mA) {
  const auto t = carried_thresholds(doc);
  if (!t) return std::nullopt;
  if (!(t->pulse == pulse))
    return "the thresholds carried are for a " + t->pulse.describe() + " pulse, not this " +
           pulse.describe() + " one: no multiples (fiber-threshold --stimulus gives them)";
  return threshold_multiples(*t, peak_current_mA / t->peak_weight) + " (" + t->model + ", " +
         pulse.describe() + ")";
}

std::optional<std::string> stimulus_against_thresholds(const Stimulus& s) {
  double peak = 0.0;
  for (double c : s.currents_mA) peak = std::max(peak, std::fabs(c));
  return stimulus_against_thresholds(s.carried, pulse_of(s.shape), peak);
}

}  // namespace tp
