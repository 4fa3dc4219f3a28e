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

TEST_CASE("2-D arrays: the document's grid and pads, read back unchanged", "[array2d][io]") {
  const Json grid = Json::parse(R"({"array": {"grid": {"columns": 3, "rows": 2, "pitch_mm": 2,
      "row_pitch_mm": 3}, "width_mm": 1, "length_mm": 1.5}})");
  const Document d = document_from_json(grid);
  CHECK(d.setup.conductor.model == "rect3d");  // a 2-D array's default model
  CHECK(d.setup.array.size() == 6);
  const Document back = document_from_json(document_to_json(d));
  CHECK(back.setup.array.positions_mm == d.setup.array.positions_mm);
  CHECK(back.setup.array.z_mm == d.setup.array.z_mm);
  CHECK(back.setup.array.columns == 3);
  const Json pads = Json::parse(R"({"array": {"pads": [{"x_mm": 0, "z_mm": 0},
      {"x_mm": 1, "z_mm": 0}, {"x_mm": 0, "z_mm": 2}], "width_mm": 1, "length_mm": 2},
      "model": {"conductor": "point3d"}})");
  const Document p = document_from_json(pads);
  CHECK(p.setup.array.size() == 3);
  CHECK(document_from_json(document_to_json(p)).setup.array.z_mm == p.setup.array.z_mm);
}

TEST_CASE("2-D arrays refuse overlapping pads, too many pads and the 2-D models", "[array2d][io]") {
  auto refuses = [](const char* text, const char* says) {
    try {
      document_from_json(Json::parse(text));
      FAIL("accepted " << text);
    } catch (const Error& e) {
      CHECK(e.code() == ExitCode::bad_input);
      CHECK_THAT(e.what(), Catch::Contains(says));
    }
  };
  // Touching along an edge is allowed, also where a grid's centres are rounded (0.3 mm);
  // closer is not.
  for (const double p : {0.1, 0.15, 0.3, 0.7, 1.1, 2.3})
    CHECK_NOTHROW(ElectrodeArray::grid_of(8, 8, p, p, p, p));
  CHECK_NOTHROW(document_from_json(Json::parse(R"({"array": {"pads": [{"x_mm": 0, "z_mm": 0},
      {"x_mm": 1, "z_mm": 0.5}], "width_mm": 1, "length_mm": 1}})")));
  refuses(R"({"array": {"pads": [{"x_mm": 0, "z_mm": 0}, {"x_mm": 0.9, "z_mm": 0.5}],
      "width_mm": 1, "length_mm": 1}})",
          "overlap");
  refuses(R"({"array": {"grid": {"columns": 3, "rows": 3, "pitch_mm": 1}, "width_mm": 1.5,
      "length_mm": 0.5}})",
          "overlap");
  refuses(R"({"array": {"grid": {"columns": 16, "rows": 17, "pitch_mm": 2}, "width_mm": 1,
      "length_mm": 1}})",
          "at most 256");
  refuses(R"({"array": {"grid": {"columns": 2, "rows": 2, "pitch_mm": 2}, "width_mm": 1,
      "length_mm": 1}, "model": {"conductor": "line2d"}})",
          "takes no 2-D array");
  refuses(R"({"array": {"grid": {"columns": 2, "rows": 2, "pitch_mm": 2}, "width_mm": 1,
      "length_mm": 1}, "model": {"conductor": "strip2d"}})",
          "takes no 2-D array");
  refuses(R"({"array": {"grid": {"columns": 2, "rows": 2, "pitch_mm": 2}}})", "width_mm");
  refuses(R"({"array": {"electrodes": 4, "pitch_mm": 1}, "receptors": [{"name": "A",
      "orientation": "horizontal", "depth_mm": 1, "diameter_um": 10, "azimuth_deg": 30},
      {"name": "B", "orientation": "vertical", "depth_mm": [0.7, 2], "diameter_um": 4}]})",
          "azimuth_deg applies under a 2-D array");
  ElectrodeArray many;
  for (int i = 0; i < 257; ++i) {
    many.positions_mm.push_back(2.0 * i - 256.0);
    many.z_mm.push_back(0.0);
  }
  many.width_mm = 1.0;
  many.length_mm = 1.0;
  CHECK_THROWS_AS(many.validate(), Error);
}
