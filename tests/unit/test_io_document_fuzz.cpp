// Property-based fuzz of the document parsers: random JSON (random nesting, sizes, keys
// mixed with the real ones, numbers of every magnitude, integers beyond 64 bits, 1e999,
// byte mutations of valid documents).  Whatever arrives, a parser either returns a value
// whose every parameter lies in its documented range (and that prints and parses back to
// the same document), or refuses it as bad input: never another exception, a crash or
// undefined behaviour (the sanitizer build runs this too).  TP_FUZZ_ITERATIONS sets the
// number of cases.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/splitmix.hpp"
#include "io/document.hpp"
#include "core/json.hpp"
#include "core/ranges.hpp"
#include "pulse/stimulus.hpp"

using namespace tp;

namespace {

class Gen {
 public:
  explicit Gen(std::uint64_t seed) : rng_{seed} {}
  double u() { return rng_.unit(); }
  std::size_t pick(std::size_t n) { return static_cast<std::size_t>(u() * static_cast<double>(n)); }

  std::string number() {
    static const char* special[] = {"1e999",
                                    "-1e999",
                                    "1e-999",
                                    "-0",
                                    "0",
                                    "1e308",
                                    "-1e308",
                                    "4.9e-324",
                                    "123456789012345678901234567890",
                                    "18446744073709551616",
                                    "-9223372036854775809",
                                    "1e-7",
                                    "0.5",
                                    "2",
                                    "64",
                                    "65",
                                    "3600"};
    const double k = u();
    if (k < 0.3) return special[pick(sizeof special / sizeof *special)];
    char b[64];
    if (k < 0.5) {
      std::snprintf(b, sizeof b, "%lld",
                    static_cast<long long>(rng_.next() >> pick(63)) * (u() < 0.5 ? -1 : 1));
      return b;
    }
    std::snprintf(b, sizeof b, "%.17g", (u() - 0.3) * std::pow(10.0, u() * 40 - 20));
    return b;
  }

  std::string key() {
    static const char* keys[] = {"format",
                                 "array",
                                 "model",
                                 "receptors",
                                 "weights",
                                 "max_current_mA",
                                 "electrodes",
                                 "pitch_mm",
                                 "positions_mm",
                                 "width_mm",
                                 "length_mm",
                                 "conductor",
                                 "resistivity_ohm_m",
                                 "lateral_margin_mm",
                                 "name",
                                 "orientation",
                                 "depth_mm",
                                 "diameter_um",
                                 "myelinated",
                                 "note",
                                 "channels",
                                 "currents_mA",
                                 "pulse",
                                 "width_us",
                                 "interphase_us",
                                 "balance_width_us",
                                 "frequency_hz",
                                 "count",
                                 "duration_s",
                                 "electrode_area_mm2",
                                 "safety",
                                 "mode",
                                 "x"};
    return keys[pick(sizeof keys / sizeof *keys)];
  }

  std::string string_value() {
    static const char* v[] = {"tactile-primaries/1",
                              "tactile-primaries/stimulus/1",
                              "line2d",
                              "strip2d",
                              "horizontal",
                              "vertical",
                              "SAI",
                              "RA",
                              "PC",
                              "",
                              "\\u0000"};
    return std::string("\"") + v[pick(sizeof v / sizeof *v)] + "\"";
  }

  std::string value(int depth) {
    const double k = u();
    if (depth > 5 || k < 0.35) return number();
    if (k < 0.45) return string_value();
    if (k < 0.5) return u() < 0.5 ? (u() < 0.5 ? "true" : "false") : "null";
    const bool object = k < 0.78;
    const std::size_t n = pick(depth == 0 ? 9 : 12);
    std::string out = object ? "{" : "[";
    for (std::size_t i = 0; i < n; ++i) {
      if (i) out += ",";
      if (object) out += "\"" + key() + "\":";
      out += value(depth + 1);
    }
    return out + (object ? "}" : "]");
  }

  // A valid document or stimulus with some fields replaced by random values.
  std::string near_valid() {
    Json d = Json::parse(
        u() < 0.5 ? R"({"format": "tactile-primaries/1", "array": {"electrodes": 8, "pitch_mm": 1,
                 "width_mm": 0.5, "length_mm": 10}, "model": {"conductor": "line2d",
                 "resistivity_ohm_m": 3, "lateral_margin_mm": 5}, "receptors": [
                 {"name": "RA", "orientation": "vertical", "depth_mm": [0.7, 2.0], "diameter_um": 4},
                 {"name": "SAI", "orientation": "horizontal", "depth_mm": 0.9, "diameter_um": 10},
                 {"name": "PC", "orientation": "horizontal", "depth_mm": 2.0, "diameter_um": 10}],
                 "weights": [0, 0, -0.5, 1, -0.5, 0, 0, 0], "max_current_mA": 2})"
                  : R"({"format": "tactile-primaries/stimulus/1", "channels": 3,
                 "currents_mA": [1, -0.5, -0.5], "max_current_mA": 2,
                 "pulse": {"width_us": 200, "interphase_us": 0, "balance_width_us": 200,
                 "frequency_hz": 200}, "count": 200, "electrode_area_mm2": 5})");
    std::string text = d.dump();
    // Replace a few number tokens by random numbers, or flip a few bytes.
    for (int m = static_cast<int>(pick(4)); m >= 0; --m) {
      if (u() < 0.7) {
        std::size_t pos = pick(text.size());
        while (pos < text.size() && !(std::isdigit(static_cast<unsigned char>(text[pos])))) ++pos;
        std::size_t end = pos;
        while (end < text.size() && (std::isdigit(static_cast<unsigned char>(text[end])) ||
                                     text[end] == '.' || text[end] == 'e' || text[end] == '-'))
          ++end;
        if (pos < text.size()) text.replace(pos, end - pos, number());
      } else {
        text[pick(text.size())] = static_cast<char>(pick(256));
      }
    }
    return text;
  }

 private:
  SplitMix64 rng_;
};

