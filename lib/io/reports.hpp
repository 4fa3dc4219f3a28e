#pragma once
// Output of the model: the AF on a grid (CSV) and the per-receptor summary (JSON).

#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "io/csv.hpp"
#include "core/json.hpp"
#include "core/number.hpp"
#include "model/field.hpp"

namespace tp {

// Columns x_mm,y_mm,af_h,af_v: the AF of horizontal and vertical myelinated fibres of the
// reference diameter, one row per grid point, y outer, x inner.  Rejects y <= 0.  The rows
// go to `out` about 1 MB at a time (a program's tp::cli::write_stdout).
void validate_grid(const Axis& x, const Axis& y);
void write_af_grid(const ByteSink& out, const Field& field, const Axis& x, const Axis& y);

// Columns x_mm,z_mm,af_h,af_v: the AF over the plane at depth y_mm (3-D models), af_h of
// horizontal fibres along x, af_v of vertical ones, z outer, x inner.
void validate_plane(const Axis& x, const Axis& z, double y_mm);
void write_af_plane(const ByteSink& out, const Field& field, const Axis& x, const Axis& z,
                    double y_mm);

// Bad input when a grid of `points` over `pads` electrodes would take more than 6.4e9 pad
// evaluations (1e8 points of a 64-electrode array): hours of output.
void check_grid_work(double points, std::size_t pads);

// Default grid: the array +-5 mm at 0.1 mm, depths 0.2 to 3 mm at 0.05 mm; along z, the
// pads' centres +-5 mm at 0.1 mm.
Axis default_x_axis(const ElectrodeArray& a);
Axis default_y_axis();
Axis default_z_axis(const ElectrodeArray& a);

// {"af_unit", "currents_mA", "receptors": {NAME: {max_af, x_mm, y_mm, ...}}, "ratios": {...}}
Json summary_to_json(const Setup& setup, const std::vector<double>& currents_mA, const Summary& s);

// optimize-weights' document: the input document's array, model and receptors with the
// new weights, plus mode, ratio, per-receptor maxima at the current limit and solver facts.
struct Document;
struct OptimizeResult;
Json optimize_result_to_json(const Document& doc, const OptimizeResult& r, bool with_time,
                             const std::optional<double>& certified);

// optimize-weights --at: the document with the focal weights, the mode, the ratio, the
// focus (place, radius, spill bound and spill reached, the target's peak) and the solver.
struct FocusOptions;
struct FocusResult;
Json focus_result_to_json(const Document& doc, const FocusResult& r, const FocusOptions& o,
                          bool with_time);

// optimize-weights --bank: the document without weights, the bank's settings and counts,
// and per pixel its place, its pad and each mode's pattern (weights, ratio, target AF,
// peak, spill, whether the bounds hold on the array, and how it was derived) or why no
// pattern satisfies it.
struct Bank;
struct BankOptions;
Json bank_to_json(const Document& doc, const Bank& bank, const BankOptions& o);

// One CSV row per result: electrodes,pitch_mm,mode,ratio,target_max_af,max_af_<R>...,w0,w1,...
std::string optimize_csv_header(const Setup& setup);  // the header line, with its newline
std::string optimize_csv_row(const Setup& setup, const OptimizeResult& r);
// The same columns for a pixel (optimize-weights --at --format csv).
std::string focus_csv_row(const Setup& setup, const FocusResult& r);

}  // namespace tp
