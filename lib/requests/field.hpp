#pragma once
// af-field's work, for the program and the Python module alike (docs/programs.md,
// af-field): a document, weights and an amplitude become the activating function on an
// x-y grid (CSV), over an x-z plane at one depth under a 2-D array (CSV), or each
// receptor's largest AF with the mode ratios (JSON).  Bad input names the program's flags.
//
//   AfFieldRequest r;  r.array.electrodes = "8";  r.weights = "0,0,-1,2,-1,0,0,0";
//   const Document doc = af_field_document(r);      // the array, the weights, the model
//   const AfFieldPlan plan = plan_af_field(doc, r);  // every check before the field
//   run_af_field(doc, plan, write);                  // the field's checks, then the rows

#include <string>
#include <vector>

#include "core/number.hpp"
#include "io/csv.hpp"
#include "io/document.hpp"
#include "requests/document_options.hpp"

namespace tp {

// The values of af-field's options, the texts as given (empty: not given); each is parsed
// by the checks, in the program's order, so that a bad one is named by its flag.
struct AfFieldRequest {
  ArrayOptions array;       // --config, or the array's flags (at least one electrode)
  ModelOptions model;       // --model, --z, --skin
  std::string weights;      // --weights W1,W2,... [the document's; else one cathode on the
                            // electrode nearest the centre]
  std::string amplitude;    // --amplitude, mA [the document's max_current_mA]
  std::string x, y, z;      // --x, --y, --z-grid MIN:MAX:STEP, mm [default_x_axis, ...]
  std::string plane_depth;  // --plane-depth MM: the x-z plane at this depth (3-D models)
  bool summary = false;     // --summary: each receptor's largest AF and the ratios (JSON)
};

// The document of --config or the array's flags, with --weights (parsed before the model's
// flags are applied, which are checked against it), then weights by default: one cathode
// (1) on the electrode nearest the centre when neither the document nor --weights has any.
Document af_field_document(const AfFieldRequest& r);

// What af-field computes, every option checked.
struct AfFieldPlan {
  enum class Output { grid, plane, summary };
  Output output = Output::grid;
  std::vector<double> currents_mA;  // weight * amplitude, one per electrode
  Axis x;                           // along the skin (grid and plane)
  Axis y;                           // the grid's depths
  Axis z;                           // the plane's across
  double depth_mm = 0.0;            // the plane's depth
};

// The checks that do not need the field, in af-field's order: the weights' count, the
// amplitude, each weight's range, the options' combinations (--summary with --x, --y or
// --plane-depth; --z-grid without --plane-depth; --y with --plane-depth), a fibre plane
// (--z, model.plane_z_mm) where it would be ignored, the axes and the work.
AfFieldPlan plan_af_field(const Document& doc, const AfFieldRequest& r);

// The field, its checks (the plane needs a 3-D model; the model's reach), then the output
// through `out`: the CSV rows (about 1 MB a call) or the summary's JSON (one call).
void run_af_field(const Document& doc, const AfFieldPlan& plan, const ByteSink& out);

// The checks the Python module shares, `what` naming the weights ("--weights", Python's
// "weights"): bad input unless there is one weight per electrode ("WHAT: expected N values
// (one per electrode), got M") and each is within ranges::weight ("WHAT item I ...").
void check_weight_count(const Document& doc, const std::vector<double>& weights,
                        const std::string& what);
void check_weight_range(const std::vector<double>& weights, const std::string& what);
// The amplitude (mA on an electrode of |w| = 1) within ranges::amplitude_mA ("--amplitude").
void check_af_amplitude(double amplitude_mA);
// --summary under a 2-D array: a fibre plane (--z, or the document's model.plane_z_mm) is
// refused, the summary's fibres filling every z.
void refuse_summary_plane_z(const Document& doc, const ModelOptions& model);
// weight * amplitude, one per electrode.
std::vector<double> af_currents_mA(const std::vector<double>& weights, double amplitude_mA);

}  // namespace tp
