#include "requests/optimize_reports.hpp"

#include <cmath>

#include "core/error.hpp"
#include "core/number.hpp"
#include "core/ranges.hpp"
#include "io/document.hpp"
#include "model/constants.hpp"
#include "opt/bank.hpp"
#include "opt/focus.hpp"
#include "opt/minimax.hpp"

namespace tp {

namespace {

// Each receptor's largest AF and where: {NAME: {max_af, x_mm, y_mm[, z_mm]}}.
Json peaks_json(const Setup& setup, const Summary& summary) {
  Json peaks = Json::object();
  for (const auto& [name, p] : summary.peaks) {
    Json e = Json{{"max_af", p.af}, {"x_mm", p.x_mm}, {"y_mm", p.y_mm}};
    if (setup.array.two_d()) e["z_mm"] = p.z_mm;
    peaks[name] = e;
  }
  return peaks;
}

}  // namespace

Json optimize_result_to_json(const Document& doc, const OptimizeResult& r, bool with_time,
                             const std::optional<double>& certified) {
  Document out = doc;
  out.weights = r.weights;
  out.extra = Json::object();
  Json j = document_to_json(out);
  j["mode"] = r.mode;
  j["ratio"] = r.ratio;
  if (certified) j["certified_optimum"] = *certified;
  j["af_unit"] = "V/ms";
  j["currents_mA"] = r.currents_mA;
  j["target_max_af"] = r.target_max_af;
  j["receptors_at_limit"] = peaks_json(doc.setup, r.summary);
  Json solver;
  solver["method"] = "p-norm surrogate (L-BFGS, Ceres) with continuation, LP polish (GLPK)";
  solver["starts"] = r.starts;
  solver["best_start"] = r.best_start;
  solver["iterations"] = r.iterations;
  solver["evaluations"] = r.evaluations;
  solver["lp_solves"] = r.lp_solves;
  if (with_time) solver["time_s"] = r.time_s;
  j["solver"] = solver;
  return j;
}

Json focus_result_to_json(const Document& doc, const FocusResult& r, const FocusOptions& o,
                          bool with_time) {
  Document out = doc;
  out.weights = r.weights;
  out.extra = Json::object();
  Json j = document_to_json(out);
  const bool two_d = doc.setup.array.two_d();
  j["mode"] = r.mode;
  j["ratio"] = r.ratio;
  j["af_unit"] = "V/ms";
  j["currents_mA"] = r.currents_mA;
  j["target_max_af"] = r.target_max_af;
  Json focus;
  focus["x_mm"] = o.x_mm;
  if (two_d) focus["z_mm"] = o.z_mm;
  focus["radius_mm"] = r.radius_mm;
  focus["spill_max"] = o.spill;
  focus["spill"] = r.spill;
  focus["pitch_mm"] = r.pitch_mm;
  focus["depth_mm"] = r.target_depth_mm;
  j["focus"] = focus;
  j["receptors_at_limit"] = peaks_json(doc.setup, r.summary);
  Json solver;
  solver["method"] = "LP at the focus (GLPK), then the least Sum w^2 within " +
                     number_text(o.tolerance) +
                     " of its optimum (NNLS), checked on the continuous fibres";
  solver["sampled_optimum"] = r.sampled_optimum;
  solver["samples"] = r.samples;
  solver["lp_solves"] = r.lp_solves;
  solver["rounds"] = r.rounds;
  solver["least_norm"] = r.least_norm;
  if (o.certify) {
    solver["certified_optimum"] = r.certified_optimum ? Json(*r.certified_optimum) : Json(nullptr);
    Json at = Json{{"x_mm", r.certified_at.x_mm}, {"y_mm", r.certified_at.y_mm}};
    if (two_d) at["z_mm"] = r.certified_at.z_mm;
    solver["certified_at"] = at;
    solver["certified_points"] = r.certified_points;
  }
  if (with_time) solver["time_s"] = r.time_s;
  j["solver"] = solver;
  return j;
}

Json bank_to_json(const Document& doc, const Bank& bank, const BankOptions& o) {
  Document out = doc;
  out.weights.reset();
  out.extra = Json::object();
  Json j = document_to_json(out);

  const ElectrodeArray& a = doc.setup.array;
  const bool two_d = a.two_d();
  std::vector<std::string> modes;
  for (std::size_t i = 0; i < bank.patterns.size() && bank.patterns[i].pixel == 0; ++i)
    modes.push_back(bank.patterns[i].mode);
  std::size_t derived = 0, infeasible = 0, failing = 0;
  for (const BankPattern& p : bank.patterns) {
    if (!p.solved) ++derived;
    if (!p.feasible)
      ++infeasible;
    else if (!p.result.bounds_hold)
      ++failing;
  }
  Json b;
  b["modes"] = modes;
  b["pitch_mm"] = nominal_pitch_mm(a);
  b["radius_mm"] = o.radius_mm > 0.0 ? o.radius_mm : nominal_pitch_mm(a);
  b["spill_max"] = o.spill;
  b["neighbourhood"] = o.neighbourhood > 0 ? Json(o.neighbourhood) : Json(nullptr);
  b["pixels"] = bank.pixels.size();
  b["patterns"] = bank.patterns.size();
  b["solved"] = bank.solves;
  b["derived"] = derived;
  b["infeasible"] = infeasible;
  b["bounds_broken"] = failing;
  b["af_unit"] = "V/ms";
  j["bank"] = b;
  Json pixels = Json::array();
  for (std::size_t px = 0; px < bank.pixels.size(); ++px) {
    Json e;
    e["x_mm"] = bank.pixels[px].first;
    if (two_d) e["z_mm"] = bank.pixels[px].second;
    e["pad"] = bank.pads[px] >= 0 ? Json(bank.pads[px]) : Json(nullptr);
    e["patterns"] = Json::object();
    pixels.push_back(e);
  }
  for (const BankPattern& p : bank.patterns) {
    Json e;
    if (!p.feasible) {
      e["feasible"] = false;
      e["reason"] = p.reason;
    } else {
      const FocusResult& r = p.result;
      e["weights"] = r.weights;
      e["ratio"] = r.ratio;
      e["target_max_af"] = r.target_max_af;
      const Peak& pk = r.summary.peaks[receptor_index(doc.setup, p.mode)].second;
      Json peak = Json{{"x_mm", pk.x_mm}, {"y_mm", pk.y_mm}};
      if (two_d) peak["z_mm"] = pk.z_mm;
      e["peak"] = peak;
      e["spill"] = r.spill;
      e["bounds_hold"] = r.bounds_hold;
    }
    if (p.solved) {
      e["derived"] = false;
    } else {
      const BankPattern& src = bank.patterns[p.from];
      Json d;
      d["pixel"] = src.pixel;
      // Relative to that pixel's pattern (each is a reflection of the problem solved).
      d["mirror_x"] = p.mirror_x != src.mirror_x;
      d["mirror_z"] = p.mirror_z != src.mirror_z;
      e["derived"] = d;
    }
    pixels[p.pixel]["patterns"][p.mode] = e;
  }
  j["pixels"] = pixels;
  return j;
}

std::string optimize_csv_header(const Setup& setup) {
  std::string h = "electrodes,pitch_mm,mode,ratio,target_max_af";
  for (const auto& rec : setup.receptors) h += ",max_af_" + rec.name;
  for (std::size_t i = 0; i < setup.array.size(); ++i) h += ",w" + std::to_string(i);
  return h + "\n";
}

std::string focus_csv_row(const Setup& setup, const FocusResult& r) {
  OptimizeResult o;
  o.mode = r.mode;
  o.ratio = r.ratio;
  o.target_max_af = r.target_max_af;
  o.summary = r.summary;
  o.weights = r.weights;
  return optimize_csv_row(setup, o);
}

std::string optimize_csv_row(const Setup& setup, const OptimizeResult& r) {
  const auto num = number_text;
  std::string line = std::to_string(setup.array.size()) + "," +
                     (setup.array.pitch_mm ? num(*setup.array.pitch_mm) : std::string()) + "," +
                     r.mode + "," + num(r.ratio) + "," + num(r.target_max_af);
  for (const auto& p : r.summary.peaks) line += "," + num(p.second.af);
  for (double w : r.weights) line += "," + num(w);
  return line + "\n";
}


}  // namespace tp
