// optimize-weights' request (lib/requests/optimize): its checks, in the program's order and
// words, and what each design returns.
// Ceres pulls in glog, whose CHECK macros clash with Catch's: use Catch's prefixed names.
#define CATCH_CONFIG_PREFIX_ALL
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "io/document.hpp"
#include "model/array.hpp"
#include "requests/optimize.hpp"

using namespace tp;

namespace {

Document paper() {
  return Document{};  // the paper's 8 x 1 mm array under line2d
}

Document grid(int columns, int rows) {
  Document d;
  d.setup.array = ElectrodeArray::grid_of(columns, rows, 2.0, 2.0, 1.0, 1.0);
  d.setup.conductor.model = "rect3d";
  return d;
}

OptimizeRequest mode(const std::string& m) {
  OptimizeRequest r;
  r.modes = {m};
  return r;
}

// The message a request is refused with (bad input), or "" when it passes.
std::string refusal(const Document& doc, const OptimizeRequest& r) {
  try {
    check_optimize(doc, r);
  } catch (const Error& e) {
    CATCH_REQUIRE(e.code() == ExitCode::bad_input);
    return e.what();
  }
  return "";
}

// Sum w = 0 and max |w| = 1: every design's weights.
void require_weights(const Json& w, std::size_t n) {
  CATCH_REQUIRE(w.size() == n);
  double sum = 0, peak = 0;
  for (const Json& x : w) {
    sum += x.get<double>();
    peak = std::max(peak, std::fabs(x.get<double>()));
  }
  CATCH_CHECK(std::fabs(sum) < 1e-9);
  CATCH_CHECK(peak == Approx(1.0).epsilon(1e-12));
}

}  // namespace

