// fiber-threshold: the current at which each receptor's fibre fires, from a nonlinear
// myelinated-fibre model (MRG or SENN) in the conductor's field, and the threshold
// selectivity of the weight pattern.
//
//   optimize-weights --mode SAI | fiber-threshold > sai-thresholds.json
//   optimize-weights --mode SAI | fiber-threshold --strength-duration > sd.csv

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "cli/array_options.hpp"
#include "cli/entry.hpp"
#include "cli/fibre_options.hpp"
#include "cli/progress.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "fibre/population.hpp"
#include "io/document.hpp"
#include "io/files.hpp"
#include "io/number.hpp"
#include "model/ranges.hpp"

namespace {

std::string num(double v) {
  return tp::number_text(v);
}

// Weiss's law, charge = rheobase x (width + chronaxie), fitted by least squares.
bool weiss_fit(const std::vector<double>& t_us, const std::vector<double>& i_mA, double& rheo,
               double& chron) {
  const std::size_t n = t_us.size();
  if (n < 2) return false;
  double st = 0, sq = 0, stt = 0, stq = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double q = i_mA[k] * t_us[k];
    st += t_us[k];
    sq += q;
    stt += t_us[k] * t_us[k];
    stq += t_us[k] * q;
  }
  const double dn = static_cast<double>(n);
  const double den = dn * stt - st * st;
  if (!(den > 0)) return false;
  rheo = (dn * stq - st * sq) / den;
  const double icpt = (sq - rheo * st) / dn;
  if (!(rheo > 0)) return false;
  chron = icpt / rheo;
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Thresholds in mA: the current on an electrode of |weight| = 1 at which each receptor's "
      "fibre fires, from a compartmental myelinated-fibre model (MRG or SENN) driven by the "
      "conductor's potential, for the whole pulse waveform.\nPrints the weights document with "
      "\"thresholds\" (per receptor: threshold_mA, where the action potential started) and "
      "\"threshold_ratio\" (threshold over the lowest other receptor's: below 1, that receptor "
      "fires first); or, with --strength-duration, a CSV table.",
      "fiber-threshold"};
  tp::cli::ArrayOptions array;
  tp::cli::ModelOptions conductor;
  conductor.flag = "--conductor";
  tp::cli::FibreOptions fibre;
  std::string weights, widths, at, recruitment;
  long population = 0;
  std::uint64_t seed = 1;
  bool sd = false;
  auto* o_config = tp::cli::add_array_options(
      app, array, "Weights document (optimize-weights' JSON; - for stdin) [stdin]");
  auto* o_w = app.add_option("--weights", weights,
                             "Comma-separated weights, one per electrode (positive = cathodic), "
                             "instead of a document")
                  ->type_name("W1,W2,...");
  o_config->excludes(o_w);
  tp::cli::add_model_options(app, conductor);
  tp::cli::add_fibre_options(app, fibre, "--model");
  app.add_option("--at", at,
                 "2-D arrays: the point X,Z (mm) the fibres pass through [the document's "
                 "focus, optimize-weights --at]")
      ->type_name("X,Z");
  tp::cli::add_integer(
      app, "--population", population,
      "N afferents of each class sampled over the array and its margin (diameters, depths and "
      "densities: docs/fibres.md), each its own threshold: CSV class,x_mm,offset_mm,depth_mm,"
      "diameter_um,threshold_mA; 1 to 10000, and no more fibre simulation than the work bound "
      "allows (refused before any work: about 7500 on the paper's 8-electrode array with a "
      "200 us pulse, fewer with longer pulses, more electrodes or a finer --tolerance)",
      1L, tp::fibre::kMaxPopulation);
  tp::cli::add_seed(app, "--seed", seed,
                    "--population: the sampling's seed, 0 to 18446744073709551615 (2^64 - 1) [1]");
  app.add_option("--recruitment", recruitment,
                 "--population: write the recruitment curves (each class's fraction recruited "
                 "against current, and each mode's selectivity index) as CSV to FILE")
      ->type_name("FILE");
  app.add_flag("--strength-duration", sd,
               "Print a strength-duration table (CSV: receptor,width_us,threshold_mA,charge_nC,"
               "rheobase_mA,chronaxie_us; rheobase and chronaxie from Weiss's law)");
  app.add_option("--widths", widths,
                 "--strength-duration: main phase widths, us, 1 to 10000 "
                 "[20,50,100,200,500,1000,2000]")
      ->type_name("US1,US2,...");
  tp::cli::add_output_option(app);

  return tp::cli::run(app, argc, argv, [&] {
    tp::cli::ArrayOptions source = array;
    if (source.config.empty() && weights.empty()) source.config = "-";
    {  // stdin can be read once: at most one of the weights document, --stimulus, --skin
      std::vector<std::string> readers;
      if (source.config == "-")
        readers.push_back(array.config.empty() ? "the weights document (no --config)"
                                               : "--config -");
      if (fibre.stimulus == "-") readers.push_back("--stimulus -");
      if (conductor.skin == "-") readers.push_back("--skin -");
      if (readers.size() > 1)
        tp::bad_input(readers[0] + " and " + readers[1] +
                      " both read stdin, which can be read once: give the other as a file");
    }
    tp::Document doc = tp::cli::load_document(source, 1);
    if (!weights.empty()) doc.weights = tp::parse_list(weights, "--weights");
    tp::cli::apply_model_options(doc, conductor);
    const std::optional<std::array<double, 2>> through = tp::fibre_point(
        doc, at.empty() ? std::nullopt : std::optional(tp::parse_list(at, "--at")), at);
    if (!doc.weights)
      tp::bad_input("weights: the document has none (optimize-weights writes them; or --weights)");
    if (doc.weights->size() != doc.setup.array.size())
      tp::bad_input("weights: expected " + std::to_string(doc.setup.array.size()) +
                    " values (one per electrode), got " + std::to_string(doc.weights->size()));
    double wmax = 0.0;
    for (std::size_t i = 0; i < doc.weights->size(); ++i) {
      tp::ranges::check((*doc.weights)[i], tp::ranges::weight,
                        "weights item " + std::to_string(i + 1));
      wmax = std::max(wmax, std::fabs((*doc.weights)[i]));
    }
    if (!(wmax > 0.0)) tp::bad_input("weights: every weight is zero");
    if (!widths.empty() && !sd) tp::bad_input("--widths: applies to --strength-duration only");
    if (app.count("--population") && sd)
      tp::bad_input("--population and --strength-duration: give one");
    if ((app.count("--seed") || !recruitment.empty()) && !app.count("--population"))
      tp::bad_input("--seed, --recruitment: apply to --population only");
    if (app.count("--population") && app.count("--at"))
      tp::bad_input(
          "--at: does not apply to --population (its afferents are sampled over the "
          "whole array and its margin, each through its own place)");
    tp::cli::FibreSetup f = tp::cli::apply_fibre_options(fibre, *doc.weights);
    f.settings.through_mm = through;

    if (app.count("--population")) {
      tp::fibre::PopulationOptions po;
      po.per_class = static_cast<std::size_t>(population);
      po.seed = seed;
      tp::cli::ProgressLine progress("fiber-threshold");  // on a terminal only
      if (progress.active())
        po.progress = [&](std::size_t done, std::size_t total) {
          progress.show("population " + std::to_string(done) + " of " + std::to_string(total) +
                        " afferents");
        };
      // The curves: a temporary beside the file from now (an unwritable place refused before
      // any work), renamed over it once the table too is written; else the file left as it was.
      std::optional<tp::AtomicFile> curves;
      if (!recruitment.empty()) curves.emplace(recruitment, "--recruitment");
      std::string table, csv;
      {
        const tp::fibre::Population pop =
            tp::fibre::sample_population(doc.setup, *doc.weights, *f.model, f.pulse, f.settings,
                                         tp::fibre::default_afferent_classes(), po);
        progress.clear();
        table = tp::fibre::population_csv(pop);
        csv = tp::fibre::recruitment_csv(pop);
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
          std::snprintf(b, sizeof b,
                        " %s %zu of %zu fire (lowest %s mA, median %s mA; %.0f in the area)",
                        pop.classes[k].c_str(), t.size(), po.per_class,
                        t.empty() ? "-" : num(t.front()).c_str(),
                        t.empty() ? "-" : num(t[t.size() / 2]).c_str(), pop.expected[k]);
          talk += b;
          if (cut) talk += ", " + std::to_string(cut) + " of them at a cut end (at_cut_end)";
          talk += k + 1 < pop.classes.size() ? ";" : "";
        }
        std::fprintf(stderr, "fiber-threshold: %s, %s, %.3g cm2, seed %llu:%s\n", f.model->name(),
                     f.pulse.describe().c_str(), pop.area_cm2,
                     static_cast<unsigned long long>(seed), talk.c_str());
      }
      if (curves) curves->write(csv);
      tp::cli::write_stdout(table);
      if (curves) curves->commit();
      return;
    }
    if (sd) {
      std::vector<double> ws = widths.empty()
                                   ? std::vector<double>{20, 50, 100, 200, 500, 1000, 2000}
                                   : tp::parse_list(widths, "--widths");
      for (double w : ws)
        if (!(w >= 1.0 && w <= 10000.0))
          tp::bad_input("--widths: " + tp::number_beside(w, 1.0, 10000.0) +
                        " us outside [1, 10000] us");
      if (ws.size() > 64) tp::bad_input("--widths: at most 64 widths");
      std::sort(ws.begin(), ws.end());
      ws.erase(std::unique(ws.begin(), ws.end()), ws.end());
      auto pulse_at = [&](double w) {  // the balancing phase keeps its ratio to the width
        tp::fibre::PulseSpec p = f.pulse;
        p.balance_width_us = f.pulse.balance_width_us / f.pulse.width_us * w;
        p.width_us = w;
        return p;
      };
      for (double w : ws) {  // every pulse checked before any work
        const tp::fibre::PulseSpec p = pulse_at(w);
        if (!p.monophasic && !(p.balance_width_us >= 1.0 && p.balance_width_us <= 10000.0))
          tp::bad_input("--widths: " + num(w) + " us gives a balancing phase of " +
                        tp::number_beside(p.balance_width_us, 1.0, 10000.0) +
                        " us, outside [1, 10000] us");
      }
      {  // the whole table's work, bounded before any of it
        double work = 0.0;
        for (double w : ws)
          work += tp::fibre::thresholds_work(doc.setup, *f.model, pulse_at(w), f.settings);
        tp::fibre::check_threshold_work(
            work, tp::fibre::kMaxThresholdWork,
            "--strength-duration (" + std::to_string(ws.size()) + " widths)");
      }
      const std::size_t nr = doc.setup.receptors.size();
      std::vector<std::vector<std::optional<double>>> th(nr);
      tp::fibre::PotentialCache cache;  // the same fibres for every width
      tp::cli::ProgressLine progress("fiber-threshold");  // on a terminal only
      std::size_t widths_done = 0;
      for (double w : ws) {
        progress.show("strength-duration " + num(w) + " us, width " +
                          std::to_string(++widths_done) + " of " + std::to_string(ws.size()),
                      true);
        const auto rep = tp::fibre::compute_thresholds(doc.setup, *doc.weights, *f.model,
                                                       pulse_at(w), f.settings, &cache);
        for (std::size_t k = 0; k < nr; ++k) th[k].push_back(rep.receptors[k].threshold_mA);
      }
      progress.clear();
      std::string out = "receptor,width_us,threshold_mA,charge_nC,rheobase_mA,chronaxie_us\n";
      std::string talk;
      for (std::size_t k = 0; k < nr; ++k) {
        std::vector<double> t, i;
        for (std::size_t q = 0; q < ws.size(); ++q)
          if (th[k][q]) {
            t.push_back(ws[q]);
            i.push_back(*th[k][q]);
          }
        double rheo = 0, chron = 0;
        const bool fit = weiss_fit(t, i, rheo, chron);
        for (std::size_t q = 0; q < ws.size(); ++q) {
          out += doc.setup.receptors[k].name + "," + num(ws[q]) + ",";
          if (th[k][q])
            out += num(*th[k][q]) + "," + num(*th[k][q] * ws[q]);
          else
            out += ",";
          out += fit ? "," + num(rheo) + "," + num(chron) : ",,";
          out += "\n";
        }
        char line[200];
        if (fit)
          std::snprintf(line, sizeof line, " %s rheobase %.4g mA chronaxie %.4g us;",
                        doc.setup.receptors[k].name.c_str(), rheo, chron);
        else
          std::snprintf(line, sizeof line, " %s no fit;", doc.setup.receptors[k].name.c_str());
        talk += line;
      }
      std::fprintf(stderr, "fiber-threshold: %s, %s%s\n", f.model->name(),
                   f.pulse.monophasic ? "monophasic" : "biphasic", talk.c_str());
      tp::cli::write_stdout(out);
      return;
    }

    const auto rep =
        tp::fibre::compute_thresholds(doc.setup, *doc.weights, *f.model, f.pulse, f.settings);
    doc.extra.erase("thresholds");
    doc.extra.erase("threshold_ratio");
    doc.extra.erase("threshold_multiples");
    doc.extra["thresholds"] = tp::fibre::thresholds_to_json(doc.setup, rep);
    doc.extra["threshold_ratio"] = tp::fibre::ratios_to_json(doc.setup, rep);
    std::string talk =
        "fiber-threshold: " + std::string(f.model->name()) + ", " + f.pulse.describe() + ":";
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
    {  // thresholds set by where a fibre was cut: said, not hidden
      std::string cut;
      for (const auto& t : rep.receptors)
        if (t.threshold_mA && t.at_cut_end) cut += (cut.empty() ? "" : ", ") + t.receptor;
      if (!cut.empty())
        talk += "\nfiber-threshold: warning: " + cut +
                " fired first at a cut end of the simulated fibre (at_cut_end): the threshold "
                "depends on where the fibre was cut (model.lateral_margin_mm), not on the field "
                "alone (docs/fibres.md, \"Cut ends\")";
    }
    if (f.stimulus) {
      double amp = 0.0;
      for (double c : f.stimulus->currents_mA) amp = std::max(amp, std::fabs(c));
      amp /= wmax;  // the current of an electrode of |w| = 1
      tp::Json mult = tp::Json::object();
      for (const auto& t : rep.receptors) {
        if (t.threshold_mA)
          mult[t.receptor] = amp / *t.threshold_mA;
        else
          mult[t.receptor] = nullptr;
      }
      doc.extra["threshold_multiples"] = mult;
      const auto carried = tp::fibre::carried_thresholds(doc.extra);
      talk += "\nfiber-threshold: stimulus " + tp::fibre::threshold_multiples(*carried, amp);
    }
    std::fprintf(stderr, "%s\n", talk.c_str());
    tp::cli::write_stdout(tp::dump_json(tp::document_to_json(doc)));
  });
}