void check_document_in_range(const Document& d) {
  using namespace ranges;
  const auto in = [](double v, const Range& r) {
    return std::isfinite(v) && v >= r.lo && v <= r.hi;
  };
  REQUIRE(d.setup.array.size() >= 1);
  REQUIRE(d.setup.array.size() <= static_cast<std::size_t>(max_electrodes));
  for (double x : d.setup.array.positions_mm) CHECK(in(x, position_mm));
  CHECK(in(d.setup.array.width_mm, width_mm));
  CHECK(in(d.setup.array.length_mm, length_mm));
  if (d.setup.array.pitch_mm) CHECK(in(*d.setup.array.pitch_mm, pitch_mm));
  if (d.setup.conductor.resistivity_ohm_m != 0)
    CHECK(in(d.setup.conductor.resistivity_ohm_m, resistivity_ohm_m));
  CHECK(in(d.setup.lateral_margin_mm, lateral_margin_mm));
  CHECK(in(d.max_current_mA, max_current_mA));
  for (const Receptor& r : d.setup.receptors) {
    CHECK(in(r.depth_min_mm, depth_mm));
    CHECK(in(r.depth_max_mm, depth_mm));
    CHECK(r.depth_min_mm <= r.depth_max_mm);
    CHECK(in(r.fibre.diameter_um, diameter_um));
  }
  if (d.weights) {
    CHECK(d.weights->size() == d.setup.array.size());
    for (double w : *d.weights) CHECK(in(w, weight));
  }
}

}  // namespace

TEST_CASE("document parsers: random JSON is a document in range, or bad input",
          "[io][fuzz][parse]") {
  const char* env = std::getenv("TP_FUZZ_ITERATIONS");
  const long cases = env ? std::max(1L, std::atol(env) / 50) : 20000;
  Gen g(20261123);
  long documents = 0, stimuli = 0, tables = 0, refused = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (long c = 0; c < cases; ++c) {
    const std::string text = g.u() < 0.5 ? g.near_valid() : g.value(0);
    Json j;
    try {
      j = parse_json_text(text, "fuzz", "case " + std::to_string(c));
    } catch (const Error& e) {
      CHECK(e.code() == ExitCode::bad_input);
      ++refused;
      continue;
    }
    INFO("case " << c << ": " << text.substr(0, 400));
    try {
      const Document d = document_from_json(j);
      check_document_in_range(d);
      // What a program prints parses back to the same document.
      const Json out = document_to_json(d);
      CHECK(document_to_json(document_from_json(Json::parse(out.dump()))).dump() == out.dump());
      ++documents;
    } catch (const Error& e) {
      CHECK(e.code() == ExitCode::bad_input);
    }
    try {
      const Stimulus s = stimulus_from_json(j);
      try {
        check_stimulus(s, StimulusLimits{});
        CHECK(s.count >= 1);
        CHECK(s.duration_s() <= StimulusLimits{}.max_duration_s);
        for (double i : s.currents_mA) CHECK(std::fabs(i) <= 2.0 + 1e-12);
        CHECK(stimulus_to_json(s).dump().find("null") == std::string::npos);
        ++stimuli;
      } catch (const Error& e) {
        CHECK(e.code() == ExitCode::bad_input);
      }
    } catch (const Error& e) {
      CHECK(e.code() == ExitCode::bad_input);
    }
    try {
      for (const Receptor& r : receptors_from_json(j)) {
        CHECK(r.depth_min_mm >= ranges::depth_mm.lo);
        CHECK(r.fibre.diameter_um <= ranges::diameter_um.hi);
      }
      ++tables;
    } catch (const Error& e) {
      CHECK(e.code() == ExitCode::bad_input);
    }
  }
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  WARN("document fuzz: " << cases << " cases in " << secs << " s: " << refused
                         << " refused as JSON, " << documents << " valid documents, " << stimuli
                         << " valid stimuli, " << tables << " receptor tables");
  CHECK(documents > 0);  // the generator reaches valid documents, so the checks run
  CHECK(stimuli > 0);
}