CATCH_TEST_CASE("the request's checks say what optimize-weights says, in its order",
                "[requests][optimize]") {
  const Document d = paper();
  const Document g = grid(3, 3);
  struct Case {
    const char* says;
    Document doc;
    std::function<void(OptimizeRequest&)> set;
  };
  const std::vector<Case> cases = {
      {"--mode: required (RA, SAI, PC, ...)", d, [](OptimizeRequest& r) { r.modes.clear(); }},
      {"array: optimisation needs at least 2 electrodes",
       [] {
         Document one;
         one.setup.array = ElectrodeArray::uniform(1, 1.0);
         return one;
       }(),
       [](OptimizeRequest& r) { r.modes.clear(); }},  // the array before the mode
      {"--z: does not apply under a 2-D array", g,
       [](OptimizeRequest& r) { r.plane_z_given = true; }},
      {"is 2-D: give a pixel's place, --at X,Z (or --bank)", g,
       [](OptimizeRequest& r) { r.modes = {"SAI"}; }},
      {"--radius, --spill: apply to a pixel (--at) or a bank (--bank)", d,
       [](OptimizeRequest& r) { r.spill = 0.5; }},
      {"--neighbourhood: with --bank only", d, [](OptimizeRequest& r) { r.neighbourhood = 3; }},
      {"--at: one place (several: with --bank)", d,
       [](OptimizeRequest& r) { r.at_mm = {{0.5}, {1.5}}; }},
      {"--max-current: 5 mA outside [0.001, 2] mA", d,
       [](OptimizeRequest& r) { r.max_current_mA = 5; }},
      {"--min-target-af: must be >= 0", d, [](OptimizeRequest& r) { r.min_target_af = -1; }},
      {"--mode: empty name in 'SAI,'", d, [](OptimizeRequest& r) { r.modes = {"SAI", ""}; }},
      {"--mode: 'SAI' given twice", d, [](OptimizeRequest& r) { r.modes = {"SAI", "SAI"}; }},
      {"unknown mode 'XY'", d, [](OptimizeRequest& r) { r.modes = {"SAI", "XY"}; }},
      {"--mode: several modes need --format csv (one row each)", d,
       [](OptimizeRequest& r) { r.modes = {"SAI", "PC"}; }},
      {"--width: applies to --objective threshold or selectivity only", d,
       [](OptimizeRequest& r) { r.fibre.width_us = 100; }},
      {"--fibre-model: applies to --objective threshold or selectivity only", d,
       [](OptimizeRequest& r) { r.fibre_model_given = true; }},
      {"--threads: applies to --objective threshold or selectivity only, --at and --bank", d,
       [](OptimizeRequest& r) { r.threads = 2; }},
      {"--at: expected X (a 1-D array), got '0,0'", d,
       [](OptimizeRequest& r) { r.at_mm = {{0, 0}}; }},
      {"--radius: must be > 0 mm (omit it for one pitch), got -1", d,
       [](OptimizeRequest& r) {
         r.at_mm = {{-0.5}};
         r.radius_mm = -1;
       }},
      {"--bank: designs by the AF objective only", g,
       [](OptimizeRequest& r) {
         r.bank = true;
         r.objective = OptimizeObjective::threshold;
       }},
      {"--bank: JSON output only", g,
       [](OptimizeRequest& r) {
         r.bank = true;
         r.csv = true;
       }},
      {"--pattern-starts, --random-starts: do not apply with --bank", g,
       [](OptimizeRequest& r) {
         r.bank = true;
         r.pattern_starts = 2;  // given, even at its default
       }},
      {"--objective threshold: one mode, JSON output", d,
       [](OptimizeRequest& r) {
         r.objective = OptimizeObjective::threshold;
         r.csv = true;
       }},
      {"--certify: certifies the AF problem, not --objective threshold", d,
       [](OptimizeRequest& r) {
         r.objective = OptimizeObjective::threshold;
         r.certify = true;
       }},
      {"--certify: the certified optimum is reported in JSON only (--format json)", d,
       [](OptimizeRequest& r) {
         r.certify = true;
         r.csv = true;
       }},
      {"--at: (4.6) mm lies outside the array's extent plus one pitch", d,
       [](OptimizeRequest& r) { r.at_mm = {{4.6}}; }},
      {"--at: designs by the AF objective or --objective selectivity, not --objective threshold", d,
       [](OptimizeRequest& r) {
         r.at_mm = {{-0.5}};
         r.objective = OptimizeObjective::threshold;
       }},
      {"--min-target-af: does not apply with --at", d,
       [](OptimizeRequest& r) {
         r.at_mm = {{-0.5}};
         r.min_target_af = 1;
       }},
      {"--header-only: needs --format csv", d, [](OptimizeRequest& r) { r.header_only = true; }},
  };
  for (const Case& c : cases) {
    CATCH_CAPTURE(c.says);
    OptimizeRequest r = mode("SAI");
    c.set(r);
    CATCH_CHECK_THAT(refusal(c.doc, r), Catch::Contains(c.says));
  }
  CATCH_CHECK(refusal(d, mode("SAI")).empty());
}

CATCH_TEST_CASE("a value that came without the command line is checked in the parser's words",
                "[requests][optimize]") {
  const Document d = paper();
  OptimizeRequest r = mode("SAI");
  r.pattern_starts = 5;
  CATCH_CHECK(refusal(d, r) == "--pattern-starts: 5 outside [0, 4]");
  r = mode("SAI");
  r.max_evaluations = 5;
  CATCH_CHECK(refusal(d, r) == "--max-evaluations: 5 outside [10, 10000]");
  r = mode("SAI");
  r.at_mm = {{std::numeric_limits<double>::quiet_NaN()}};
  CATCH_CHECK(refusal(d, r) == "--at: non-finite number 'nan'");
  r = mode("SAI");
  r.max_current_mA = -std::numeric_limits<double>::infinity();
  CATCH_CHECK(refusal(d, r) == "--max-current: non-finite number '-inf'");
  // The texts as given name a value; without them, its number does.
  r = mode("SAI");
  r.min_target_af = 1e300;
  CATCH_CHECK(refusal(d, r) == "--min-target-af: 1e+300 V/ms outside [0, 10000] V/ms");
  r.given.min_target_af = "1e300";
  CATCH_CHECK(refusal(d, r) == "--min-target-af: 1e300 V/ms outside [0, 10000] V/ms");
  r = mode("SAI");
  r.at_mm = {{0.5, 1.25}};
  CATCH_CHECK(refusal(d, r) == "--at: expected X (a 1-D array), got '0.5,1.25'");
  r.given.at = {"0.50,1.250"};
  CATCH_CHECK(refusal(d, r) == "--at: expected X (a 1-D array), got '0.50,1.250'");
}

