// fiber-threshold's request (lib/requests/threshold.hpp) and the strength-duration table
// (lib/fibre/strength_duration.hpp): Weiss's law fitted against its closed form, the
// widths and the options checked with the program's messages, each mode planned, and a
// small table whose thresholds fall and whose charges rise with the width.
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "fibre/strength_duration.hpp"
#include "io/document.hpp"
#include "requests/threshold.hpp"

using namespace tp;

namespace {

// The paper's array and receptors under line2d, with the SAI mode's shape of weights.
Document weights_document() {
  Document d;
  d.weights = std::vector<double>{0, 0, -0.5, 1, -0.5, 0, 0, 0};
  return d;
}

std::string refusal(const Document& doc, const ThresholdRequest& r) {
  try {
    plan_thresholds(doc, r);
  } catch (const Error& e) {
    CHECK(e.code() == ExitCode::bad_input);
    return e.what();
  }
  return "(accepted)";
}

}  // namespace

TEST_CASE("Weiss's law: the fit recovers a rheobase and chronaxie exactly",
          "[requests][threshold][weiss]") {
  // I(t) = rh (1 + tc / t): every charge I t = rh (t + tc) lies on the line.
  const double rh = 0.37, tc = 280.0;
  std::vector<double> t{20, 50, 100, 200, 500, 1000, 2000}, i;
  for (double w : t) i.push_back(rh * (1.0 + tc / w));
  const auto fit = fibre::weiss_fit(t, i);
  REQUIRE(fit);
  CHECK(fit->rheobase_mA == Approx(rh).epsilon(1e-12));
  CHECK(fit->chronaxie_us == Approx(tc).epsilon(1e-12));
}

TEST_CASE("Weiss's law: two points give the line through them, the least squares otherwise",
          "[requests][threshold][weiss]") {
  // Two widths: the slope and intercept of the charges' chord.
  const std::vector<double> t{100, 400}, i{1.0, 0.4};
  const double q1 = 100 * 1.0, q2 = 400 * 0.4;
  const auto fit = fibre::weiss_fit(t, i);
  REQUIRE(fit);
  const double slope = (q2 - q1) / (400.0 - 100.0);
  CHECK(fit->rheobase_mA == Approx(slope).epsilon(1e-12));
  CHECK(fit->chronaxie_us == Approx((q1 - slope * 100.0) / slope).epsilon(1e-12));
  // Three points off a line: the normal equations' solution, by hand.
  const std::vector<double> t3{100, 200, 400}, q3{60, 90, 150};
  std::vector<double> i3;
  for (std::size_t k = 0; k < 3; ++k) i3.push_back(q3[k] / t3[k]);
  // mean t = 700/3, mean q = 100; slope = sum (t - mt)(q - mq) / sum (t - mt)^2.
  const double mt = 700.0 / 3.0, mq = 100.0;
  double sxy = 0, sxx = 0;
  for (std::size_t k = 0; k < 3; ++k) {
    sxy += (t3[k] - mt) * (q3[k] - mq);
    sxx += (t3[k] - mt) * (t3[k] - mt);
  }
  const auto fit3 = fibre::weiss_fit(t3, i3);
  REQUIRE(fit3);
  CHECK(fit3->rheobase_mA == Approx(sxy / sxx).epsilon(1e-12));
  CHECK(fit3->chronaxie_us == Approx((mq - sxy / sxx * mt) / (sxy / sxx)).epsilon(1e-12));
}

TEST_CASE("Weiss's law: no fit from one width, one width twice, or a falling charge",
          "[requests][threshold][weiss]") {
  CHECK_FALSE(fibre::weiss_fit({}, {}));
  CHECK_FALSE(fibre::weiss_fit({100}, {1.0}));
  CHECK_FALSE(fibre::weiss_fit({100, 100}, {1.0, 1.2}));
  CHECK_FALSE(fibre::weiss_fit({100, 200}, {1.0, 0.4}));  // charge 100 then 80: no rheobase
}

