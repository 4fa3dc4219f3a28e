#include "io/reports.hpp"

#include <cmath>

#include "core/error.hpp"
#include "io/csv.hpp"
#include "io/document.hpp"
#include "model/constants.hpp"
#include "core/ranges.hpp"
#include "opt/bank.hpp"
#include "opt/focus.hpp"
#include "opt/minimax.hpp"

namespace tp {

namespace {

// An axis along the skin (MIN and MAX within the positions' range), and the grid's size.
void check_lateral(const Axis& a, const std::string& flag) {
  ranges::check(a.min, ranges::position_mm, flag + " MIN");
  ranges::check(a.max, ranges::position_mm, flag + " MAX");
}
void check_points(const Axis& a, const Axis& b) {
  const double points = static_cast<double>(a.count()) * static_cast<double>(b.count());
  if (points > ranges::max_grid_points)
    bad_input("grid: " + number_text(points) + " points, more than " +
              number_text(ranges::max_grid_points));
}

}  // namespace

void validate_grid(const Axis& x, const Axis& y) {
  if (!(y.min > 0.0)) bad_input("--y: depths must be > 0 mm (the skin surface is y = 0)");
  ranges::check(y.min, ranges::depth_mm, "--y MIN");
  ranges::check(y.max, ranges::depth_mm, "--y MAX");
  check_lateral(x, "--x");
  check_points(x, y);
}

namespace {

// Rows (a, b, af_h, af_v) over the grid a (inner) by b (outer): values(a, b, af_h, af_v).
template <class F>
void write_map(const ByteSink& out, const char* b_name, const Axis& a, const Axis& b, F&& values) {
  CsvWriter csv(out, 1 << 20);
  csv.header({"x_mm", b_name, "af_h", "af_v"});
  const std::size_t na = a.count(), nb = b.count();
  double row[4];
  for (std::size_t j = 0; j < nb; ++j) {
    row[1] = b.at(j);
    for (std::size_t i = 0; i < na; ++i) {
      row[0] = a.at(i);
      values(row[0], row[1], row[2], row[3]);
      csv.row(row, 4);
    }
  }
  csv.flush();
}

}  // namespace

void write_af_grid(const ByteSink& out, const Field& field, const Axis& x, const Axis& y) {
  validate_grid(x, y);
  const double k = fibre_factor_mm2_per_ms(
      Fibre{Orientation::horizontal, constants::reference_diameter_um, true});
  write_map(out, "y_mm", x, y, [&](double xv, double yv, double& h, double& v) {
    double xx = 0.0, yy = 0.0;
    field.second_derivatives(xv, yv, xx, yy);
    h = k * xx;
    v = k * yy;
  });
}

void validate_plane(const Axis& x, const Axis& z, double y_mm) {
  ranges::check(y_mm, ranges::depth_mm, "--plane-depth");
  check_lateral(x, "--x");
  check_lateral(z, "--z-grid");
  check_points(x, z);
}

void write_af_plane(const ByteSink& out, const Field& field, const Axis& x, const Axis& z,
                    double y_mm) {
  validate_plane(x, z, y_mm);
  const Fibre fibre{Orientation::horizontal, constants::reference_diameter_um, true};
  const FibreAxis along_x{}, vertical{true, 0.0, 0.0};
  write_map(out, "z_mm", x, z, [&](double xv, double zv, double& h, double& v) {
    h = field.af_3d(fibre, along_x, xv, y_mm, zv);
    v = field.af_3d(fibre, vertical, xv, y_mm, zv);
  });
}

void check_grid_work(double points, std::size_t pads) {
  constexpr double kMaxWork = 6.4e9;
  const double work = points * static_cast<double>(pads);
  if (!(work <= kMaxWork))
    bad_input("grid: " + number_text(points) + " points x " + std::to_string(pads) +
              " pads = " + number_text(work) + " pad evaluations, more than " +
              number_text(kMaxWork) + " (a coarser or smaller grid)");
}

Axis default_z_axis(const ElectrodeArray& a) {
  return Axis{std::max(ranges::position_mm.lo, std::floor(a.z_min_mm() - 5.0)),
              std::min(ranges::position_mm.hi, std::ceil(a.z_max_mm() + 5.0)), 0.1};
}

Axis default_x_axis(const ElectrodeArray& a) {
  return Axis{std::max(ranges::position_mm.lo, std::floor(a.x_min_mm() - 5.0)),
              std::min(ranges::position_mm.hi, std::ceil(a.x_max_mm() + 5.0)), 0.1};
}
Axis default_y_axis() {
  return Axis{0.2, 3.0, 0.05};
}

Json summary_to_json(const Setup& setup, const std::vector<double>& currents_mA, const Summary& s) {
  Json j;
  j["format"] = "tactile-primaries/af-summary/1";
  j["af_unit"] = "V/ms";
  j["conductor"] = setup.conductor.model;
  if (setup.conductor.model == "layered") j["skin"] = effective_skin(setup.conductor).name;
  j["currents_mA"] = currents_mA;
  Json rec = Json::object();
  for (std::size_t i = 0; i < s.peaks.size(); ++i) {
    const Receptor& r = setup.receptors[i];
    const Peak& p = s.peaks[i].second;
    Json e;
    e["max_af"] = p.af;
    e["x_mm"] = p.x_mm;
    e["y_mm"] = p.y_mm;
    if (setup.array.two_d()) e["z_mm"] = p.z_mm;
    e["orientation"] = to_string(r.fibre.orientation);
    e["diameter_um"] = r.fibre.diameter_um;
    e["fibre_factor_mm2_per_ms"] = fibre_factor_mm2_per_ms(r.fibre);
    rec[s.peaks[i].first] = e;
  }
  j["receptors"] = rec;
  Json ratios = Json::object();
  for (const auto& [name, ratio] : s.ratios) ratios[name] = ratio ? Json(*ratio) : Json(nullptr);
  j["ratios"] = ratios;
  return j;
}

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