CATCH_TEST_CASE("a mode's weights: the document, or a CSV row a mode", "[requests][optimize]") {
  const Document d = paper();
  OptimizeRequest r = mode("SAI");
  r.max_current_mA = 1.5;
  const OptimizeOutput out = run_optimize(d, r);
  CATCH_CHECK(out.text == dump_json(out.document));
  CATCH_CHECK(out.document["mode"] == "SAI");
  CATCH_CHECK(out.document["max_current_mA"] == 1.5);
  require_weights(out.document["weights"], 8);
  const Json& w = out.document["weights"];
  for (std::size_t i = 0; i < 8; ++i)  // the currents at the limit given
    CATCH_CHECK(out.document["currents_mA"][i].get<double>() ==
                Approx(1.5 * w[i].get<double>()).margin(1e-12));
  CATCH_REQUIRE(out.notes.size() == 1);
  CATCH_CHECK(out.notes[0].rfind("SAI ratio ", 0) == 0);
  CATCH_CHECK(out.notes[0].find("at 1.5 mA") != std::string::npos);

  r = mode("PC");
  r.modes = {"PC", "RA"};
  r.csv = true;
  const OptimizeOutput csv = run_optimize(d, r);
  CATCH_CHECK(csv.document.is_null());
  const std::string header = csv.text.substr(0, csv.text.find('\n') + 1);
  CATCH_CHECK(header.rfind("electrodes,pitch_mm,mode,ratio", 0) == 0);
  CATCH_CHECK(std::count(csv.text.begin(), csv.text.end(), '\n') == 3);  // header, PC, RA
  CATCH_CHECK(csv.text.find("\n8,1,PC,") != std::string::npos);
  CATCH_CHECK(csv.text.find("\n8,1,RA,") != std::string::npos);
  CATCH_CHECK(csv.notes.size() == 2);
  r.header = false;
  CATCH_CHECK(run_optimize(d, r).text == csv.text.substr(header.size()));
  // --header-only: the checks and the header, no work.
  r.header = true;
  r.header_only = true;
  const OptimizeOutput only = run_optimize(d, r);
  CATCH_CHECK(only.text == header);
  CATCH_CHECK(only.notes.empty());
  r.modes = {"PC", "XY"};  // still checked
  CATCH_CHECK_THAT(refusal(d, r), Catch::Contains("unknown mode 'XY'"));
}

CATCH_TEST_CASE("a pixel's and a bank's documents, and the bank's progress",
                "[requests][optimize]") {
  OptimizeRequest r = mode("PC");
  r.at_mm = {{-0.5}};
  r.threads = 1;
  const OptimizeOutput pixel = run_optimize(paper(), r);
  CATCH_CHECK(pixel.document["mode"] == "PC");
  require_weights(pixel.document["weights"], 8);
  CATCH_CHECK(pixel.document["focus"]["x_mm"] == -0.5);
  CATCH_REQUIRE(!pixel.notes.empty());
  CATCH_CHECK(pixel.notes.back().rfind("PC pixel at -0.5, ratio ", 0) == 0);

  const Document g = grid(3, 2);
  r = OptimizeRequest{};
  r.bank = true;
  r.modes = {"SAI"};
  r.threads = 2;
  std::vector<std::string> lines;
  int stages = 0;
  r.progress = [&](const std::string& text, bool new_stage) {
    lines.push_back(text);
    stages += new_stage;
  };
  const OptimizeOutput bank = run_optimize(g, r);
  CATCH_CHECK(bank.document["pixels"].size() == 6);  // every pad's centre
  CATCH_REQUIRE(bank.notes.size() == 1);
  CATCH_CHECK(bank.notes[0].rfind("bank of 6 pixels x 1 modes: ", 0) == 0);
  CATCH_REQUIRE(!lines.empty());
  CATCH_CHECK(lines.front().rfind("bank ", 0) == 0);
  CATCH_CHECK(lines.back().find("patterns judged") != std::string::npos);
  CATCH_CHECK(stages == 1);  // judging starts once
}