TEST_CASE("the strength-duration table: its pulses, widths and CSV",
          "[requests][threshold][strength-duration]") {
  tp::PulseSpec p;
  p.width_us = 100;
  p.balance_width_us = 300;
  p.interphase_us = 20;
  const tp::PulseSpec q = fibre::pulse_at_width(p, 50);
  CHECK(q.width_us == 50);
  CHECK(q.balance_width_us == 150);  // the balancing phase keeps its ratio, 3
  CHECK(q.interphase_us == 20);
  // Sorted, each once; each width and its balancing phase within [1, 10000] us.
  CHECK(strength_duration_widths({500, 20, 500, 100}, p) == std::vector<double>{20, 100, 500});
  CHECK_THROWS_WITH(strength_duration_widths({100, 0}, p), "--widths: 0 us outside [1, 10000] us");
  CHECK_THROWS_WITH(strength_duration_widths({5000}, p),
                    "--widths: 5000 us gives a balancing phase of 15000 us, outside [1, 10000] us");
  p.monophasic = true;  // no balancing phase to check
  CHECK(strength_duration_widths({5000}, p) == std::vector<double>{5000});
  CHECK_THROWS_WITH(strength_duration_widths(std::vector<double>(65, 100.0), p),
                    "--widths: at most 64 widths");

  fibre::StrengthDuration sd;
  sd.widths_us = {100, 200};
  sd.receptors = {"RA", "SAI"};
  sd.threshold_mA = {{1.5, std::nullopt}, {0.5, 0.3}};
  sd.fits = {std::nullopt, fibre::WeissFit{0.1, 400}};
  CHECK(fibre::strength_duration_csv(sd) ==
        "receptor,width_us,threshold_mA,charge_nC,rheobase_mA,chronaxie_us\n"
        "RA,100,1.5,150,,\n"
        "RA,200,,,,\n"
        "SAI,100,0.5,50,0.1,400\n"
        "SAI,200,0.3,60,0.1,400\n");
}

TEST_CASE("a threshold request is refused with fiber-threshold's messages",
          "[requests][threshold][refusals]") {
  const Document doc = weights_document();
  ThresholdRequest r;
  SECTION("weights") {
    Document none;
    CHECK(refusal(none, r) ==
          "weights: the document has none (optimize-weights writes them; or --weights)");
    Document zero = doc;
    zero.weights = std::vector<double>(8, 0.0);
    CHECK(refusal(zero, r) == "weights: every weight is zero");
    Document two = doc;
    two.weights = std::vector<double>{1, -1};
    CHECK(refusal(two, r) == "weights: expected 8 values (one per electrode), got 2");
  }
  SECTION("options of one mode") {
    r.widths_us = std::vector<double>{100};
    CHECK(refusal(doc, r) == "--widths: applies to --strength-duration only");
    r = {};
    r.population = 10;
    r.strength_duration = true;
    CHECK(refusal(doc, r) == "--population and --strength-duration: give one");
    r = {};
    r.seed = 3;
    CHECK(refusal(doc, r) == "--seed, --recruitment: apply to --population only");
    r = {};
    r.recruitment = "r.csv";
    CHECK(refusal(doc, r) == "--seed, --recruitment: apply to --population only");
    r = {};
    r.population = 0;
    CHECK(refusal(doc, r) == "--population: 0 outside [1, 10000]");
  }
  SECTION("--at") {
    r.at_mm = std::vector<double>{0, 0};
    r.at_text = "0,0";
    CHECK(refusal(doc, r) == "--at: applies to 2-D arrays only (a 1-D array's fibres span it)");
  }
  SECTION("the fibre and the pulse, as the command line's parser says them") {
    r.fibre.model = "hh";
    CHECK(refusal(doc, r) == "--model: unknown fibre model 'hh' (mrg or senn)");
    r = {};
    r.fibre.stimulus = "s.json";
    r.fibre.width_us = 100;
    CHECK(refusal(doc, r) == "--stimulus excludes --width");
    r = {};
    r.fibre.monophasic = true;
    r.fibre.interphase_us = 10;
    CHECK(refusal(doc, r) == "--interphase excludes --monophasic");
    r = {};
    r.fibre.width_us = INFINITY;
    CHECK(refusal(doc, r) == "--width: non-finite number 'inf'");
    r = {};
    r.fibre.width_us = 0;
    CHECK(refusal(doc, r) == "--width: 0 us outside [1, 10000] us");
    r = {};
    r.fibre.offsets = 65;
    CHECK(refusal(doc, r) == "--offsets: 65 outside [1, 64]");
    r = {};
    r.fibre.threads = 300;
    CHECK(refusal(doc, r) == "--threads: 300 outside [1, 256]");
    r = {};
    r.fibre.tolerance = 0.5;
    CHECK(refusal(doc, r) == "--tolerance: 0.5 outside [0.0001, 0.1]");
    r.fibre.tolerance_text = "0.50";  // the program's flag as given
    CHECK(refusal(doc, r) == "--tolerance: 0.50 outside [0.0001, 0.1]");
  }
  SECTION("the conductor") {
    r.conductor.model = "nope";
    CHECK(refusal(doc, r).rfind("--conductor: unknown conductor model 'nope'", 0) == 0);
  }
}

