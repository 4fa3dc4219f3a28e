#include "requests/threshold.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "core/error.hpp"
#include "fibre/threshold.hpp"
#include "core/number.hpp"
#include "core/ranges.hpp"

namespace tp {

namespace {

// The weights: one per electrode, each in range, not all zero; returns max |w|.
double checked_peak_weight(const Document& doc) {
  if (!doc.weights)
    bad_input("weights: the document has none (optimize-weights writes them; or --weights)");
  const std::vector<double>& w = *doc.weights;
  if (w.size() != doc.setup.array.size())
    bad_input("weights: expected " + std::to_string(doc.setup.array.size()) +
              " values (one per electrode), got " + std::to_string(w.size()));
  double wmax = 0.0;
  for (std::size_t i = 0; i < w.size(); ++i) {
    ranges::check(w[i], ranges::weight, "weights item " + std::to_string(i + 1));
    wmax = std::max(wmax, std::fabs(w[i]));
  }
  if (!(wmax > 0.0)) bad_input("weights: every weight is zero");
  return wmax;
}

// The options that go with one mode only, and the population's count.
void check_modes(const ThresholdRequest& r) {
  if (r.population && !(*r.population >= 1 && *r.population <= fibre::kMaxPopulation))
    bad_input("--population: " + std::to_string(*r.population) + " outside [1, " +
              std::to_string(fibre::kMaxPopulation) + "]");
  if (r.widths_us && !r.strength_duration)
    bad_input("--widths: applies to --strength-duration only");
  if (r.population && r.strength_duration)
    bad_input("--population and --strength-duration: give one");
  if ((r.seed || !r.recruitment.empty()) && !r.population)
    bad_input("--seed, --recruitment: apply to --population only");
  if (r.population && r.at_mm)
    bad_input(
        "--at: does not apply to --population (its afferents are sampled over the "
        "whole array and its margin, each through its own place)");
}

// The whole table's work, bounded before any of it.
void check_strength_duration_work(const ThresholdPlan& p) {
  double work = 0.0;
  for (double w : p.widths_us)
    work += fibre::thresholds_work(p.doc.setup, *p.fibre.model,
                                   fibre::pulse_at_width(p.fibre.pulse, w), p.fibre.settings);
  fibre::check_threshold_work(
      work, fibre::kMaxThresholdWork,
      "--strength-duration (" + std::to_string(p.widths_us.size()) + " widths)");
}

// "mrg, 200 us biphasic (200 us balance): RA 1.003 mA (ratio 1.43), ..."
std::string thresholds_line(const fibre::ThresholdReport& rep, const FibreSetup& f) {
  std::string talk = std::string(f.model->name()) + ", " + f.pulse.describe() + ":";
  for (std::size_t k = 0; k < rep.receptors.size(); ++k) {
    const auto& t = rep.receptors[k];
    char b[64];
    std::snprintf(b, sizeof b, "%.4g mA", t.threshold_mA ? *t.threshold_mA : 0.0);
    talk += " " + t.receptor + " " + (t.threshold_mA ? std::string(b) : "none");
    if (rep.ratios[k]) {
      std::snprintf(b, sizeof b, " (ratio %.3g)", *rep.ratios[k]);
      talk += b;
    }
    talk += k + 1 < rep.receptors.size() ? "," : "";
  }
  return talk;
}

// Thresholds set by where a fibre was cut: said, not hidden.  Empty when there are none.
std::string cut_end_warning(const fibre::ThresholdReport& rep) {
  std::string cut;
  for (const auto& t : rep.receptors)
    if (t.threshold_mA && t.at_cut_end)
      cut += (cut.empty() ? "" : "; ") + t.receptor +
             (t.cut_end_reason.empty() ? "" : " (" + t.cut_end_reason + ")");
  if (cut.empty()) return cut;
  return "warning: " + cut +
         ": fired first at a cut end of the simulated fibre (at_cut_end), which could not be "
         "lengthened: the threshold depends on where the fibre was cut, not on the field "
         "alone (docs/fibres.md, \"Cut ends\")";
}

// A mode whose target does not fire first (docs/fibres.md, "Is each mode a primary?"):
// the document's mode names a receptor, and another fires at or below its threshold, or
// it does not fire while another does.  Empty otherwise.
std::string target_first_warning(const Json& extra, const fibre::ThresholdReport& rep) {
  const auto mode = extra.find("mode");
  if (mode == extra.end() || !mode->is_string()) return "";
  const std::string target = mode->get<std::string>();
  const fibre::ReceptorThreshold* mine = nullptr;
  const fibre::ReceptorThreshold* first = nullptr;  // the lowest other threshold
  for (const auto& t : rep.receptors) {
    if (t.receptor == target) {
      mine = &t;
    } else if (t.threshold_mA && (!first || *t.threshold_mA < *first->threshold_mA)) {
      first = &t;
    }
  }
  if (!mine || !first) return "";
  if (mine->threshold_mA && *mine->threshold_mA < *first->threshold_mA) return "";
  char b[160];
  if (mine->threshold_mA)
    std::snprintf(b, sizeof b, " (%.4g mA, %s %.4g mA)", *first->threshold_mA, target.c_str(),
                  *mine->threshold_mA);
  else
    std::snprintf(b, sizeof b, " (%.4g mA; %s does not fire)", *first->threshold_mA,
                  target.c_str());
  return "warning: " + target + " mode: " + first->receptor + " fires first" + b +
         ": the pattern is not a primary for " + target +
         " (docs/fibres.md, \"Is each mode a primary?\")";
}

ThresholdOutput run_receptor_thresholds(const ThresholdPlan& p) {
  const FibreSetup& f = p.fibre;
  const auto rep =
      fibre::compute_thresholds(p.doc.setup, *p.doc.weights, *f.model, f.pulse, f.settings);
  Document doc = p.doc;
  doc.extra.erase("thresholds");
  doc.extra.erase("threshold_ratio");
  doc.extra.erase("threshold_multiples");
  doc.extra["thresholds"] = fibre::thresholds_to_json(doc.setup, rep);
  doc.extra["threshold_ratio"] = fibre::ratios_to_json(doc.setup, rep);
  ThresholdOutput out;
  out.notes.push_back(thresholds_line(rep, f));
  const std::string warning = cut_end_warning(rep);
  if (!warning.empty()) out.notes.push_back(warning);
  const std::string not_first = target_first_warning(p.doc.extra, rep);
  if (!not_first.empty()) out.notes.push_back(not_first);
  if (f.stimulus) {  // the stimulus's amplitude in units of each threshold
    double amp = 0.0;
    for (double c : f.stimulus->currents_mA) amp = std::max(amp, std::fabs(c));
    amp /= p.peak_weight;  // the current of an electrode of |w| = 1
    Json mult = Json::object();
    for (const auto& t : rep.receptors) {
      if (t.threshold_mA)
        mult[t.receptor] = amp / *t.threshold_mA;
      else
        mult[t.receptor] = nullptr;
    }
    doc.extra["threshold_multiples"] = mult;
    const auto carried = tp::carried_thresholds(doc.extra);
    out.notes.push_back("stimulus " + tp::threshold_multiples(*carried, amp));
  }
  out.document = document_to_json(doc);
  return out;
}

// " SAI rheobase 0.2 mA chronaxie 310 us;" per receptor, or " SAI no fit;".
std::string strength_duration_note(const fibre::StrengthDuration& sd, const FibreSetup& f) {
  std::string talk = std::string(f.model->name()) + ", " +
                     (f.pulse.monophasic ? "monophasic" : "biphasic");
  for (std::size_t k = 0; k < sd.receptors.size(); ++k) {
    char line[200];
    if (sd.fits[k])
      std::snprintf(line, sizeof line, " %s rheobase %.4g mA chronaxie %.4g us;",
                    sd.receptors[k].c_str(), sd.fits[k]->rheobase_mA, sd.fits[k]->chronaxie_us);
    else
      std::snprintf(line, sizeof line, " %s no fit;", sd.receptors[k].c_str());
    talk += line;
  }
  return talk;
}

ThresholdOutput run_strength_duration(const ThresholdPlan& p, const ThresholdProgress& progress) {
  const FibreSetup& f = p.fibre;
  std::function<void(double, std::size_t, std::size_t)> shown;
  if (progress)
    shown = [&](double w, std::size_t nth, std::size_t total) {
      progress("strength-duration " + number_text(w) + " us, width " + std::to_string(nth) +
                   " of " + std::to_string(total),
               true);
    };
  const fibre::StrengthDuration sd = fibre::strength_duration(
      p.doc.setup, *p.doc.weights, *f.model, f.pulse, f.settings, p.widths_us, shown);
  ThresholdOutput out;
  out.table = fibre::strength_duration_csv(sd);
  out.notes.push_back(strength_duration_note(sd, f));
  return out;
}

// "mrg, 200 us biphasic (...), 0.32 cm2, seed 1: RA 100 of 100 fire (lowest ..., median
// ...; 45 in the area); ..."
std::string population_note(const fibre::Population& pop, const FibreSetup& f,
                            const fibre::PopulationOptions& o) {
  std::string talk;
  for (std::size_t k = 0; k < pop.classes.size(); ++k) {
    std::vector<double> t;
    std::size_t cut = 0;
    for (const auto& a : pop.afferents)
      if (a.receptor == pop.classes[k] && a.threshold_mA) {
        t.push_back(*a.threshold_mA);
        cut += a.at_cut_end ? 1 : 0;
      }
    std::sort(t.begin(), t.end());
    char b[200];
    std::snprintf(b, sizeof b, " %s %zu of %zu fire (lowest %s mA, median %s mA; %.0f in the area)",
                  pop.classes[k].c_str(), t.size(), o.per_class,
                  t.empty() ? "-" : number_text(t.front()).c_str(),
                  t.empty() ? "-" : number_text(t[t.size() / 2]).c_str(), pop.expected[k]);
    talk += b;
    if (cut) talk += ", " + std::to_string(cut) + " of them at a cut end (at_cut_end)";
    talk += k + 1 < pop.classes.size() ? ";" : "";
  }
  char head[400];
  std::snprintf(head, sizeof head, "%s, %s, %.3g cm2, seed %llu:", f.model->name(),
                f.pulse.describe().c_str(), pop.area_cm2, static_cast<unsigned long long>(o.seed));
  return head + talk;
}

// "SAI mode at I50 = 0.79 mA (half of SAI recruited): RA 0.12, PC 0.03 recruited; selectivity
// 0.76 (1 - 2 x the worst other class's, RA)", or why there is none.
std::optional<std::string> half_selectivity_note(const fibre::Population& pop,
                                                 const std::string& mode) {
  if (std::find(pop.classes.begin(), pop.classes.end(), mode) == pop.classes.end())
    return std::nullopt;
  const auto h = fibre::selectivity_at_half(pop, mode);
  if (!h) return mode + " mode: fewer than half of " + mode + " fire: no selectivity at I50";
  std::string others;
  for (std::size_t k = 0; k < pop.classes.size(); ++k)
    if (pop.classes[k] != mode)
      others += (others.empty() ? "" : ", ") + pop.classes[k] + " " + number_text(h->fraction[k]);
  char b[96];
  std::snprintf(b, sizeof b, "%.3g", h->index);
  return mode + " mode at I50 = " + number_text(h->i50_mA) + " mA (half of " + mode +
         " recruited): " + others + " recruited; selectivity " + b + " (1 - 2 x the worst " +
         "other class's fraction, " + h->worst + ")";
}

ThresholdOutput run_population(const ThresholdPlan& p, const ThresholdProgress& progress) {
  const FibreSetup& f = p.fibre;
  fibre::PopulationOptions po = p.population;
  if (progress)
    po.progress = [&](std::size_t done, std::size_t total) {
      progress("population " + std::to_string(done) + " of " + std::to_string(total) +
                   " afferents",
               false);
    };
  const fibre::Population pop =
      fibre::sample_population(p.doc.setup, *p.doc.weights, *f.model, f.pulse, f.settings,
                               fibre::default_afferent_classes(), po);
  ThresholdOutput out;
  out.table = fibre::population_csv(pop);
  out.recruitment = fibre::recruitment_csv(pop);
  out.notes.push_back(population_note(pop, f, po));
  if (p.doc.extra.contains("mode") && p.doc.extra["mode"].is_string())
    if (const auto note = half_selectivity_note(pop, p.doc.extra["mode"].get<std::string>()))
      out.notes.back() += "; " + *note;  // one summary line
  return out;
}

}  // namespace

std::vector<double> strength_duration_widths(std::vector<double> ws,
                                             const tp::PulseSpec& pulse) {
  if (!pulse.phases.empty())
    bad_input("--strength-duration: a shaped pulse (phases) has no single width to vary; give "
              "--width (and --balance-width, --interphase)");
  for (double w : ws)
    if (!(w >= 1.0 && w <= 10000.0))
      bad_input("--widths: " + number_beside(w, 1.0, 10000.0) + " us outside [1, 10000] us");
  if (ws.size() > 64) bad_input("--widths: at most 64 widths");
  std::sort(ws.begin(), ws.end());
  ws.erase(std::unique(ws.begin(), ws.end()), ws.end());
  for (double w : ws) {  // every pulse checked before any work
    const tp::PulseSpec p = fibre::pulse_at_width(pulse, w);
    if (!p.monophasic && !(p.balance_width_us >= 1.0 && p.balance_width_us <= 10000.0))
      bad_input("--widths: " + number_text(w) + " us gives a balancing phase of " +
                number_beside(p.balance_width_us, 1.0, 10000.0) + " us, outside [1, 10000] us");
  }
  return ws;
}

std::string threshold_document_source(const ThresholdText& t) {
  const std::string source = t.config.empty() && t.weights.empty() ? "-" : t.config;
  std::vector<std::string> readers;  // stdin can be read once
  if (source == "-")
    readers.push_back(t.config.empty() ? "the weights document (no --config)" : "--config -");
  if (t.fibre.stimulus == "-") readers.push_back("--stimulus -");
  if (t.skin == "-") readers.push_back("--skin -");
  if (readers.size() > 1)
    bad_input(readers[0] + " and " + readers[1] +
              " both read stdin, which can be read once: give the other as a file");
  return source;
}

void parse_threshold_text(const ThresholdText& t, Document& doc, ThresholdRequest& r) {
  if (!t.weights.empty()) doc.weights = parse_list(t.weights, "--weights");
  r.fibre = fibre_values(t.fibre);
  if (!t.at.empty()) {
    r.at_mm = parse_list(t.at, "--at");
    r.at_text = t.at;
  }
  // --widths is parsed where it applies, so that without --strength-duration it is told so.
  if (!t.widths.empty())
    r.widths_us = r.strength_duration ? parse_list(t.widths, "--widths") : std::vector<double>{};
}

ThresholdPlan plan_thresholds(Document doc, const ThresholdRequest& r) {
  ThresholdPlan p;
  apply_model_options(doc, r.conductor);
  const std::optional<std::array<double, 2>> through = fibre_point(doc, r.at_mm, r.at_text);
  p.peak_weight = checked_peak_weight(doc);
  check_modes(r);
  FibreOptions fibre = r.fibre;
  if (doc.extra.contains("pulse"))  // the weights document's pulse, when no flag gives one
    fibre.carried_pulse = pulse_spec_from_json(doc.extra["pulse"], "weights document: pulse");
  p.fibre = apply_fibre_options(fibre, *doc.weights);
  p.fibre.settings.through_mm = through;
  p.doc = std::move(doc);
  if (r.population) {
    p.mode = ThresholdMode::population;
    p.population.per_class = static_cast<std::size_t>(*r.population);
    p.population.seed = r.seed.value_or(1);
  } else if (r.strength_duration) {
    p.mode = ThresholdMode::strength_duration;
    p.widths_us = strength_duration_widths(
        r.widths_us.value_or(fibre::kStrengthDurationWidths_us), p.fibre.pulse);
    check_strength_duration_work(p);
  }
  return p;
}

ThresholdOutput run_thresholds(const ThresholdPlan& plan, const ThresholdProgress& progress) {
  switch (plan.mode) {
    case ThresholdMode::population:
      return run_population(plan, progress);
    case ThresholdMode::strength_duration:
      return run_strength_duration(plan, progress);
    case ThresholdMode::thresholds:
      break;
  }
  return run_receptor_thresholds(plan);
}

ThresholdOutput run_thresholds(Document doc, const ThresholdRequest& r,
                               const ThresholdProgress& progress) {
  return run_thresholds(plan_thresholds(std::move(doc), r), progress);
}

}  // namespace tp
