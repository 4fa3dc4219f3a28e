#include "requests/field.hpp"

#include "core/error.hpp"
#include "core/json.hpp"
#include "core/ranges.hpp"
#include "io/reports.hpp"
#include "model/field.hpp"

namespace tp {

namespace {

// The x-z plane at --plane-depth: --y refused, no fibre plane, the depth, the axes, the
// work and the model's depth checked.
void plan_plane(const Document& doc, const AfFieldRequest& r, AfFieldPlan& plan) {
  if (!r.y.empty()) bad_input("--y: does not apply with --plane-depth (one depth)");
  refuse_plane_z(doc, r.model, "with --plane-depth (a plane at one depth, over every z)");
  const double depth = parse_finite(r.plane_depth, "--plane-depth");
  ranges::check(depth, ranges::depth_mm, "--plane-depth");
  plan.output = AfFieldPlan::Output::plane;
  plan.depth_mm = depth;
  plan.x = r.x.empty() ? default_x_axis(doc.setup.array) : parse_axis(r.x, "--x");
  plan.z = r.z.empty() ? default_z_axis(doc.setup.array) : parse_axis(r.z, "--z-grid");
  validate_plane(plan.x, plan.z, depth);
  check_grid_work(static_cast<double>(plan.x.count()) * static_cast<double>(plan.z.count()),
                  doc.setup.array.size());
  check_model_depth(doc.setup, depth, "--plane-depth");
}

// The x-y grid (every check before the first row is written), or the summary.
void plan_grid(const Document& doc, const AfFieldRequest& r, AfFieldPlan& plan) {
  plan.output = r.summary ? AfFieldPlan::Output::summary : AfFieldPlan::Output::grid;
  plan.x = r.x.empty() ? default_x_axis(doc.setup.array) : parse_axis(r.x, "--x");
  plan.y = r.y.empty() ? default_y_axis() : parse_axis(r.y, "--y");
  if (r.summary) return;
  validate_grid(plan.x, plan.y);
  check_grid_work(static_cast<double>(plan.x.count()) * static_cast<double>(plan.y.count()),
                  doc.setup.array.size());
  check_model_depth(doc.setup, plan.y.at(plan.y.count() - 1), "--y: the deepest row,");
}

}  // namespace

Document af_field_document(const AfFieldRequest& r) {
  Document doc = load_document(r.array, 1);
  if (!r.weights.empty()) doc.weights = parse_list(r.weights, "--weights");
  apply_model_options(doc, r.model);
  if (!doc.weights) {
    // Default pattern: one cathode at the electrode nearest the centre.
    doc.weights = std::vector<double>(doc.setup.array.size(), 0.0);
    (*doc.weights)[doc.setup.array.centre_index()] = 1.0;
  }
  return doc;
}

AfFieldPlan plan_af_field(const Document& doc, const AfFieldRequest& r) {
  if (!doc.weights) bad_input("--weights: the document has none");
  const std::vector<double>& w = *doc.weights;
  check_weight_count(doc, w, "--weights");
  const double amp =
      r.amplitude.empty() ? doc.max_current_mA : parse_finite(r.amplitude, "--amplitude");
  check_af_amplitude(amp);
  check_weight_range(w, "--weights");
  AfFieldPlan plan;
  plan.currents_mA = af_currents_mA(w, amp);
  if (r.summary && (!r.x.empty() || !r.y.empty() || !r.plane_depth.empty()))
    bad_input("--summary: --x, --y and --plane-depth do not apply");
  if (!r.z.empty() && r.plane_depth.empty()) bad_input("--z-grid: applies with --plane-depth only");
  if (r.summary && doc.setup.array.two_d()) refuse_summary_plane_z(doc, r.model);
  if (!r.plane_depth.empty())
    plan_plane(doc, r, plan);
  else
    plan_grid(doc, r, plan);
  return plan;
}

void run_af_field(const Document& doc, const AfFieldPlan& plan, const ByteSink& out) {
  const Field field(doc.setup, plan.currents_mA);
  switch (plan.output) {
    case AfFieldPlan::Output::plane:
      if (!field.conductor().three_d())
        bad_input("--plane-depth: " + doc.setup.conductor.model +
                  " does not evaluate points off the fibres' plane; use point3d, rect3d or "
                  "layered");
      check_plane(doc.setup, field.conductor(), plan.x, plan.z, plan.depth_mm);
      write_af_plane(out, field, plan.x, plan.z, plan.depth_mm);
      return;
    case AfFieldPlan::Output::grid:
      check_grid(doc.setup, field.conductor(), plan.x, plan.y);  // before the first row
      write_af_grid(out, field, plan.x, plan.y);
      return;
    case AfFieldPlan::Output::summary: {
      const Summary s = summarize(doc.setup, plan.currents_mA);
      out(dump_json(summary_to_json(doc.setup, plan.currents_mA, s)));
      return;
    }
  }
}

void check_weight_count(const Document& doc, const std::vector<double>& weights,
                        const std::string& what) {
  if (weights.size() != doc.setup.array.size())
    bad_input(what + ": expected " + std::to_string(doc.setup.array.size()) +
              " values (one per electrode), got " + std::to_string(weights.size()));
}

void check_weight_range(const std::vector<double>& weights, const std::string& what) {
  for (std::size_t i = 0; i < weights.size(); ++i)
    ranges::check(weights[i], ranges::weight, what + " item " + std::to_string(i + 1));
}

void check_af_amplitude(double amplitude_mA) {
  ranges::check(amplitude_mA, ranges::amplitude_mA, "--amplitude");
}

void refuse_summary_plane_z(const Document& doc, const ModelOptions& model) {
  refuse_plane_z(doc, model,
                 "to --summary under a 2-D array (its fibres fill every z; the plane places "
                 "af-field's x-y section only)");
}

std::vector<double> af_currents_mA(const std::vector<double>& weights, double amplitude_mA) {
  std::vector<double> currents_mA;
  currents_mA.reserve(weights.size());
  for (double w : weights) currents_mA.push_back(w * amplitude_mA);
  return currents_mA;
}

}  // namespace tp
