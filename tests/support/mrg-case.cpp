// mrg-case: the project's MRG threshold for one case of the NEURON peer's JSON format
// (../shared/peers/mrg-neuron/mrg_threshold.py): the same fibre (a middle node at offset_mm,
// `nodes` nodes), the same field (line2d weights or a table, linearly interpolated), the
// same pulse after 0.1 ms, the same detection (-20 mV at the sixth node from each end) and
// the same bisection (from 0.05 mA, doubling, to a relative tolerance).  Used by the
// `neuron` tests and scripts/bench, side by side with the peer.
// With "search": "lattice", the library's own search instead (fibre_threshold: the lattice
// of the tolerance, bracketed from the passive estimate by steps that double, one core), as
// fiber-threshold runs it:
// a threshold within the tolerance of the bisection's, with fewer runs below threshold
// (the costly ones: they run to the end of the simulated time, or pause once settled).

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <memory>

#include "fibre/cable.hpp"
#include "fibre/geometry.hpp"
#include "fibre/threshold.hpp"

using namespace tp::fibre;
using json = nlohmann::json;

namespace {
constexpr double kPi = 3.14159265358979323846;

// The field at (x, y): y from the case's depth_mm, or one per point (an afferent's path).
std::vector<double> field(const json& c, const std::vector<double>& x,
                          const std::vector<double>& ys = {}) {
  const double depth = ys.empty() ? c.at("depth_mm").get<double>() : 0.0;
  const json& f = c.at("field");
  std::vector<double> out;
  if (f.contains("line2d")) {
    const json& p = f["line2d"];
    const auto w = p.at("weights").get<std::vector<double>>();
    const double pitch = p.at("pitch_mm").get<double>();
    const double rho = p.value("resistivity_ohm_m", 3.0), len = p.value("length_mm", 10.0);
    const double n = static_cast<double>(w.size());
    for (std::size_t k = 0; k < x.size(); ++k) {
      const double xx = x[k], y = ys.empty() ? depth : ys[k];
      double v = 0.0;
      for (std::size_t i = 0; i < w.size(); ++i) {
        const double r = std::hypot(xx - (static_cast<double>(i) - (n - 1) / 2) * pitch, y);
        v += w[i] * rho / len * std::log(r) / (2 * kPi);
      }
      out.push_back(1000.0 * v);
    }
    return out;
  }
  const auto xs = f.at("table").at("x_mm").get<std::vector<double>>();
  const auto ps = f.at("table").at("psi_mV_per_mA").get<std::vector<double>>();
  for (double xx : x) {
    if (xx <= xs.front()) {
      out.push_back(ps.front());
      continue;
    }
    if (xx >= xs.back()) {
      out.push_back(ps.back());
      continue;
    }
    std::size_t lo = 0, hi = xs.size() - 1;
    while (hi - lo > 1) {
      const std::size_t m = (lo + hi) / 2;
      (xs[m] <= xx ? lo : hi) = m;
    }
    const double a = (xx - xs[lo]) / (xs[hi] - xs[lo]);
    out.push_back(ps[lo] * (1 - a) + ps[hi] * a);
  }
  return out;
}
}  // namespace

int main() {
  try {
    const json c = json::parse(std::string(std::istreambuf_iterator<char>(std::cin), {}));
    const auto t0 = std::chrono::steady_clock::now();
    auto model = make_fibre_model("mrg");
    const double d = c.value("diameter_um", 10.0);
    std::vector<double> ve;
    std::vector<std::size_t> detect;
    std::unique_ptr<CableSimulator> simulator;
    if (c.contains("afferent")) {
      // {"afferent": {"x_mm", "top_mm", "drop_mm", "direction", "stem_mm", and optionally
      // the shape's ending_um, ending_diameter_um, short_internodes, short_internode_um,
      // bend_radius_mm}}: the ending's tip at (x_mm, top_mm); detection at the sixth node
      // from the stem's end.
      const json& g = c["afferent"];
      AfferentShape shape;
      shape.ending_um = g.value("ending_um", shape.ending_um);
      shape.ending_diameter_um = g.value("ending_diameter_um", shape.ending_diameter_um);
      shape.short_internodes = g.value("short_internodes", shape.short_internodes);
      shape.short_internode_um = g.value("short_internode_um", shape.short_internode_um);
      shape.bend_radius_mm = g.value("bend_radius_mm", shape.bend_radius_mm);
      simulator = std::make_unique<CableSimulator>(
          *model,
          afferent_axon(*model, d, g.at("drop_mm").get<double>(), g.at("direction").get<int>(),
                        g.at("stem_mm").get<double>(), shape));
      const Axon& a = simulator->axon();
      std::vector<double> x, y;
      for (std::size_t k = 0; k < a.centre_um.size(); ++k) {
        x.push_back(g.at("x_mm").get<double>() + a.path_x_mm[k]);
        y.push_back(g.at("top_mm").get<double>() + a.path_y_mm[k]);
      }
      ve = field(c, x, y);
      detect = {a.nodes.size() - 6};
    } else {
      const auto nodes = c.value("nodes", 41);
      simulator = std::make_unique<CableSimulator>(*model, model->axon(d, nodes));
      const Axon& a = simulator->axon();
      const double mid = a.centre_um[a.nodes[static_cast<std::size_t>(nodes / 2)]];
      std::vector<double> x;
      for (double s : a.centre_um) x.push_back((s - mid) / 1000.0 + c.value("offset_mm", 0.0));
      ve = field(c, x);
      detect = {5, static_cast<std::size_t>(nodes - 6)};
    }
    CableSimulator& sim = *simulator;
    Waveform w;
    w.delay_ms = 0.1;
    for (const auto& p : c.value("pulse", json::array({json::array({0.2, 1.0})})))
      w.phases.push_back({p[0].get<double>(), p[1].get<double>()});
    SimOptions o;
    o.dt_ms = c.value("dt_ms", 0.005);
    o.tstop_ms = c.value("tstop_ms", 3.0);
    o.detect = detect;
    const double tol = c.value("tolerance", 1e-3);
    if (c.value("search", std::string("bisection")) == "lattice") {
      ThresholdSettings s;
      s.tolerance = tol;
      const auto t = fibre_threshold(*model, sim.axon(), ve, w, o, s);
      json out;
      out["threshold_mA"] = t ? json(*t) : json(nullptr);
      out["time_s"] =
          std::round(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() *
                     1e4) /
          1e4;
      std::cout << out.dump() << "\n";
      return 0;
    }
    double lo = 0.0, hi = 0.05;
    bool none = false;
    while (!sim.run(ve.data(), hi, w, o).fired) {
      lo = hi;
      hi *= 2;
      if (hi > 1e4) {
        none = true;
        break;
      }
    }
    while (!none && hi - lo > tol * hi) {
      const double m = 0.5 * (lo + hi);
      (sim.run(ve.data(), m, w, o).fired ? hi : lo) = m;
    }
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    json out;
    out["threshold_mA"] = none ? json(nullptr) : json(hi);
    out["time_s"] = std::round(s * 1e4) / 1e4;
    std::cout << out.dump() << "\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "mrg-case: " << e.what() << "\n";
    return 2;
  }
}
