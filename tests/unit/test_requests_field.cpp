// af-field's request (lib/requests/field.hpp): the default weights, the refusals with the
// program's messages in its order, the plan's defaults (the amplitude, the axes), and the
// output: the grid's rows through the writer, the summary's JSON.
#include <catch2/catch.hpp>

#include <algorithm>
#include <string>
#include <string_view>
#include <vector>

#include "core/json.hpp"
#include "error_support.hpp"
#include "io/reports.hpp"
#include "requests/field.hpp"

using namespace tp;
using tp::test::message_of;

namespace {

// --electrodes 8, with the given weights text and options.
AfFieldRequest uniform(const std::string& weights = "") {
  AfFieldRequest r;
  r.array.electrodes = "8";
  r.weights = weights;
  return r;
}

// The plan's refusal (af_field_document's, then plan_af_field's), "" if none.
std::string plan_refusal(const AfFieldRequest& r) {
  return message_of([&] { plan_af_field(af_field_document(r), r); });
}

// Everything the writer is given, in order.
std::string output_of(const AfFieldRequest& r) {
  const Document doc = af_field_document(r);
  const AfFieldPlan plan = plan_af_field(doc, r);
  std::string text;
  run_af_field(doc, plan, [&](std::string_view bytes) { text.append(bytes); });
  return text;
}

}  // namespace

TEST_CASE("af-field: the default weights are one cathode on the centre electrode",
          "[requests][field]") {
  const Document doc = af_field_document(uniform());
  REQUIRE(doc.weights);
  REQUIRE(doc.weights->size() == 8);
  const std::size_t centre = doc.setup.array.centre_index();
  for (std::size_t i = 0; i < 8; ++i) CHECK((*doc.weights)[i] == (i == centre ? 1.0 : 0.0));
  // --weights replaces them, as given.
  const Document given = af_field_document(uniform("0,0,-1,2,-1,0,0,0"));
  CHECK(*given.weights == std::vector<double>{0, 0, -1, 2, -1, 0, 0, 0});
}

TEST_CASE("af-field: the amplitude defaults to the document's limit, the axes to the array's",
          "[requests][field]") {
  AfFieldRequest r = uniform("0,0,-1,2,-1,0,0,0");
  const Document doc = af_field_document(r);
  AfFieldPlan plan = plan_af_field(doc, r);
  CHECK(plan.output == AfFieldPlan::Output::grid);
  CHECK(plan.currents_mA == std::vector<double>{0, 0, -2, 4, -2, 0, 0, 0});  // 2 mA
  CHECK(plan.x.min == default_x_axis(doc.setup.array).min);
  CHECK(plan.x.max == default_x_axis(doc.setup.array).max);
  CHECK(plan.y.min == 0.2);
  CHECK(plan.y.max == 3.0);
  CHECK(plan.y.step == 0.05);
  r.amplitude = "0.5";
  r.y = "0.5:1:0.25";
  plan = plan_af_field(doc, r);
  CHECK(plan.currents_mA == std::vector<double>{0, 0, -0.5, 1, -0.5, 0, 0, 0});
  CHECK(plan.y.count() == 3);
  r = uniform();
  r.summary = true;
  CHECK(plan_af_field(doc, r).output == AfFieldPlan::Output::summary);
}

TEST_CASE("af-field: refusals name the flag, in the program's order", "[requests][field]") {
  // The weights' count before the amplitude, the amplitude before each weight's range.
  AfFieldRequest r = uniform("1,2");
  r.amplitude = "200";
  CHECK(plan_refusal(r) == "--weights: expected 8 values (one per electrode), got 2");
  r.weights = "0,0,0,0,0,0,0,5000";
  CHECK(plan_refusal(r) == "--amplitude: 200 mA outside [1e-06, 100] mA");
  r.amplitude = "1";
  CHECK_THAT(plan_refusal(r), Catch::StartsWith("--weights item 8: 5000"));
  // --weights is read before the model's flags.
  r = uniform("abc");
  r.model.model = "nonesuch";
  CHECK(plan_refusal(r) == "--weights item 1: not a number 'abc'");
  r.weights.clear();
  CHECK_THAT(plan_refusal(r), Catch::StartsWith("--model: unknown conductor model"));
}