TEST_CASE("a threshold request plans its mode", "[requests][threshold][plan]") {
  const Document doc = weights_document();
  ThresholdRequest r;
  ThresholdPlan p = plan_thresholds(doc, r);
  CHECK(p.mode == ThresholdMode::thresholds);
  CHECK(p.peak_weight == 1.0);
  CHECK(p.fibre.pulse.width_us == 200);
  CHECK(p.fibre.pulse.balance_width_us == 200);
  r.strength_duration = true;
  p = plan_thresholds(doc, r);
  CHECK(p.mode == ThresholdMode::strength_duration);
  CHECK(p.widths_us == fibre::kStrengthDurationWidths_us);
  r.widths_us = std::vector<double>{1000, 50, 1000};
  r.fibre.width_us = 100;
  r.fibre.balance_width_us = 400;
  p = plan_thresholds(doc, r);
  CHECK(p.widths_us == std::vector<double>{50, 1000});
  r = {};
  r.population = 7;
  p = plan_thresholds(doc, r);
  CHECK(p.mode == ThresholdMode::population);
  CHECK(p.population.per_class == 7);
  CHECK(p.population.seed == 1);  // the default
  r.seed = 18446744073709551615ull;
  CHECK(plan_thresholds(doc, r).population.seed == 18446744073709551615ull);
}

TEST_CASE("a small strength-duration table: thresholds fall, charges rise, Weiss's fit",
          "[requests][threshold][strength-duration][run]") {
  Document doc = weights_document();
  std::vector<Receptor> sai;
  for (const Receptor& x : doc.setup.receptors)
    if (x.name == "SAI") sai.push_back(x);
  doc.setup.receptors = sai;
  ThresholdRequest r;
  r.fibre.monophasic = true;
  r.fibre.offsets = 1;
  r.fibre.tolerance = 0.01;
  r.fibre.threads = 1;
  r.strength_duration = true;
  r.widths_us = std::vector<double>{400, 50};
  std::vector<std::string> shown;
  const ThresholdOutput out =
      run_thresholds(doc, r, [&](const std::string& text, bool new_stage) {
        CHECK(new_stage);
        shown.push_back(text);
      });
  CHECK(shown == std::vector<std::string>{"strength-duration 50 us, width 1 of 2",
                                          "strength-duration 400 us, width 2 of 2"});
  CHECK_FALSE(out.document);
  // The thresholds as the plain request gives them, one width at a time.
  std::vector<double> th;
  for (double w : {50.0, 400.0}) {
    ThresholdRequest one = r;
    one.strength_duration = false;
    one.widths_us.reset();
    one.fibre.width_us = w;
    const ThresholdOutput o = run_thresholds(doc, one);
    REQUIRE(o.document);
    th.push_back((*o.document)["thresholds"]["receptors"]["SAI"]["threshold_mA"].get<double>());
  }
  CHECK(th[0] > th[1]);                  // a shorter pulse needs more current
  CHECK(th[0] * 50.0 < th[1] * 400.0);  // and less charge
  const auto fit = fibre::weiss_fit({50, 400}, th);
  REQUIRE(fit);
  fibre::StrengthDuration sd;
  sd.widths_us = {50, 400};
  sd.receptors = {"SAI"};
  sd.threshold_mA = {{th[0], th[1]}};
  sd.fits = {fit};
  CHECK(out.table == fibre::strength_duration_csv(sd));
  REQUIRE(out.notes.size() == 1);
  CHECK(out.notes[0].rfind("mrg, monophasic SAI rheobase ", 0) == 0);
}

