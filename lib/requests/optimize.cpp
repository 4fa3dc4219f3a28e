#include "requests/optimize.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <thread>
#include <utility>

#include "core/error.hpp"
#include "core/text.hpp"
#include "core/number.hpp"
#include "requests/document_options.hpp"
#include "requests/optimize_reports.hpp"
#include "core/ranges.hpp"
#include "opt/bank.hpp"
#include "render/recruitment.hpp"
#include "opt/focus.hpp"
#include "opt/minimax.hpp"
#include "opt/selectivity_design.hpp"
#include "opt/threshold_objective.hpp"

namespace tp {

namespace {

// The checks the program's parser makes, for values that come without it, in its words.
void check_whole(const std::string& flag, long value, long lo, long hi) {
  if (!(value >= lo && value <= hi))
    bad_input(flag + ": " + std::to_string(value) + " outside [" + std::to_string(lo) + ", " +
              std::to_string(hi) + "]");
}
void check_finite(const std::string& flag, std::optional<double> value) {
  if (value && !std::isfinite(*value))
    parse_finite(std::isnan(*value) ? "nan" : *value > 0 ? "inf" : "-inf", flag);
}

enum class Design { modes, pixel, bank, threshold, selectivity };

// The checked request: the document with its current limit, and what the design runs on.
struct OptimizePlan {
  Document doc;
  Design design = Design::modes;
  OptimizeOptions opt;
  FocusOptions focus;
  std::vector<std::pair<double, double>> places;  // (x, z) mm
  BankOptions bank;
  FibreOptions fibre;
  fibre::ThresholdSearchOptions search;
  fibre::SelectivityOptions selectivity;
  std::optional<RecruitmentOptions> recruitment;  // a bank's (--population)
};

bool by_threshold(const OptimizeRequest& r) {
  return r.objective == OptimizeObjective::threshold;
}
bool by_selectivity(const OptimizeRequest& r) {
  return r.objective == OptimizeObjective::selectivity;
}
// The objectives by a fibre model (their flags, one mode, JSON).
bool by_fibre(const OptimizeRequest& r) { return by_threshold(r) || by_selectivity(r); }
std::string objective_flag(const OptimizeRequest& r) {
  return by_selectivity(r) ? "--objective selectivity" : "--objective threshold";
}

std::string given_or(const std::string& given, const std::string& number) {
  return given.empty() ? number : given;
}

// A pixel's place as the user gave it: the flag's text, or the numbers, comma-separated.
std::string at_text(const OptimizeRequest& r, std::size_t k) {
  if (k < r.given.at.size()) return r.given.at[k];
  std::string text;
  for (double v : r.at_mm[k]) text += (text.empty() ? "" : ",") + number_text(v);
  return text;
}

// The checks the program's parser makes (whole numbers' ranges, finite numbers).
void check_values(const OptimizeRequest& r) {
  if (r.pattern_starts) check_whole("--pattern-starts", *r.pattern_starts, 0, 4);
  if (r.random_starts) check_whole("--random-starts", *r.random_starts, 0, 1000);
  if (r.max_evaluations)
    check_whole("--max-evaluations", *r.max_evaluations, 10, by_selectivity(r) ? 1000 : 10000);
  if (r.population) check_whole("--population", *r.population, 1, 1000);
  check_finite("--max-charge", r.max_charge_nC);
  if (r.max_charge_nC && !(*r.max_charge_nC > 0 && *r.max_charge_nC <= 1e5))
    bad_input("--max-charge: " + number_text(*r.max_charge_nC) + " nC outside (0, 100000] nC");
  if (r.neighbourhood) check_whole("--neighbourhood", *r.neighbourhood, 3, 255);
  if (r.threads) check_whole("--threads", *r.threads, 1, 256);
  check_finite("--max-current", r.max_current_mA);
  check_finite("--min-target-af", r.min_target_af);
  check_finite("--radius", r.radius_mm);
  check_finite("--spill", r.spill);
  for (const std::vector<double>& place : r.at_mm)
    for (double v : place) check_finite("--at", v);
}

// The array, and the options that need a pixel, a bank or a mode.
void check_array(const Document& doc, const OptimizeRequest& r) {
  const ElectrodeArray& a = doc.setup.array;
  if (a.size() < 2) bad_input("array: optimisation needs at least 2 electrodes");
  if (a.two_d())
    refuse_plane_z(doc, r.plane_z_given,
                   "under a 2-D array (its fibres fill every z; the plane places af-field's x-y "
                   "section only)");
  if (a.two_d() && r.at_mm.empty() && !r.bank)
    bad_input("array: " + a.describe() + " is 2-D: give a pixel's place, --at X,Z (or --bank)");
  if (r.modes.empty() && !r.bank) bad_input("--mode: required (RA, SAI, PC, ...)");
  if ((r.radius_mm || r.spill) && r.at_mm.empty() && !r.bank)
    bad_input("--radius, --spill: apply to a pixel (--at) or a bank (--bank)");
  if (r.neighbourhood && !r.bank) bad_input("--neighbourhood: with --bank only");
  if (r.at_mm.size() > 1 && !r.bank) bad_input("--at: one place (several: with --bank)");
}

// The current limit (set on the document) and the AF objective's options.
OptimizeOptions solver_options(Document& doc, const OptimizeRequest& r) {
  if (r.max_current_mA) doc.max_current_mA = *r.max_current_mA;
  ranges::check(doc.max_current_mA, ranges::max_current_mA, "--max-current");
  OptimizeOptions opt;
  opt.max_current_mA = doc.max_current_mA;
  opt.min_target_af = r.min_target_af;
  if (!(opt.min_target_af <= 1e4))  // the paper's optima reach 0.8 to 6 V/ms
    bad_input(
        "--min-target-af: " + given_or(r.given.min_target_af, number_beside(r.min_target_af, 1e4)) +
        " V/ms outside [0, 10000] V/ms");
  if (opt.min_target_af < 0.0) bad_input("--min-target-af: must be >= 0");
  opt.random_starts = r.random_starts.value_or(0);
  opt.pattern_starts = r.pattern_starts.value_or(2);
  return opt;
}

// Every mode named once, each in the document's table, all before any work.
void check_modes(const Document& doc, const OptimizeRequest& r) {
  std::string text;  // --mode as given
  for (std::size_t k = 0; k < r.modes.size(); ++k) text += (k ? "," : "") + r.modes[k];
  for (std::size_t k = 0; k < r.modes.size(); ++k) {
    if (r.modes[k].empty()) bad_input("--mode: empty name in " + quoted_text(text));
    for (std::size_t q = 0; q < k; ++q)
      if (r.modes[q] == r.modes[k])
        bad_input("--mode: " + quoted_text(r.modes[k]) + " given twice");
  }
  for (const std::string& m : r.modes) receptor_index(doc.setup, m);
  if (r.modes.size() > 1 && !r.csv && !r.bank && !by_fibre(r))
    bad_input("--mode: several modes need --format csv (one row each)");
}

// The threshold objective's flags, refused with the AF objective (--threads serves a pixel
// and a bank too).
void check_threshold_flags(const OptimizeRequest& r) {
  const std::pair<const char*, bool> design[] = {{"--population", r.population.has_value()},
                                                 {"--seed", r.seed.has_value()},
                                                 {"--max-charge", r.max_charge_nC.has_value()}};
  for (const auto& [flag, is_given] : design)
    if (is_given && !by_selectivity(r) && !(r.bank && std::string(flag) != "--max-charge"))
      bad_input(std::string(flag) + ": applies to --objective selectivity" +
                (std::string(flag) == "--max-charge" ? "" : " or --bank") + " only");
  if (by_fibre(r)) return;
  const FibreOptions& f = r.fibre;
  const std::pair<const char*, bool> given[] = {
      {"--fibre-model", r.fibre_model_given},
      {"--stimulus", !f.stimulus.empty()},
      {"--width", f.width_us.has_value()},
      {"--interphase", f.interphase_us.has_value()},
      {"--balance-width", f.balance_width_us.has_value()},
      {"--monophasic", f.monophasic},
      {"--phases", !f.phases.empty()},
      {"--geometry", f.geometry != "straight"},
      {"--offsets", r.offsets_given},
      {"--tolerance", f.tolerance.has_value()},
      {"--threads", r.threads && !r.bank && r.at_mm.empty()},
      {"--max-evaluations", r.max_evaluations.has_value()}};
  for (const auto& [flag, is_given] : given)
    if (is_given)
      bad_input(std::string(flag) + ": applies to --objective threshold or selectivity only" +
                (std::string(flag) == "--threads" ? ", --at and --bank" : ""));
}

// The pixels' places, X or X,Z by the array.
std::vector<std::pair<double, double>> places_of(const Document& doc, const OptimizeRequest& r) {
  const bool two_d = doc.setup.array.two_d();
  std::vector<std::pair<double, double>> places;
  for (std::size_t k = 0; k < r.at_mm.size(); ++k) {
    const std::vector<double>& xz = r.at_mm[k];
    if (xz.size() != (two_d ? 2u : 1u))
      bad_input("--at: expected " + std::string(two_d ? "X,Z (a 2-D array)" : "X (a 1-D array)") +
                ", got " + quoted_text(at_text(r, k)));
    places.emplace_back(xz[0], two_d ? xz[1] : 0.0);
  }
  return places;
}

FocusOptions focus_options(const OptimizeRequest& r, double max_current_mA) {
  FocusOptions focus;
  if (r.radius_mm) {
    focus.radius_mm = *r.radius_mm;
    if (!(focus.radius_mm > 0.0))
      bad_input("--radius: must be > 0 mm (omit it for one pitch), got " +
                given_or(r.given.radius, number_text(*r.radius_mm)));
  }
  if (r.spill) focus.spill = *r.spill;
  focus.max_current_mA = max_current_mA;
  return focus;
}

BankOptions bank_options(const OptimizeRequest& r, const OptimizePlan& p) {
  if (by_fibre(r)) bad_input("--bank: designs by the AF objective only");
  if (r.certify) bad_input("--certify: with --bank is not available yet");
  if (p.opt.min_target_af > 0) bad_input("--min-target-af: does not apply with --bank");
  if (r.csv || r.header_only || !r.header)
    bad_input("--bank: JSON output only (no --format csv, --header-only, --no-header)");
  if (r.pattern_starts || r.random_starts)
    bad_input("--pattern-starts, --random-starts: do not apply with --bank");
  if (r.population && !r.at_mm.empty())
    bad_input("--population: with --bank, every pad's pixel (no --at): render-tactile's bank");
  if (r.population && !p.doc.setup.array.grid())
    bad_input("--population: with --bank on a grid of pads only");
  if (r.seed && !r.population)
    bad_input("--seed: with --bank, seeds the recruitment's population: give --population N");
  BankOptions b;
  b.modes = r.modes;
  b.at = p.places;
  b.radius_mm = p.focus.radius_mm;
  b.spill = p.focus.spill;
  b.max_current_mA = p.focus.max_current_mA;
  b.neighbourhood = r.neighbourhood.value_or(0);
  b.threads = static_cast<unsigned>(r.threads.value_or(0));
  if (r.progress)
    b.progress = [progress = r.progress](const BankProgress& q) {
      progress(q.judged == 0 ? "bank " + std::to_string(q.solved) + " of " +
                                   std::to_string(q.problems) + " problems"
                             : "bank " + std::to_string(q.judged) + " of " +
                                   std::to_string(q.patterns) + " patterns judged",
               q.judged == 1);  // the second stage: shown as it starts
    };
  return b;
}

// A bank's recruitment (--bank --population N [--seed S]): the modes' colours for
// render-tactile's gamut, at its default pulse, by the MRG model.
RecruitmentOptions recruitment_options(const OptimizeRequest& r) {
  RecruitmentOptions o;
  o.per_class = static_cast<std::size_t>(*r.population);
  o.seed = r.seed.value_or(1);
  o.threads = static_cast<unsigned>(r.threads.value_or(0));
  if (r.progress)
    o.progress = [progress = r.progress](std::size_t done, std::size_t total) {
      progress("recruitment " + std::to_string(done) + " of " + std::to_string(total) +
                   " afferents",
               done == 1);
    };
  return o;
}

// The single-target designs' output options.
void check_outputs(const OptimizeRequest& r) {
  if (by_fibre(r) && (r.csv || r.modes.size() > 1))
    bad_input(objective_flag(r) + ": one mode, JSON output");
  if (by_fibre(r) && r.certify)
    bad_input("--certify: certifies the AF problem, not " + objective_flag(r));
  if (by_fibre(r) && r.min_target_af > 0)
    bad_input("--min-target-af: applies to the AF objective only");
  if (r.certify && r.csv)
    bad_input("--certify: the certified optimum is reported in JSON only (--format json)");
}

void plan_pixel(const OptimizeRequest& r, OptimizePlan& p) {
  p.focus.x_mm = p.places[0].first;
  p.focus.z_mm = p.places[0].second;
  p.focus.threads = r.threads ? static_cast<unsigned>(*r.threads)
                              : std::max(1u, std::thread::hardware_concurrency());
  check_focus(p.doc.setup, p.focus);
  if (by_threshold(r))
    bad_input("--at: designs by the AF objective or --objective selectivity, not --objective "
              "threshold");
  p.focus.certify = r.certify;
  if (p.opt.min_target_af > 0) bad_input("--min-target-af: does not apply with --at");
  if (!r.csv && r.modes.size() > 1)
    bad_input("--at: several modes need --format csv (one row each)");
  if (r.csv && r.certify) bad_input("--certify: the certified optimum is reported in JSON only");
  if (r.pattern_starts || r.random_starts)
    bad_input(
        "--pattern-starts, --random-starts: do not apply with --at (the focus is solved by "
        "linear programming)");
}

// The selectivity design's options: the population, the budget, the limits at I50 (the
// document's current limit, make-pulse's default rate, the document's pads).
void plan_selectivity(const OptimizeRequest& r, OptimizePlan& p) {
  fibre::SelectivityOptions& s = p.selectivity;
  s.per_class = static_cast<std::size_t>(r.population.value_or(30));
  s.seed = r.seed.value_or(1);
  s.held_out_seed = s.seed + 1;  // wraps at 2^64 - 1: still another population
  s.max_evaluations = static_cast<std::size_t>(r.max_evaluations.value_or(40));
  s.max_charge_nC = r.max_charge_nC.value_or(0.0);
  s.limits.max_current_mA = p.opt.max_current_mA;
  s.electrode_area_mm2 = p.doc.setup.array.width_mm * p.doc.setup.array.length_mm;
  s.threads = static_cast<unsigned>(r.threads.value_or(0));
  if (r.progress)
    s.progress = [progress = r.progress, n = s.max_evaluations](std::size_t k,
                                                               const std::string& stage) {
      progress("selectivity design " + std::to_string(std::min(k, n)) + " of at most " +
                   std::to_string(n) + " populations (" + stage + ")",
               false);
    };
}

void plan_threshold(const OptimizeRequest& r, OptimizePlan& p) {
  p.fibre = r.fibre;
  p.fibre.model_flag = "--fibre-model";
  p.fibre.threads = r.threads.value_or(0);
  if (by_selectivity(r)) {
    // A 1 % lattice unless --tolerance says otherwise: the populations rank designs, and a
    // population's fractions move by whole afferents (docs/fibres.md).
    if (!p.fibre.tolerance) p.fibre.tolerance = 0.01;
    plan_selectivity(r, p);
    p.design = Design::selectivity;
    return;
  }
  p.search.max_evaluations = static_cast<std::size_t>(r.max_evaluations.value_or(12));
  if (r.progress)
    p.search.progress = [progress = r.progress, n = p.search.max_evaluations](std::size_t k) {
      progress("threshold search " + std::to_string(k) + " of at most " + std::to_string(n) +
                   " whole searches",
               false);
    };
}

// Every check, in the program's order; the plan each design runs.
OptimizePlan plan_optimize(const Document& doc, const OptimizeRequest& r) {
  check_values(r);
  OptimizePlan p;
  p.doc = doc;
  check_array(p.doc, r);
  p.opt = solver_options(p.doc, r);
  check_modes(p.doc, r);
  check_threshold_flags(r);
  p.places = places_of(p.doc, r);
  p.focus = focus_options(r, p.opt.max_current_mA);
  if (r.bank) {
    p.design = Design::bank;
    p.bank = bank_options(r, p);
    if (r.population) p.recruitment = recruitment_options(r);
    return p;
  }
  check_outputs(r);
  if (!p.places.empty()) {
    p.design = Design::pixel;
    plan_pixel(r, p);
  }
  if (r.header_only && !r.csv) bad_input("--header-only: needs --format csv");
  if (p.design == Design::modes && by_threshold(r)) p.design = Design::threshold;
  if (by_fibre(r)) plan_threshold(r, p);
  return p;
}

// ---------------------------------------------------------------------------------------
// The designs.

OptimizeOutput run_bank(const OptimizePlan& p) {
  OptimizeOutput out;
  const Bank result = optimize_bank(p.doc.setup, p.bank);
  out.document = bank_to_json(p.doc, result, p.bank);
  std::vector<std::string> recruitment;
  if (p.recruitment) {
    const BankRecruitment rec =
        bank_recruitment(pixel_bank_from_json(out.document), *p.recruitment, &recruitment);
    out.document["recruitment"] = recruitment_to_json(rec);
    recruitment.push_back(recruitment_note(rec));
  }
  std::size_t infeasible = 0, broken = 0;
  for (const BankPattern& q : result.patterns) {
    if (!q.feasible)
      ++infeasible;
    else if (!q.result.bounds_hold)
      ++broken;
  }
  char line[256];
  std::snprintf(line, sizeof line,
                "bank of %zu pixels x %zu modes: %d solved, %zu derived, %zu with no pattern, "
                "%zu breaking a bound on the whole array",
                result.pixels.size(),
                result.patterns.size() / std::max<std::size_t>(1, result.pixels.size()),
                result.solves, result.patterns.size() - static_cast<std::size_t>(result.solves),
                infeasible, broken);
  out.notes.push_back(line);
  out.notes.insert(out.notes.end(), recruitment.begin(), recruitment.end());
  return out;
}

OptimizeOutput run_pixel(const OptimizePlan& p, const OptimizeRequest& r) {
  OptimizeOutput out;
  if (r.csv && r.header) out.text = optimize_csv_header(p.doc.setup);
  for (const std::string& m : r.modes) {
    const FocusResult f = optimize_focus(p.doc.setup, m, p.focus);
    if (r.csv)
      out.text += focus_csv_row(p.doc.setup, f);
    else
      out.document = focus_result_to_json(p.doc, f, p.focus, r.timing);
    if (!f.least_norm)
      out.notes.push_back("warning: " + m +
                          ": the least-Sum-w^2 step did not converge; these are the LP's "
                          "weights, optimal but not the unique least-power ones");
    char line[320];
    std::snprintf(line, sizeof line,
                  "%s pixel at %s, ratio %.6g, spill %.3g (at most %.3g beyond %.3g mm), target "
                  "AF %.4g V/ms at %.3g mA, %d rounds, %.3f s",
                  m.c_str(), at_text(r, 0).c_str(), f.ratio, f.spill, p.focus.spill, f.radius_mm,
                  f.target_max_af, p.opt.max_current_mA, f.rounds, f.time_s);
    out.notes.push_back(line);
  }
  return out;
}

OptimizeOutput run_modes(const OptimizePlan& p, const OptimizeRequest& r) {
  OptimizeOutput out;
  const OptimizeOptions& opt = p.opt;
  if (r.csv && r.header) out.text = optimize_csv_header(p.doc.setup);
  for (const std::string& m : r.modes) {
    const OptimizeResult o = optimize_mode(p.doc.setup, m, opt);
    std::optional<double> certified;
    if (r.certify) {
      const double bound = opt.min_target_af > 0 ? opt.max_current_mA / opt.min_target_af : 0.0;
      certified = certify_mode(p.doc.setup, m, opt.polish_step_mm, bound).optimum;
    }
    if (r.csv)
      out.text += optimize_csv_row(p.doc.setup, o);
    else
      out.document = optimize_result_to_json(p.doc, o, r.timing, certified);
    char line[256];
    std::snprintf(line, sizeof line,
                  "%s ratio %.6g, target AF %.4g V/ms at %.3g mA, %d starts, %.3f s", m.c_str(),
                  o.ratio, o.target_max_af, opt.max_current_mA, o.starts, o.time_s);
    out.notes.push_back(line);
  }
  return out;
}

// The threshold objective's document: the input's, with the weights the search found, the
// AF ratio and currents at them, every receptor's threshold, and where the search started.
Json threshold_document(const OptimizePlan& p, const std::string& mode, const OptimizeResult& af,
                        const fibre::ThresholdOptimum& t) {
  const std::size_t target = receptor_index(p.doc.setup, mode);
  Document out = p.doc;
  out.weights = t.weights;
  std::vector<double> currents;
  for (double w : t.weights) currents.push_back(w * p.opt.max_current_mA);
  const Summary s = summarize(p.doc.setup, currents);
  out.extra.erase("thresholds");
  out.extra.erase("threshold_ratio");
  out.extra["mode"] = mode;
  out.extra["objective"] = "threshold";
  const auto af_ratio = mode_ratio(s.peaks, mode);
  out.extra["ratio"] = af_ratio ? Json(*af_ratio) : Json(nullptr);
  out.extra["currents_mA"] = currents;
  out.extra["thresholds"] = fibre::thresholds_to_json(p.doc.setup, t.report);
  out.extra["threshold_ratio"] = fibre::ratios_to_json(p.doc.setup, t.report);
  Json start = Json::object();
  start["weights"] = af.weights;
  start["ratio"] = af.ratio;
  start["threshold_ratio"] = t.start.ratios[target] ? Json(*t.start.ratios[target]) : Json(nullptr);
  start["threshold_mA"] = t.start.receptors[target].threshold_mA
                              ? Json(*t.start.receptors[target].threshold_mA)
                              : Json(nullptr);
  out.extra["af_optimum"] = start;
  Json search = Json::object();
  search["method"] =
      "Nelder-Mead over the zero-sum weights from the AF optimum, on linear stand-ins checked "
      "by whole searches, then on whole searches";
  search["evaluations"] = t.evaluations;
  search["rounds"] = t.rounds;
  search["improved"] = t.improved;
  out.extra["threshold_search"] = search;
  return document_to_json(out);
}

OptimizeOutput run_threshold(const OptimizePlan& p, const std::string& mode) {
  const OptimizeResult af = optimize_mode(p.doc.setup, mode, p.opt);
  const FibreSetup f = apply_fibre_options(p.fibre, af.weights);
  const std::size_t target = receptor_index(p.doc.setup, mode);
  const fibre::ThresholdOptimum t = fibre::optimize_threshold(
      p.doc.setup, target, af.weights, *f.model, f.pulse, f.settings, p.search);
  OptimizeOutput out;
  out.document = threshold_document(p, mode, af, t);
  const auto& ratio = out.document["ratio"];
  char line[1024];
  std::snprintf(line, sizeof line, "%s, AF ratio %.4g, %zu evaluations, %s, %s",
                fibre::threshold_search_summary(t, target, f.settings.max_mA).c_str(),
                ratio.is_number() ? ratio.get<double>() : 0.0, t.evaluations, f.model->name(),
                f.pulse.describe().c_str());
  out.notes.push_back(line);
  return out;
}

// The selectivity design's document: the input's, with the weights and the pulse found,
// their AF ratio, the index and recruitment on the design's and the held-out population,
// the starts scored alike, and the search with its front (docs/document-format.md).
Json score_json(const fibre::SelectivityScore& s, const std::vector<std::string>& classes) {
  Json j = Json::object();
  j["index"] = s.fires ? Json(s.half.index) : Json(nullptr);
  j["i50_mA"] = s.fires ? Json(s.half.i50_mA) : Json(nullptr);
  Json rec = Json::object();
  for (std::size_t k = 0; k < classes.size() && k < s.half.fraction.size(); ++k)
    rec[classes[k]] = s.half.fraction[k];
  j["recruited"] = s.fires ? rec : Json(nullptr);
  j["worst"] = s.fires ? Json(s.half.worst) : Json(nullptr);
  j["margin"] = s.fires ? Json(s.margin) : Json(nullptr);
  j["charge_per_phase_nC"] = s.fires ? Json(s.charge_nC) : Json(nullptr);
  if (!s.refused.empty()) j["refused"] = s.refused;
  return j;
}

Json design_json(const fibre::ScoredDesign& d, const std::vector<std::string>& classes) {
  Json j = Json::object();
  j["name"] = d.name;
  j["weights"] = d.design.weights;
  Json pulse = Json::object();
  pulse["phases"] = phases_to_json(d.design.phases);
  j["pulse"] = pulse;
  j["design_population"] = score_json(d.score, classes);
  j["held_out"] = score_json(d.held_out, classes);
  return j;
}

Json selectivity_document(const OptimizePlan& p, const std::string& mode,
                          const fibre::SelectivityResult& r) {
  const fibre::SelectivityOptions& o = p.selectivity;
  std::vector<std::string> classes;
  for (const fibre::AfferentClass& c : fibre::default_afferent_classes()) classes.push_back(c.receptor);
  Document out = p.doc;
  out.weights = r.best.design.weights;
  std::vector<double> currents;
  for (double w : r.best.design.weights) currents.push_back(w * p.opt.max_current_mA);
  const Summary s = summarize(p.doc.setup, currents);
  for (const char* stale : {"thresholds", "threshold_ratio", "threshold_search", "af_optimum"})
    out.extra.erase(stale);
  out.extra["mode"] = mode;
  out.extra["objective"] = "selectivity";
  Json pulse = Json::object();
  pulse["phases"] = phases_to_json(r.best.design.phases);
  out.extra["pulse"] = pulse;
  const auto af_ratio = mode_ratio(s.peaks, mode);
  out.extra["ratio"] = af_ratio ? Json(*af_ratio) : Json(nullptr);
  if (!p.places.empty()) out.extra["at_mm"] = p.doc.setup.array.two_d()
                                                  ? Json({p.places[0].first, p.places[0].second})
                                                  : Json({p.places[0].first});
  Json sel = score_json(r.best.score, classes);
  sel["definition"] =
      "1 - 2 x the largest fraction of another class recruited at I50, the least current "
      "recruiting half of the target class (docs/fibres.md)";
  Json pop = Json::object();
  pop["per_class"] = o.per_class;
  pop["seed"] = o.seed;
  sel["population"] = pop;
  Json held = score_json(r.best.held_out, classes);
  held["seed"] = o.held_out_seed;
  sel["held_out"] = held;
  sel["comfort_bound_nC"] = r.max_charge_nC > 0 ? Json(r.max_charge_nC) : Json(nullptr);
  out.extra["selectivity"] = sel;
  Json starts = Json::array();
  for (const fibre::ScoredDesign& d : r.starts) starts.push_back(design_json(d, classes));
  out.extra["starts"] = starts;
  Json search = Json::object();
  search["method"] =
      "from the starts, turns of a pass over the pulse's shape (polarity, main phase width, "
      "recovery asymmetry, prepulse), one parameter at a time on a grid, and Nelder-Mead over "
      "the zero-sum weights, on one population; each design scored where it can be delivered "
      "at its I50";
  search["evaluations"] = r.evaluations;
  search["turns"] = r.turns;
  search["improved"] = r.improved;
  Json front = Json::array();
  for (const fibre::FrontPoint& f : r.front) {
    Json q = Json::object();
    q["charge_per_phase_nC"] = f.charge_nC;
    q["index"] = f.index;
    q["i50_mA"] = f.i50_mA;
    q["phases"] = describe_phases(f.phases);
    front.push_back(q);
  }
  search["front"] = front;
  out.extra["selectivity_search"] = search;
  return document_to_json(out);
}

// The starts: the AF optimum (a pixel's focus, at --at), and on an array the threshold
// optimum where it differs; each with the pulse asked.
std::vector<fibre::ScoredDesign> selectivity_starts(const OptimizePlan& p, const std::string& mode,
                                                   const FibreSetup& f,
                                                   const std::vector<double>& af) {
  const std::vector<Phase> phases = f.pulse.delivered();
  std::vector<fibre::ScoredDesign> starts{{"af optimum", {af, phases}, {}, {}}};
  if (!p.places.empty()) return starts;
  fibre::ThresholdSearchOptions search;
  const fibre::ThresholdOptimum t = fibre::optimize_threshold(
      p.doc.setup, receptor_index(p.doc.setup, mode), af, *f.model, f.pulse, f.settings, search);
  if (t.improved) starts.push_back({"threshold optimum", {t.weights, phases}, {}, {}});
  return starts;
}

OptimizeOutput run_selectivity(const OptimizePlan& p, const std::string& mode) {
  const std::vector<double> af = p.places.empty()
                                     ? optimize_mode(p.doc.setup, mode, p.opt).weights
                                     : optimize_focus(p.doc.setup, mode, p.focus).weights;
  const FibreSetup f = apply_fibre_options(p.fibre, af);
  fibre::check_selectivity(p.doc.setup, mode, *f.model, f.settings, p.selectivity);
  const std::vector<fibre::ScoredDesign> starts = selectivity_starts(p, mode, f, af);
  const fibre::SelectivityResult r =
      fibre::design_for_selectivity(p.doc.setup, mode, starts, *f.model, f.settings, p.selectivity);
  OptimizeOutput out;
  out.document = selectivity_document(p, mode, r);
  char line[1024];
  std::snprintf(line, sizeof line, "%s, %zu populations of %zu a class, %s, %s",
                fibre::selectivity_summary(r, mode).c_str(), r.evaluations,
                p.selectivity.per_class, f.model->name(), describe_phases(r.best.design.phases).c_str());
  out.notes.push_back(line);
  return out;
}

}  // namespace

void parse_optimize_text(const OptimizeText& t, OptimizeRequest& r) {
  for (std::size_t a = 0; !t.modes.empty();) {  // several, comma-separated
    const std::size_t b = t.modes.find(',', a);
    r.modes.push_back(t.modes.substr(a, b == std::string::npos ? std::string::npos : b - a));
    if (b == std::string::npos) break;
    a = b + 1;
  }
  if (!t.max_current_mA.empty()) r.max_current_mA = parse_finite(t.max_current_mA, "--max-current");
  if (!t.min_target_af.empty()) r.min_target_af = parse_finite(t.min_target_af, "--min-target-af");
  r.given.min_target_af = t.min_target_af;
  r.fibre = fibre_values(t.fibre);
  for (const std::string& p : t.at) r.at_mm.push_back(parse_list(p, "--at"));
  r.given.at = t.at;
  if (!t.radius_mm.empty()) r.radius_mm = parse_finite(t.radius_mm, "--radius");
  r.given.radius = t.radius_mm;
  if (!t.spill.empty()) r.spill = parse_finite(t.spill, "--spill");
  if (!t.max_charge_nC.empty()) r.max_charge_nC = parse_finite(t.max_charge_nC, "--max-charge");
}

void check_optimize(const Document& doc, const OptimizeRequest& r) {
  plan_optimize(doc, r);
}

OptimizeOutput run_optimize(const Document& doc, const OptimizeRequest& r) {
  const OptimizePlan p = plan_optimize(doc, r);
  if (r.header_only) {  // the checks, and no work
    OptimizeOutput out;
    out.text = optimize_csv_header(p.doc.setup);
    return out;
  }
  OptimizeOutput out = p.design == Design::bank        ? run_bank(p)
                       : p.design == Design::pixel     ? run_pixel(p, r)
                       : p.design == Design::threshold ? run_threshold(p, r.modes[0])
                       : p.design == Design::selectivity ? run_selectivity(p, r.modes[0])
                                                       : run_modes(p, r);
  if (!r.csv) out.text = dump_json(out.document);
  return out;
}

}  // namespace tp