TEST_CASE("af-field: the options' combinations", "[requests][field]") {
  AfFieldRequest r = uniform();
  r.summary = true;
  r.x = "0:1:1";
  CHECK(plan_refusal(r) == "--summary: --x, --y and --plane-depth do not apply");
  r.x.clear();
  r.plane_depth = "1";
  CHECK(plan_refusal(r) == "--summary: --x, --y and --plane-depth do not apply");
  r = uniform();
  r.z = "0:1:1";
  CHECK(plan_refusal(r) == "--z-grid: applies with --plane-depth only");
  r.model.model = "point3d";
  r.plane_depth = "1";
  r.y = "1:2:1";
  CHECK(plan_refusal(r) == "--y: does not apply with --plane-depth (one depth)");
  r.y.clear();
  r.model.plane_z = "0.5";
  CHECK(plan_refusal(r) ==
        "--z: does not apply with --plane-depth (a plane at one depth, over every z)");
  r.model.plane_z.clear();
  r.plane_depth = "abc";
  CHECK_THAT(plan_refusal(r), Catch::StartsWith("--plane-depth: "));
  r.plane_depth = "100";
  CHECK(plan_refusal(r) == "--plane-depth: 100 mm outside [0.01, 20] mm");
  // A plane needs a 3-D model: the field's check, before any row.
  r = uniform();
  r.plane_depth = "1";
  std::string written;
  const std::string refusal = message_of([&] {
    const Document doc = af_field_document(r);
    run_af_field(doc, plan_af_field(doc, r), [&](std::string_view b) { written.append(b); });
  });
  CHECK(refusal ==
        "--plane-depth: line2d does not evaluate points off the fibres' plane; use point3d, "
        "rect3d or layered");
  CHECK(written.empty());
}

TEST_CASE("af-field: --summary under a 2-D array refuses a fibre plane", "[requests][field]") {
  AfFieldRequest r;
  r.array.grid = "4x4";
  r.array.pitch = "2";
  r.summary = true;
  r.model.plane_z = "1";
  const std::string why =
      "does not apply to --summary under a 2-D array (its fibres fill every z; the plane "
      "places af-field's x-y section only)";
  CHECK(plan_refusal(r) == "--z: " + why);
  // The document's model.plane_z_mm, as Python's summarize meets it (no --z).
  Document doc = af_field_document(r);
  doc.model_settings.push_back("plane_z_mm");
  CHECK(message_of([&] { refuse_summary_plane_z(doc, ModelOptions{}); }) ==
        "model.plane_z_mm: " + why);
}

TEST_CASE("af-field: the shared checks name the weights as the caller does", "[requests][field]") {
  Document doc = af_field_document(uniform());
  CHECK(message_of([&] {
          check_weight_count(doc, {1, 2, 3}, "weights");
        }) == "weights: expected 8 values (one per electrode), got 3");
  CHECK_THAT(message_of([&] {
               check_weight_range({0, -2000}, "weights");
             }),
             Catch::StartsWith("weights item 2: -2000"));
  CHECK(message_of([&] { check_weight_range({0, -1000, 1000}, "weights"); }).empty());
  CHECK(message_of([&] { check_af_amplitude(0.0); }) ==
        "--amplitude: 0 mA outside [1e-06, 100] mA");
  CHECK(af_currents_mA({1, -0.5}, 2.0) == std::vector<double>{2, -1});
}

TEST_CASE("af-field: the grid's rows and the summary through the writer", "[requests][field]") {
  AfFieldRequest r = uniform("0,0,-1,2,-1,0,0,0");
  r.x = "-1:1:1";
  r.y = "0.5:1:0.5";
  const std::string csv = output_of(r);
  CHECK(csv.rfind("x_mm,y_mm,af_h,af_v\n-1,0.5,", 0) == 0);
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 1 + 3 * 2);
  r.x.clear();
  r.y.clear();
  r.summary = true;
  const Json j = parse_json_text(output_of(r), "summary", "the writer");
  CHECK(j.contains("receptors"));
  CHECK(j.contains("ratios"));
  CHECK(j["currents_mA"].size() == 8);
}
