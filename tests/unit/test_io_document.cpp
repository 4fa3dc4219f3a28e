// The JSON document (io/document): round trips, extra keys kept, malformed documents.
#include <catch2/catch.hpp>

#include <string>

#include "core/error.hpp"
#include "core/json.hpp"
#include "io/document.hpp"
#include "error_support.hpp"

using namespace tp;
using tp::test::code_of;

TEST_CASE("documents round-trip and keep extra keys", "[io][document]") {
  Document d;
  d.setup.array = ElectrodeArray::uniform(4, 1.5);
  d.weights = std::vector<double>{1, -1, 0.5, -0.5};
  d.max_current_mA = 1.5;
  d.extra["mode"] = "SAI";
  d.extra["ratio"] = 0.25;
  const Json j = document_to_json(d);
  const Document e = document_from_json(Json::parse(j.dump()));
  CHECK(e.setup.array.positions_mm == d.setup.array.positions_mm);
  CHECK(*e.setup.array.pitch_mm == 1.5);
  CHECK(*e.weights == *d.weights);
  CHECK(e.max_current_mA == 1.5);
  CHECK(e.extra["mode"] == "SAI");
  CHECK(e.setup.receptors.size() == 3);
  CHECK(document_to_json(e).dump() == j.dump());
}

TEST_CASE("malformed documents are bad input", "[io][document]") {
  auto bad = [](const char* text) {
    return code_of([&] { document_from_json(Json::parse(text)); });
  };
  CHECK(bad(R"({})") == ExitCode::bad_input);
  CHECK(bad(R"([1,2])") == ExitCode::bad_input);
  CHECK(bad(R"({"array": {"electrodes": 2}})") == ExitCode::bad_input);
  CHECK(bad(R"({"array": {"electrodes": 2, "pitch_mm": 0}})") == ExitCode::bad_input);
  CHECK(bad(R"({"array": {"electrodes": 2, "pitch_mm": 1, "bogus": 1}})") == ExitCode::bad_input);
  CHECK(bad(R"({"array": {"electrodes": 2, "pitch_mm": 1}, "weights": [1]})") ==
        ExitCode::bad_input);
  CHECK(bad(R"({"array": {"electrodes": 2, "pitch_mm": 1}, "weights": [1, "a"]})") ==
        ExitCode::bad_input);
  CHECK(bad(R"({"array": {"positions_mm": [0, 0.1]}})") == ExitCode::bad_input);
  CHECK(bad(R"({"array": {"electrodes": 2, "pitch_mm": 1}, "model": {"conductor": "x"}})") ==
        ExitCode::bad_input);
  CHECK(bad(R"({"array": {"electrodes": 2, "pitch_mm": 1}, "receptors": []})") ==
        ExitCode::bad_input);
  CHECK(bad(R"({"array": {"electrodes": 2, "pitch_mm": 1}, "format": "other"})") ==
        ExitCode::bad_input);
  CHECK(bad(R"({"array": {"electrodes": 2, "pitch_mm": 1}, "weights": [1, -1]})") == ExitCode::ok);
}
