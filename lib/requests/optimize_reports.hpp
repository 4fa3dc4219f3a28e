#pragma once
// The documents and CSV rows of optimize-weights' results (docs/document-format.md), beside
// the request that makes them (requests/optimize) and for the Python module alike.

#include <optional>
#include <string>

#include "core/json.hpp"
#include "model/field.hpp"

namespace tp {

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