CATCH_TEST_CASE("the threshold objective: never worse than the AF optimum it starts from",
                "[requests][optimize]") {
  Document d;
  d.setup.array = ElectrodeArray::uniform(4, 1.0);
  OptimizeRequest r = mode("SAI");
  r.objective = OptimizeObjective::threshold;
  r.max_evaluations = 10;
  r.fibre.tolerance = 0.05;
  r.fibre.offsets = 1;
  r.threads = 1;
  std::size_t progress_calls = 0;
  r.progress = [&](const std::string& text, bool) {
    CATCH_CHECK(text.rfind("threshold search ", 0) == 0);
    ++progress_calls;
  };
  const OptimizeOutput out = run_optimize(d, r);
  const Json& doc = out.document;
  CATCH_CHECK(doc["objective"] == "threshold");
  CATCH_CHECK(doc["mode"] == "SAI");
  require_weights(doc["weights"], 4);
  require_weights(doc["af_optimum"]["weights"], 4);
  const Json& search = doc["threshold_search"];
  CATCH_CHECK(search["evaluations"].get<std::size_t>() <= 10);
  CATCH_CHECK(progress_calls == search["evaluations"].get<std::size_t>());
  CATCH_CHECK(doc["threshold_ratio"]["SAI"].get<double>() <=
              doc["af_optimum"]["threshold_ratio"].get<double>());
  for (std::size_t i = 0; i < 4; ++i)
    CATCH_CHECK(doc["currents_mA"][i].get<double>() ==
                Approx(2.0 * doc["weights"][i].get<double>()).margin(1e-12));
  CATCH_REQUIRE(out.notes.size() == 1);
  CATCH_CHECK(out.notes[0].find(", mrg, 200 us biphasic") != std::string::npos);

  // The fibre options are checked with the AF optimum's weights, before the search.
  r.progress = nullptr;
  r.fibre.model = "hh";
  r.fibre_model_given = true;
  CATCH_CHECK(refusal(d, r).empty());
  CATCH_CHECK_THROWS_WITH(run_optimize(d, r),
                          "--fibre-model: unknown fibre model 'hh' (mrg or senn)");
}

CATCH_TEST_CASE("optimize-weights' typed flags are parsed in its order and named", "[requests][optimize]") {
  auto message = [](const OptimizeText& t) {
    OptimizeRequest r;
    try {
      parse_optimize_text(t, r);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  OptimizeText t;
  t.modes = "SAI,PC,,RA";
  t.max_current_mA = "1.5";
  t.min_target_af = "2";
  t.at = {"0.5", "1,2"};
  t.radius_mm = "3";
  t.spill = "0.2";
  t.fibre.width = "100";
  OptimizeRequest r;
  r.bank = true;  // kept
  parse_optimize_text(t, r);
  CATCH_CHECK(r.modes == std::vector<std::string>{"SAI", "PC", "", "RA"});
  CATCH_CHECK(r.max_current_mA == 1.5);
  CATCH_CHECK(r.min_target_af == 2.0);
  CATCH_CHECK(r.at_mm == std::vector<std::vector<double>>{{0.5}, {1, 2}});
  CATCH_CHECK(r.given.at == t.at);
  CATCH_CHECK(r.radius_mm == 3.0);
  CATCH_CHECK(r.given.radius == "3");
  CATCH_CHECK(r.spill == 0.2);
  CATCH_CHECK(r.fibre.width_us == 100.0);
  CATCH_CHECK(r.bank);
  OptimizeRequest none;
  parse_optimize_text(OptimizeText{}, none);
  CATCH_CHECK(none.modes.empty());
  CATCH_CHECK(!none.max_current_mA);
  CATCH_CHECK(!none.radius_mm);
  CATCH_CHECK(none.fibre.model == "mrg");
  // The first text that is not a number, in the program's order.
  t.spill = "x";
  CATCH_CHECK(message(t) == "--spill: not a number 'x'");
  t.fibre.tolerance = "tight";
  CATCH_CHECK(message(t) == "--tolerance: not a number 'tight'");
  t.min_target_af = "high";
  CATCH_CHECK(message(t) == "--min-target-af: not a number 'high'");
  t.max_current_mA = "nan";
  CATCH_CHECK_THAT(message(t), Catch::Contains("--max-current"));
}