TEST_CASE("the thresholds' document replaces what an earlier run left",
          "[requests][threshold][run]") {
  Document doc = weights_document();
  std::vector<Receptor> sai;
  for (const Receptor& x : doc.setup.receptors)
    if (x.name == "SAI") sai.push_back(x);
  doc.setup.receptors = sai;
  doc.extra["threshold_multiples"] = Json::object({{"SAI", 3.0}});  // from another stimulus
  doc.extra["mode"] = "SAI";
  ThresholdRequest r;
  r.fibre.offsets = 1;
  r.fibre.tolerance = 0.05;
  r.fibre.threads = 1;
  const ThresholdOutput out = run_thresholds(doc, r);
  REQUIRE(out.document);
  const Json& j = *out.document;
  CHECK_FALSE(j.contains("threshold_multiples"));
  CHECK(j["mode"] == "SAI");
  CHECK(j["thresholds"]["receptors"]["SAI"]["threshold_mA"].is_number());
  CHECK(j["threshold_ratio"].is_object());
  REQUIRE_FALSE(out.notes.empty());
  CHECK(out.notes[0].rfind("mrg, 200 us biphasic", 0) == 0);
}

TEST_CASE("fiber-threshold's typed flags: the document's source, stdin once, the numbers",
          "[requests][threshold]") {
  auto message = [](const std::function<void()>& f) {
    try {
      f();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  ThresholdText t;
  CHECK(threshold_document_source(t) == "-");  // no --config: the document on stdin
  t.weights = "1,-1";
  CHECK(threshold_document_source(t).empty());  // --weights: the default array
  t.config = "doc.json";
  CHECK(threshold_document_source(t) == "doc.json");
  ThresholdText both;
  both.fibre.stimulus = "-";
  CHECK(message([&] { threshold_document_source(both); }) ==
        "the weights document (no --config) and --stimulus - both read stdin, which can be "
        "read once: give the other as a file");
  both.config = "-";
  both.skin = "-";
  CHECK(message([&] { threshold_document_source(both); }) ==
        "--config - and --stimulus - both read stdin, which can be read once: give the other "
        "as a file");
  both.fibre.stimulus = "s.json";
  CHECK(message([&] { threshold_document_source(both); }) ==
        "--config - and --skin - both read stdin, which can be read once: give the other as a "
        "file");
  // The numbers: the weights into the document, the at as typed, the widths where they apply.
  Document doc;
  ThresholdRequest r;
  t.weights = "0,1,-1";
  t.at = "1.5,2";
  t.widths = "100,50";
  t.fibre.width = "150";
  parse_threshold_text(t, doc, r);
  CHECK(doc.weights == std::vector<double>{0, 1, -1});
  CHECK(r.at_mm == std::vector<double>{1.5, 2});
  CHECK(r.at_text == "1.5,2");
  CHECK(r.fibre.width_us == 150.0);
  REQUIRE(r.widths_us);
  CHECK(r.widths_us->empty());  // given without --strength-duration: the plan says so
  ThresholdRequest no_at = r;
  no_at.at_mm.reset();
  CHECK_THAT(refusal(weights_document(), no_at), Catch::Contains("--widths"));
  ThresholdRequest sd;
  sd.strength_duration = true;
  parse_threshold_text(t, doc, sd);
  CHECK(sd.widths_us == std::vector<double>{100, 50});
  // The first text that is not a number, in this order.
  t.widths = "w";
  t.at = "a";
  t.fibre.tolerance = "tol";
  CHECK(message([&] { parse_threshold_text(t, doc, sd); }) == "--tolerance: not a number 'tol'");
  t.weights = "x";
  CHECK(message([&] { parse_threshold_text(t, doc, sd); }) == "--weights item 1: not a number 'x'");
}
