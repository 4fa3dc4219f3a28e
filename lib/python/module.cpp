// The Python module tactile_primaries._core (pybind11): the library's documents, fields,
// optimisation, fibre thresholds, stimuli and the stimulator, with NumPy arrays in and out.
// The package (lib/python/tactile_primaries/) wraps it; docs/python.md is the reference.
//
// Errors: the library's bad input is tactile_primaries.BadInput (a ValueError), a runtime
// failure tactile_primaries.Failure (a RuntimeError), each with the message the programs
// print after their name.  Long work releases the GIL.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>
#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <limits>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "core/error.hpp"
#include "fibre/report.hpp"
#include "host/delivery.hpp"
#include "host/impedance_check.hpp"
#include "host/live.hpp"
#include "host/session.hpp"
#include "host/transport.hpp"
#include "io/document.hpp"
#include "core/json.hpp"
#include "core/number.hpp"
#include "io/reports.hpp"
#include "model/constants.hpp"
#include "model/fibre_factor.hpp"
#include "model/field.hpp"
#include "core/ranges.hpp"
#include "requests/pulse.hpp"
#include "pulse/mix.hpp"
#include "requests/document_options.hpp"
#include "requests/field.hpp"
#include "requests/optimize.hpp"
#include "requests/threshold.hpp"
#include "version.hpp"

namespace py = pybind11;

namespace {

// ---------------------------------------------------------------------------------------
// JSON to Python objects (through the json module's text: exact for every double, since
// nlohmann's and Python's float repr both round-trip).

py::object to_python(const tp::Json& j) {
  // Kept for the process's life, never destroyed (a Python object must not be released
  // after the interpreter has finalised).
  static auto* loads = new py::object(py::module_::import("json").attr("loads"));
  return (*loads)(j.dump());
}
std::string number_arg(double v) {  // a float as the programs' flags would take it: the
  char b[40];                       // shortest text that reads back as the same double
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(b, sizeof b, "%.*g", digits, v);
    if (std::strtod(b, nullptr) == v) break;
  }
  return b;
}

// A keyword's float, refused as the program refuses its flag's text when it is not finite.
double finite_arg(double v, const std::string& flag) {
  if (!std::isfinite(v))
    tp::bad_input(flag + ": non-finite number '" +
                  std::string(std::isnan(v) ? "nan"
                              : v > 0       ? "inf"
                                            : "-inf") +
                  "'");
  return v;
}
std::optional<double> finite_arg(std::optional<double> v, const std::string& flag) {
  if (v) finite_arg(*v, flag);
  return v;
}

// phases=[(duration_us, level), ...]: --phases (at most 16, each number finite).
using PyPhases = std::optional<std::vector<std::pair<double, double>>>;
std::vector<tp::Phase> phases_arg(const PyPhases& phases) {
  std::vector<tp::Phase> out;
  if (!phases) return out;
  if (phases->size() > tp::kMaxPhases)
    tp::bad_input("--phases: more than " + std::to_string(tp::kMaxPhases) + " phases");
  for (const auto& [d_us, level] : *phases) {
    finite_arg(d_us, "--phases duration");
    finite_arg(level, "--phases level");
    out.push_back({d_us, level});
  }
  if (out.empty()) tp::bad_input("--phases: no phases");
  return out;
}
std::vector<double> finite_list(const std::vector<double>& v, const std::string& flag) {
  for (double x : v) finite_arg(x, flag);
  return v;
}

// A seed, 0 to 2^64 - 1, refused as the programs' --seed refuses it.
std::uint64_t seed_arg(const py::int_& seed) {
  const unsigned long long v = PyLong_AsUnsignedLongLong(seed.ptr());
  if (v == static_cast<unsigned long long>(-1) && PyErr_Occurred()) {
    PyErr_Clear();
    tp::bad_input("--seed: " + py::cast<std::string>(seed.attr("__str__")()) +
                  " outside [0, 18446744073709551615]");
  }
  return v;
}

std::string cli11_range_message(const std::string& flag, long v, long lo, long hi) {
  return flag + ": Value " + std::to_string(v) + " not in range " + std::to_string(lo) + " to " +
         std::to_string(hi);  // CLI11's words, as stimctl says it
}

// A path: str or os.PathLike.
std::string path_arg(const py::object& o) {
  static auto* fspath = new py::object(py::module_::import("os").attr("fspath"));
  return py::cast<std::string>((*fspath)(o));
}

// ---------------------------------------------------------------------------------------
// Documents.

struct PyDocument {
  tp::Document doc;
  static PyDocument from_json(const std::string& text) {
    return {tp::document_from_json(tp::parse_json_text(text, "document", "text"))};
  }
  static PyDocument load(const py::object& path) {
    return {tp::document_from_json(tp::read_json(path_arg(path), "document"))};
  }
  std::string to_json() const { return tp::dump_json(tp::document_to_json(doc)); }
  tp::Json json() const { return tp::document_to_json(doc); }
};

PyDocument document_of(const tp::Json& j) {
  return {tp::document_from_json(j)};
}

PyDocument make_document(std::optional<int> electrodes, std::optional<double> pitch_mm,
                         std::optional<std::string> grid, std::optional<double> row_pitch_mm,
                         std::optional<std::string> pad, std::optional<std::string> model,
                         std::optional<double> plane_z_mm, std::optional<std::string> skin) {
  tp::ArrayOptions a;
  if (electrodes) a.electrodes = std::to_string(*electrodes);
  if (pitch_mm) a.pitch = number_arg(*pitch_mm);
  if (grid) a.grid = *grid;
  if (row_pitch_mm) a.row_pitch = number_arg(*row_pitch_mm);
  if (pad) a.pad = *pad;
  if (a.electrodes.size() && a.grid.size()) tp::bad_input("--electrodes and --grid: give one");
  tp::Document d = tp::load_document(a, 1);
  tp::ModelOptions m;
  if (model) m.model = *model;
  if (plane_z_mm) m.plane_z = number_arg(*plane_z_mm);
  if (skin) m.skin = *skin;
  tp::apply_model_options(d, m);
  return {d};
}

PyDocument with_model(const PyDocument& in, std::optional<std::string> model,
                      std::optional<double> plane_z_mm, std::optional<std::string> skin) {
  tp::Document d = in.doc;
  tp::ModelOptions m;
  if (model) m.model = *model;
  if (plane_z_mm) m.plane_z = number_arg(*plane_z_mm);
  if (skin) m.skin = *skin;
  tp::apply_model_options(d, m);
  return {d};
}

std::vector<double> checked_weights(const tp::Document& doc, const std::string& what) {
  if (!doc.weights)
    tp::bad_input("weights: the document has none (optimize-weights writes them; or --weights)");
  tp::check_weight_count(doc, *doc.weights, what);  // af-field's checks (requests/field)
  tp::check_weight_range(*doc.weights, what);
  return *doc.weights;
}

// ---------------------------------------------------------------------------------------
// The activating function at points (af-field's values, without the CSV).

using Array = py::array_t<double, py::array::forcecast>;

// Arrays of one shape, read in C order through their strides: broadcast views (stride 0)
// are read in place, never copied.
struct Points {
  std::vector<py::ssize_t> shape;
  std::vector<const char*> base;
  std::vector<std::vector<py::ssize_t>> strides;  // bytes, per array
  std::size_t size = 1;
  explicit Points(const std::vector<Array*>& arrays) {
    const Array& a0 = *arrays[0];
    shape.assign(a0.shape(), a0.shape() + a0.ndim());
    for (py::ssize_t n : shape) size *= static_cast<std::size_t>(n);
    for (Array* a : arrays) {
      if (a->ndim() != a0.ndim() || !std::equal(shape.begin(), shape.end(), a->shape()))
        tp::bad_input("x_mm, y_mm, z_mm: the arrays do not have one shape");
      base.push_back(reinterpret_cast<const char*>(a->data()));
      strides.emplace_back(a->strides(), a->strides() + a->ndim());
    }
  }
  // f(i, values) for every point in C order; values[k] is array k's element.  The last axis
  // runs in a tight loop, the others through a counter.
  template <class F>
  void for_each(F&& f) const {
    if (size == 0) return;
    const std::size_t nd = shape.size(), na = base.size();
    double v[3] = {0, 0, 0};
    const char* p[3] = {nullptr, nullptr, nullptr};
    for (std::size_t k = 0; k < na; ++k) p[k] = base[k];
    if (nd == 0) {
      for (std::size_t k = 0; k < na; ++k) std::memcpy(&v[k], p[k], sizeof(double));
      f(std::size_t{0}, v);
      return;
    }
    const py::ssize_t inner = shape[nd - 1];
    py::ssize_t step[3] = {0, 0, 0};
    for (std::size_t k = 0; k < na; ++k) step[k] = strides[k][nd - 1];
    std::vector<py::ssize_t> idx(nd, 0);
    std::size_t i = 0;
    for (;;) {
      const char* q[3] = {p[0], p[1], p[2]};
      for (py::ssize_t j = 0; j < inner; ++j, ++i) {
        for (std::size_t k = 0; k < na; ++k) {
          std::memcpy(&v[k], q[k], sizeof(double));
          q[k] += step[k];
        }
        f(i, v);
      }
      std::size_t dd = nd - 1;  // the counter over the outer axes
      for (; dd-- > 0;) {
        for (std::size_t k = 0; k < na; ++k) p[k] += strides[k][dd];
        if (++idx[dd] < shape[dd]) break;
        for (std::size_t k = 0; k < na; ++k) p[k] -= strides[k][dd] * shape[dd];
        idx[dd] = 0;
      }
      if (dd == static_cast<std::size_t>(-1)) return;
    }
  }
};

std::pair<py::array_t<double>, py::array_t<double>> af_points(const PyDocument& d, Array x, Array y,
                                                              std::optional<Array> z,
                                                              std::optional<double> amplitude_mA) {
  const tp::Document& doc = d.doc;
  const std::vector<double> w = checked_weights(doc, "weights");
  const double amp = amplitude_mA ? finite_arg(*amplitude_mA, "--amplitude") : doc.max_current_mA;
  tp::check_af_amplitude(amp);
  std::vector<Array*> arrays{&x, &y};
  if (z) arrays.push_back(&*z);
  const Points pts(arrays);
  const std::size_t n = pts.size;
  const bool has_z = z.has_value();
  if (static_cast<double>(n) > tp::ranges::max_grid_points)
    tp::bad_input("grid: " + tp::number_text(static_cast<double>(n)) + " points, more than " +
                  tp::number_text(tp::ranges::max_grid_points));
  tp::check_grid_work(static_cast<double>(n), doc.setup.array.size());
  double x_lo = 0, x_hi = 0, y_lo = 0, y_hi = 0, z_lo = 0, z_hi = 0;
  const tp::ranges::Range& D = tp::ranges::depth_mm;
  const tp::ranges::Range& P = tp::ranges::position_mm;
  pts.for_each([&](std::size_t i, const double* v) {
    // The ranges by comparison; the message (ranges::check) only for a point outside.
    if (!(v[1] >= D.lo && v[1] <= D.hi && v[0] >= P.lo && v[0] <= P.hi &&
          (!has_z || (v[2] >= P.lo && v[2] <= P.hi)))) {
      if (!(v[1] > 0.0)) tp::bad_input("y_mm: depths must be > 0 mm (the skin surface is y = 0)");
      tp::ranges::check(v[1], D, "y_mm");
      tp::ranges::check(v[0], P, "x_mm");
      if (has_z) tp::ranges::check(v[2], P, "z_mm");
    }
    x_lo = i ? std::min(x_lo, v[0]) : v[0];
    x_hi = i ? std::max(x_hi, v[0]) : v[0];
    y_lo = i ? std::min(y_lo, v[1]) : v[1];
    y_hi = i ? std::max(y_hi, v[1]) : v[1];
    if (has_z) {
      z_lo = i ? std::min(z_lo, v[2]) : v[2];
      z_hi = i ? std::max(z_hi, v[2]) : v[2];
    }
  });
  const std::vector<double> currents = tp::af_currents_mA(w, amp);
  py::array_t<double> h(pts.shape), v(pts.shape);
  if (n == 0) return {h, v};
  tp::check_model_depth(doc.setup, y_hi, "y_mm: the deepest point,");
  const tp::Field field(doc.setup, currents);
  const tp::Setup& s = doc.setup;
  if (has_z && !field.conductor().three_d())
    tp::bad_input("z_mm: " + s.conductor.model +
                  " does not evaluate points off the fibres' plane; use point3d, rect3d or "
                  "layered");
  if (!has_z && s.array.two_d()) tp::bad_input("z_mm: the array is 2-D: give the points' z");
  // The layered model's reach, and a buried point source's singularity (af-field's checks).
  tp::check_points(s, field.conductor(), {x_lo, x_hi, y_lo, y_hi, z_lo, z_hi, has_z},
                   [&](const tp::PointVisitor& visit) {
                     pts.for_each([&](std::size_t, const double* p) {
                       visit(p[0], p[1], has_z ? p[2] : s.conductor.plane_z_mm);
                     });
                   });
  double* hp = h.mutable_data();
  double* vp = v.mutable_data();
  // The arrays are the caller's and the GIL is released: another thread could change them
  // meanwhile.  Each point is computed only inside the box checked above (cheap
  // comparisons); one outside is bad input after the loop, never evaluated.
  std::atomic<bool> changed{false};
  auto inside = [&](const double* p) {
    const bool ok = p[0] >= x_lo && p[0] <= x_hi && p[1] >= y_lo && p[1] <= y_hi &&
                    (!has_z || (p[2] >= z_lo && p[2] <= z_hi));
    if (!ok) changed = true;
    return ok;
  };
  {
    py::gil_scoped_release release;
    if (!has_z) {
      const double k = tp::fibre_factor_mm2_per_ms(
          tp::Fibre{tp::Orientation::horizontal, tp::constants::reference_diameter_um, true});
      pts.for_each([&](std::size_t i, const double* p) {
        double xx = 0.0, yy = 0.0;
        if (inside(p)) field.second_derivatives(p[0], p[1], xx, yy);
        hp[i] = k * xx;
        vp[i] = k * yy;
      });
    } else {
      const tp::Fibre fibre{tp::Orientation::horizontal, tp::constants::reference_diameter_um,
                            true};
      const tp::FibreAxis along_x{}, vertical{true, 0.0, 0.0};
      pts.for_each([&](std::size_t i, const double* p) {
        const bool ok = inside(p);
        hp[i] = ok ? field.af_3d(fibre, along_x, p[0], p[1], p[2]) : 0.0;
        vp[i] = ok ? field.af_3d(fibre, vertical, p[0], p[1], p[2]) : 0.0;
      });
    }
  }
  if (changed) tp::bad_input("x_mm, y_mm, z_mm: the arrays changed while af_field read them");
  return {h, v};
}

// The reference for the benchmark: the library alone computing af-field's values over the
// same grid (Field::second_derivatives over x fastest, as write_af_grid does, without the
// CSV), in seconds.
double af_grid_time_s(const PyDocument& d, double x0, double x1, double dx, double y0, double y1,
                      double dy) {
  const std::vector<double> currents =
      tp::af_currents_mA(checked_weights(d.doc, "weights"), d.doc.max_current_mA);
  const tp::Axis x{x0, x1, dx}, y{y0, y1, dy};
  py::gil_scoped_release release;
  const auto t0 = std::chrono::steady_clock::now();
  const tp::Field field(d.doc.setup, currents);
  const double k = tp::fibre_factor_mm2_per_ms(
      tp::Fibre{tp::Orientation::horizontal, tp::constants::reference_diameter_um, true});
  std::vector<double> h(x.count() * y.count()), v(h.size());
  std::size_t i = 0;
  for (std::size_t j = 0; j < y.count(); ++j)
    for (std::size_t q = 0; q < x.count(); ++q, ++i) {
      double xx = 0.0, yy = 0.0;
      field.second_derivatives(x.at(q), y.at(j), xx, yy);
      h[i] = k * xx;
      v[i] = k * yy;
    }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

py::object summarize(const PyDocument& d, std::optional<double> amplitude_mA) {
  const std::vector<double> w = checked_weights(d.doc, "weights");
  const double amp = amplitude_mA ? finite_arg(*amplitude_mA, "--amplitude") : d.doc.max_current_mA;
  if (d.doc.setup.array.two_d()) tp::refuse_summary_plane_z(d.doc, tp::ModelOptions{});
  tp::check_af_amplitude(amp);
  const std::vector<double> currents = tp::af_currents_mA(w, amp);
  tp::Json j;
  {
    py::gil_scoped_release release;
    const tp::Summary s = tp::summarize(d.doc.setup, currents);
    j = tp::summary_to_json(d.doc.setup, currents, s);
  }
  return to_python(j);
}

// ---------------------------------------------------------------------------------------
// optimize-weights: a mode's minimax weights, a pixel (at), a bank, or the threshold
// objective; the program's request (lib/requests/optimize.hpp) and its document.

// at: one place, [x] or [x, z]; with a bank, several.
using Places = std::variant<std::vector<double>, std::vector<std::vector<double>>>;

PyDocument optimize_weights(
    const PyDocument& d, std::optional<std::string> mode, std::optional<Places> at,
    std::optional<double> radius_mm, std::optional<double> spill,
    std::optional<double> max_current_mA, double min_target_af, std::optional<int> pattern_starts,
    std::optional<int> random_starts, bool certify, bool bank, std::optional<int> neighbourhood,
    std::optional<int> threads, std::optional<std::vector<std::string>> modes,
    const std::string& objective, std::optional<std::string> fibre_model,
    const std::string& geometry, const std::optional<py::object>& stimulus,
    std::optional<double> width_us, std::optional<double> interphase_us,
    std::optional<double> balance_width_us, bool monophasic, std::optional<int> offsets,
    std::optional<double> tolerance, std::optional<int> max_evaluations, bool timing,
    const PyPhases& phases, std::optional<int> population, std::optional<py::int_> seed,
    std::optional<double> max_charge_nC) {
  if (mode && modes) tp::bad_input("mode and modes: give one");
  if (modes && !bank) tp::bad_input("modes: several modes with bank=True only (one: mode=)");
  if (modes && modes->empty()) tp::bad_input("--mode: no modes given");
  if (objective != "af" && objective != "threshold" && objective != "selectivity")  // CLI11's
    tp::bad_input("--objective: " + objective + " not in {af,threshold,selectivity}");
  tp::OptimizeRequest r;
  r.modes = modes ? *modes : mode ? std::vector<std::string>{*mode} : std::vector<std::string>{};
  if (at && at->index() == 0) r.at_mm.push_back(std::get<0>(*at));
  if (at && at->index() == 1) r.at_mm = std::get<1>(*at);
  r.radius_mm = radius_mm;
  r.spill = spill;
  r.max_current_mA = max_current_mA;
  r.min_target_af = min_target_af;
  r.pattern_starts = pattern_starts;
  r.random_starts = random_starts;
  r.certify = certify;
  r.bank = bank;
  r.neighbourhood = neighbourhood;
  r.threads = threads;
  r.timing = timing;
  if (objective == "threshold") r.objective = tp::OptimizeObjective::threshold;
  if (objective == "selectivity") r.objective = tp::OptimizeObjective::selectivity;
  r.population = population;
  if (seed) r.seed = seed_arg(*seed);
  r.max_charge_nC = max_charge_nC;
  r.fibre.model = fibre_model.value_or("mrg");
  r.fibre_model_given = fibre_model.has_value();
  r.fibre.geometry = geometry;
  if (stimulus) r.fibre.stimulus = path_arg(*stimulus);
  r.fibre.width_us = width_us;
  r.fibre.interphase_us = interphase_us;
  r.fibre.balance_width_us = balance_width_us;
  r.fibre.monophasic = monophasic;
  r.fibre.phases = phases_arg(phases);
  r.fibre.offsets = offsets.value_or(8);
  r.offsets_given = offsets.has_value();
  r.fibre.tolerance = tolerance;
  r.max_evaluations = max_evaluations;
  py::gil_scoped_release release;
  return document_of(tp::run_optimize(d.doc, r).document);
}

// ---------------------------------------------------------------------------------------
// fiber-threshold.

// The program's stderr warnings ("warning: ..." notes) as Python warnings (UserWarning),
// so that filters and pytest see them; an error raised by a filter ("error") propagates.
void warn_notes(const std::vector<std::string>& notes) {
  const std::string prefix = "warning: ";
  for (const std::string& note : notes)
    if (note.compare(0, prefix.size(), prefix) == 0 &&
        PyErr_WarnEx(PyExc_UserWarning, note.substr(prefix.size()).c_str(), 1) != 0)
      throw py::error_already_set();
}

// A CSV table (what fiber-threshold prints with --strength-duration or --population) as
// its columns: {header: [values]}, a number as a float, an empty cell None, text (and the
// names in the receptor and class columns) a str.
py::dict csv_columns(const std::string& csv) {
  std::vector<std::string> names;
  std::vector<py::list> columns;
  std::size_t at = 0;
  for (bool header = true; at < csv.size(); header = false) {
    const std::size_t end = csv.find('\n', at);
    const std::string line = csv.substr(at, end - at);
    at = end == std::string::npos ? csv.size() : end + 1;
    std::size_t k = 0, from = 0;
    for (bool more = true; more; ++k) {
      const std::size_t comma = line.find(',', from);
      more = comma != std::string::npos;
      const std::string cell = line.substr(from, more ? comma - from : std::string::npos);
      from = comma + 1;
      if (header) {
        names.push_back(cell);
        columns.emplace_back();
        continue;
      }
      double v = 0.0;
      const char* last = cell.data() + cell.size();
      const bool name = names.at(k) == "receptor" || names[k] == "class";
      if (cell.empty())
        columns[k].append(py::none());
      else if (!name && std::from_chars(cell.data(), last, v).ptr == last)
        columns[k].append(v);
      else
        columns[k].append(cell);
    }
  }
  py::dict out;
  for (std::size_t k = 0; k < names.size(); ++k) out[py::str(names[k])] = columns[k];
  return out;
}

py::object fiber_threshold(const PyDocument& d, const std::string& model,
                           std::optional<double> width_us, std::optional<double> interphase_us,
                           std::optional<double> balance_width_us, bool monophasic, int offsets,
                           std::optional<double> tolerance, int threads,
                           std::optional<std::vector<double>> at,
                           std::optional<py::object> stimulus,
                           std::optional<std::string> conductor, const std::string& geometry,
                           bool strength_duration, std::optional<std::vector<double>> widths_us,
                           std::optional<long> population, std::optional<py::int_> seed,
                           const PyPhases& phases) {
  tp::ThresholdRequest r;
  if (conductor) r.conductor.model = *conductor;
  r.fibre.model = model;
  r.fibre.geometry = geometry;
  if (stimulus) r.fibre.stimulus = path_arg(*stimulus);
  r.fibre.width_us = width_us;
  r.fibre.interphase_us = interphase_us;
  r.fibre.balance_width_us = balance_width_us;
  r.fibre.monophasic = monophasic;
  r.fibre.phases = phases_arg(phases);
  r.fibre.offsets = offsets;
  r.fibre.tolerance = tolerance;
  if (tolerance) r.fibre.tolerance_text = number_arg(*tolerance);
  r.fibre.threads = threads;
  if (at) {
    r.at_mm = finite_list(*at, "--at");
    for (double v : *at) r.at_text += (r.at_text.empty() ? "" : ",") + number_arg(v);
  }
  r.strength_duration = strength_duration;
  if (widths_us) r.widths_us = finite_list(*widths_us, "--widths");
  r.population = population;
  if (seed) r.seed = seed_arg(*seed);
  tp::Document doc = d.doc;  // copied with the GIL held
  tp::ThresholdOutput out;
  {
    py::gil_scoped_release release;
    out = tp::run_thresholds(std::move(doc), r);
  }
  warn_notes(out.notes);
  if (out.document) return to_python(*out.document);
  if (!population) return csv_columns(out.table);
  py::dict both;
  both["afferents"] = csv_columns(out.table);
  both["recruitment"] = csv_columns(out.recruitment);
  return both;
}

// ---------------------------------------------------------------------------------------
// Stimuli.

struct PyStimulus {
  tp::Mix mix;
  static PyStimulus from_json(const std::string& text) {
    PyStimulus s{tp::mix_from_json(tp::parse_json_text(text, "stimulus", "text"))};
    tp::check_mix(s.mix, tp::StimulusLimits{});
    return s;
  }
  static PyStimulus load(const py::object& path) {
    PyStimulus s{tp::mix_from_json(tp::read_json(path_arg(path), "stimulus"))};
    tp::check_mix(s.mix, tp::StimulusLimits{});
    return s;
  }
  tp::Json json() const {
    return mix.table() ? tp::mix_to_json(mix) : tp::stimulus_to_json(mix.patterns[0]);
  }
  std::string to_json() const { return tp::dump_json(json()); }
};

PyStimulus make_pulse(const PyDocument& d, std::optional<double> amplitude_mA, double frequency_hz,
                      std::optional<double> width_us, std::optional<double> balance_width_us,
                      std::optional<double> interphase_us, std::optional<double> duration_s,
                      std::optional<long> count, std::optional<py::object> profile,
                      std::optional<double> intensity, const PyPhases& phases) {
  if (amplitude_mA && intensity) tp::bad_input("--amplitude excludes --intensity");
  if (duration_s && count) tp::bad_input("--duration excludes --count");
  finite_arg(amplitude_mA, "--amplitude");
  finite_arg(intensity, "--intensity");
  finite_arg(frequency_hz, "--frequency");
  finite_arg(width_us, "--width");
  finite_arg(balance_width_us, "--balance-width");
  finite_arg(interphase_us, "--interphase");
  finite_arg(duration_s, "--duration");
  tp::PulseRequest r;
  r.amplitude_mA = amplitude_mA;
  r.intensity = intensity;
  if (profile) {
    if (!d.doc.weights) tp::bad_input("weights document: no 'weights'");
    r.profile = tp::pulse_profile(d.doc, path_arg(*profile));
  }
  r.frequency_hz = frequency_hz;
  r.width_us = width_us;
  r.balance_width_us = balance_width_us;
  r.interphase_us = interphase_us;
  r.phases = phases_arg(phases);
  r.count = count;
  r.duration_s = duration_s;
  tp::Mix m;
  m.patterns.push_back(tp::make_stimulus(d.doc, r));
  return {m};
}

// ---------------------------------------------------------------------------------------
// The stimulator: stimctl's session on a thread of its own, the caller waiting with the GIL
// released and Python's signals checked every 20 ms.  KeyboardInterrupt (or any exception
// raised by a signal handler) sets the session's stop flag: the output stops first, then
// the exception goes on.

struct SessionRun {
  volatile std::sig_atomic_t flag = 0;  // a Python signal's exception: SIGINT
  tp::host::StopSource closed;          // close() from another thread
  std::shared_ptr<tp::host::FrameQueue> frames;  // a live session's input
  std::mutex m;
  std::condition_variable cv;
  bool done = false;
  tp::host::SessionReport report;
  tp::host::ImpedanceCheck check;  // an impedance check's
  std::exception_ptr error;
  std::thread thread;
};

// Each channel's impedance, kOhm: None where it carried no current, inf where none flowed.
py::list impedance_list(const std::vector<tp::device::ChannelMeasurement>& m) {
  py::list out;
  for (const auto& c : m) {
    if (!c.carried)
      out.append(py::none());
    else if (c.impedance_ohm == tp::device::kOpenOhm)
      out.append(std::numeric_limits<double>::infinity());
    else
      out.append(c.impedance_ohm * 1e-3);
  }
  return out;
}

py::dict report_dict(const tp::host::SessionReport& r) {
  py::dict d;
  d["port"] = r.port;
  d["end"] = r.end;
  d["exit_code"] = r.exit_code;
  d["started"] = r.started;
  d["preempted"] = r.preempted;
  d["pulses"] = r.pulses;
  d["frames"] = r.weight_frames;
  d["peak_mA"] = r.peak_mA;
  d["seconds"] = r.seconds;
  d["retransmissions"] = r.retransmissions;
  if (r.caps.measures()) d["impedances_kohm"] = impedance_list(r.measured);
  return d;
}

// One stimulator: its methods may be called from several Python threads.  One operation
// at a time holds the port (`busy_`): a delivery, or a live session from start_live to
// stop; close() from another thread stops a running one first and waits for it.
class Stimulator {
 public:
  Stimulator(const py::object& port, int baud, int emu_channels, std::optional<py::object> record,
             std::string backend, std::optional<py::object> emu_skin,
             std::optional<double> emu_compliance_V, std::string contact_loss,
             std::optional<double> probe_mA, bool hold_sensation)
  {
    // stimctl's request (host/delivery), checked as stimctl checks it; CLI11's range checks
    // of stimctl's flags, with CLI11's messages.
    if (!(baud >= 300 && baud <= 4000000))
      tp::bad_input(cli11_range_message("--baud", baud, 300, 4000000));
    if (!(emu_channels >= 1 && emu_channels <= 64))
      tp::bad_input(cli11_range_message("--emu-channels", emu_channels, 1, 64));
    if (backend != "auto" && backend != "libserialport" && backend != "posix")
      tp::bad_input("--backend: " + backend + " not in {auto,libserialport,posix}");
    req_.port = path_arg(port);
    req_.baud = baud;
    req_.backend = std::move(backend);
    if (record) req_.record_path = path_arg(*record);
    if (emu_skin) req_.emu_skin_path = path_arg(*emu_skin);
    req_.emu_compliance_V = emu_compliance_V;
    req_.contact_loss = std::move(contact_loss);
    req_.probe_mA = probe_mA;
    req_.hold_sensation = hold_sensation;
    // emu_channels always has a value here: a port's own channels win.
    if (req_.port == "emu") req_.emu_channels = emu_channels;
    tp::host::check_delivery(req_);
  }
  ~Stimulator() {
    // Only when Python destroys it (the GIL held): stop whatever runs.
    try {
      close();
    } catch (...) {
    }
  }

  void open() {
    std::lock_guard<std::mutex> lock(m_);
    open_locked();
  }

  // Delivers a stimulus; returns the session's report.  Blocks until it ends.
  py::dict deliver(const PyStimulus& s, std::optional<double> duration_s) {
    tp::host::SessionOptions opt = session_options(false, duration_s);
    tp::check_mix(s.mix, tp::StimulusLimits{});
    const std::unique_ptr<SessionRun> run = run_held("deliver", s.mix, opt, std::nullopt);
    return finish(*run);
  }

  // stimctl --check-impedance: the probe on every pad the stimulus uses; each pad's row, or
  // BadInput naming the pad without contact or the peak above the compliance.
  py::list check_impedance(const PyStimulus& s, double probe_mA) {
    tp::host::SessionOptions opt = session_options(false, std::nullopt);
    tp::check_mix(s.mix, tp::StimulusLimits{});
    tp::host::probe_stimulus(s.mix, probe_mA);  // the probe's own checks, before the port
    const std::unique_ptr<SessionRun> run = run_held("check_impedance", s.mix, opt, probe_mA);
    if (run->error) std::rethrow_exception(run->error);
    if (!run->check.refusal.empty()) tp::bad_input(run->check.refusal);
    py::list rows;
    for (const tp::host::ImpedanceRow& x : run->check.rows) {
      py::dict d;
      d["channel"] = x.channel;
      d["probe_mA"] = x.probe_mA;
      d["contact"] = x.contact;
      d["impedance_kohm"] = x.impedance_kohm;
      d["voltage_V"] = x.voltage_V;
      d["peak_mA"] = x.peak_mA;
      d["needed_V"] = x.needed_V;
      rows.append(d);
    }
    return rows;
  }

  // Starts a live session: frames come from set_currents / set_amplitudes until stop().
  void start_live(const PyStimulus& s, std::optional<double> duration_s) {
    tp::host::SessionOptions opt = session_options(true, duration_s);
    tp::check_mix(s.mix, tp::StimulusLimits{});
    claim("start_live");
    try {
      std::lock_guard<std::mutex> lock(m_);
      open_locked();
      // The frames' own check, at each call, by the session's rules (host/live.hpp) and
      // the host's limits; the session checks them again against the device's.
      live_check_.emplace(s.mix, tp::StimulusLimits{}, tp::device::Capabilities{});
      live_ = start(s.mix, opt, std::make_shared<tp::host::FrameQueue>());
      current_ = live_.get();
    } catch (...) {
      release();
      throw;
    }
  }

  bool set_currents(const std::vector<double>& currents_mA) {
    return push_frame(tp::host::LiveFrame::Kind::currents, currents_mA, "set_currents");
  }

  bool set_amplitudes(const std::vector<double>& amplitudes_mA) {
    return push_frame(tp::host::LiveFrame::Kind::amplitudes, amplitudes_mA, "set_amplitudes");
  }

  // Ends a live session (the end of its input): the output stops; returns its report, or
  // raises what ended it.  None when no live session runs.
  py::object stop() {
    if (!live_) return py::none();
    const std::unique_ptr<SessionRun> run = take_live();
    return finish(*run);
  }

  bool running() const { return live_ && !live_->done; }

  // Stops any output at once (a delivery on another thread, a live session) and closes
  // the port.
  void close() {
    {
      std::unique_lock<std::mutex> lock(m_);
      if (current_) current_->closed.request("closed (Stimulator.close())");
    }
    if (live_) {
      std::unique_ptr<SessionRun> run = std::move(live_);
      run->frames->close();
      {
        py::gil_scoped_release release;
        if (run->thread.joinable()) run->thread.join();
      }
      release();
    }
    {  // a delivery on another thread: wait until it has stopped and let go of the port
      py::gil_scoped_release release;
      std::unique_lock<std::mutex> lock(m_);
      idle_.wait(lock, [&] { return !busy_; });
      transport_.reset();
    }
  }

  // A device that measures (protocol 7): each channel's last impedance, kOhm, as the
  // session last read it (every 0.25 s while it runs, and at its end or a guard's stop):
  // None where the channel carried no current, inf where none flowed (no contact).  Empty
  // before any reading, and from a device that does not measure.
  py::list impedances() {
    std::vector<tp::device::ChannelMeasurement> m;
    {
      std::lock_guard<std::mutex> lock(measured_m_);
      m = measured_;
    }
    return impedance_list(m);
  }

 private:
  // The session's options as stimctl makes them (its --duration's check and message).
  tp::host::SessionOptions session_options(bool live, std::optional<double> duration_s) {
    tp::host::DeliveryRequest r = req_;
    r.live = live;
    r.duration_s = duration_s;
    tp::host::SessionOptions opt = tp::host::delivery_session(r);
    // A device that measures: its readings as the session reads them, for impedances().
    opt.measurements = [this](const std::vector<tp::device::ChannelMeasurement>& m) {
      std::lock_guard<std::mutex> lock(measured_m_);
      measured_ = m;
    };
    return opt;
  }

  void open_locked() {
    if (transport_) return;
    transport_ = tp::host::open_delivery(req_);
  }

  // One blocking operation holding the port (`what` names it when another holds it): the
  // session (or, with probe_mA, the impedance check) on its thread, waited for; the run.
  std::unique_ptr<SessionRun> run_held(const char* what, const tp::Mix& m,
                                       const tp::host::SessionOptions& opt,
                                       std::optional<double> probe_mA) {
    claim(what);
    std::unique_ptr<SessionRun> run;
    try {
      {
        std::lock_guard<std::mutex> lock(m_);
        open_locked();
        run = start(m, opt, nullptr, probe_mA);
        current_ = run.get();
      }
      wait(*run);
    } catch (...) {
      release();
      throw;
    }
    release();
    return run;
  }

  // Takes the port for one operation; bad input when another holds it.
  void claim(const char* what) {
    if (live_ && live_->done) {  // a live session that ended by itself: its end is news
      const std::unique_ptr<SessionRun> run = take_live();
      finish(*run);  // raises what ended it, if it failed
    }
    std::lock_guard<std::mutex> lock(m_);
    if (busy_)
      tp::bad_input(std::string(what) + ": " +
                    (live_ ? "a live session is running (stop() it first)"
                           : "a delivery is running on another thread"));
    busy_ = true;
  }
  void release() {
    std::lock_guard<std::mutex> lock(m_);
    busy_ = false;
    current_ = nullptr;
    idle_.notify_all();
  }

  // A session on its own thread: run_session, or with probe_mA the impedance check's probe
  // (its result in the run's `check`).
  std::unique_ptr<SessionRun> start(const tp::Mix& m, tp::host::SessionOptions opt,
                                    std::shared_ptr<tp::host::FrameQueue> frames = nullptr,
                                    std::optional<double> probe_mA = std::nullopt) {
    auto run = std::make_unique<SessionRun>();
    SessionRun* r = run.get();
    r->frames = std::move(frames);
    opt.frames = r->frames.get();
    opt.stop = r->closed.token().with_signals(&r->flag);
    tp::host::Transport* t = transport_.get();
    run->thread = std::thread([r, t, m, opt, probe_mA] {
      try {
        if (probe_mA)
          r->check = tp::host::check_impedance(*t, m, opt, *probe_mA);
        else
          r->report = tp::host::run_session(*t, m, opt);
      } catch (...) {
        r->error = std::current_exception();
      }
      std::lock_guard<std::mutex> lock(r->m);
      r->done = true;
      r->cv.notify_all();
    });
    return run;
  }

  // Checks Python's signals; one raised an exception: the run's output stops first (its
  // stop flag, then its end), then the exception goes on.
  void check_signals(SessionRun& r) {
    if (PyErr_CheckSignals() == 0) return;
    py::error_already_set e;  // KeyboardInterrupt, SystemExit, ...
    r.flag = SIGINT;
    {
      py::gil_scoped_release release;
      if (r.thread.joinable()) r.thread.join();
    }
    throw e;
  }

  // Waits for the session to end, the GIL released, Python's signals checked every 20 ms.
  void wait(SessionRun& r) {
    for (;;) {
      {
        py::gil_scoped_release release;
        std::unique_lock<std::mutex> lock(r.m);
        if (r.cv.wait_for(lock, std::chrono::milliseconds(20), [&] { return r.done; })) break;
      }
      check_signals(r);
    }
    py::gil_scoped_release release;
    if (r.thread.joinable()) r.thread.join();
  }

  py::dict finish(SessionRun& r) {
    if (r.error) std::rethrow_exception(r.error);
    if (!r.report.started)
      throw tp::Error(static_cast<tp::ExitCode>(r.report.exit_code ? r.report.exit_code : 1),
                      "stopped: " + r.report.end + " before the output started; nothing delivered");
    if (r.report.exit_code != 0 && r.report.exit_code < 128)
      throw tp::Error(static_cast<tp::ExitCode>(r.report.exit_code), "stopped: " + r.report.end);
    return report_dict(r.report);
  }

  // Ends the live session's input and waits for it (a signal's exception stops it first),
  // then lets go of its pipe and the port: the run, for its report.
  std::unique_ptr<SessionRun> take_live() {
    std::unique_ptr<SessionRun> run = std::move(live_);
    run->frames->close();
    try {
      wait(*run);
    } catch (...) {
      release();
      throw;
    }
    release();
    return run;
  }

  // A live session that has ended: raises what ended it (the output is stopped).
  void end_live(const char* what) {
    const std::unique_ptr<SessionRun> run = take_live();
    finish(*run);
    tp::failure(std::string(what) + ": the live session has ended: " + run->report.end);
  }

  void require_live(const char* what) {
    if (!live_) tp::bad_input(std::string(what) + ": no live session (start_live first)");
    if (live_->done) end_live(what);
  }

  // A frame: checked now (bad input at the call, nothing sent), then handed to the
  // session, which sends the last of the frames that arrived since its previous turn.
  // False (nothing sent) when the session has completed its duration meanwhile: a frame
  // racing the end is not an error, as in stimctl; any other end raises what ended it.
  bool push_frame(tp::host::LiveFrame::Kind kind, const std::vector<double>& values,
                  const char* what) {
    if (!live_) tp::bad_input(std::string(what) + ": no live session (start_live first)");
    {
      std::lock_guard<std::mutex> lock(live_->m);
      if (live_->done && completed(*live_)) return false;
    }
    require_live(what);
    tp::host::LiveFrame f;
    f.kind = kind;
    f.values_mA = values;
    f.where = what;
    for (std::size_t i = 0; i < values.size(); ++i)
      if (!std::isfinite(values[i]))
        tp::bad_input(std::string(what) + " item " + std::to_string(i + 1) +
                      ": not a finite number");
    live_check_->add(f);
    live_check_->take();
    live_->frames->push(std::move(f));
    return true;
  }

  static bool completed(const SessionRun& r) {
    return !r.error && r.report.end == "stimulus complete";
  }

  tp::host::DeliveryRequest req_;
  std::mutex measured_m_;  // measured_, written by a session's thread
  std::vector<tp::device::ChannelMeasurement> measured_;
  std::mutex m_;  // busy_, current_, transport_
  std::condition_variable idle_;
  bool busy_ = false;
  SessionRun* current_ = nullptr;
  std::unique_ptr<tp::host::Transport> transport_;
  std::unique_ptr<SessionRun> live_;
  std::optional<tp::host::LiveState> live_check_;
};

}  // namespace

namespace {

// BadInput and Failure, the programs' exit 2 and exit 1, from tp::Error and JSON errors.
void bind_errors(py::module_& m) {
  // Never destroyed: see to_python().
  static auto* bad_input_exc = new py::exception<tp::Error>(m, "BadInput", PyExc_ValueError);
  static auto* failure_exc = new py::exception<tp::Error>(m, "Failure", PyExc_RuntimeError);
  bad_input_exc->doc() = "Bad input: the message the programs print (they exit 2).";
  failure_exc->doc() = "A runtime failure: the message the programs print (they exit 1).";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const tp::Error& e) {
      if (e.code() == tp::ExitCode::bad_input)
        (*bad_input_exc)(e.what());
      else
        (*failure_exc)(e.what());
    } catch (const nlohmann::json::exception& e) {  // printable as tp::Error's are
      (*bad_input_exc)(tp::printable(e.what()).c_str());
    }
  });
}

// Document: a design document, its JSON and its parts.
void bind_document(py::module_& m) {
  py::class_<PyDocument>(m, "Document",
                         "A design document (tactile-primaries/1): array, model, receptors, "
                         "weights and whatever else the programs carry along.")
      .def_static("from_json", &PyDocument::from_json, py::arg("text"),
                  "Parses and checks a document's JSON text.")
      .def_static("load", &PyDocument::load, py::arg("path"), "Reads a document file.")
      .def_static("create", &make_document, py::arg("electrodes") = py::none(),
                  py::arg("pitch_mm") = py::none(), py::arg("grid") = py::none(),
                  py::arg("row_pitch_mm") = py::none(), py::arg("pad") = py::none(),
                  py::arg("model") = py::none(), py::arg("plane_z_mm") = py::none(),
                  py::arg("skin") = py::none(),
                  "A document as the programs' flags make it: --electrodes/--pitch, or --grid "
                  "CxR/--pitch/--row-pitch/--pad WxL; --model, --z, --skin.")
      .def("to_json", &PyDocument::to_json,
           "The document's JSON text, byte for byte as the programs print it.")
      .def("with_model", &with_model, py::arg("model") = py::none(),
           py::arg("plane_z_mm") = py::none(), py::arg("skin") = py::none(),
           "A copy under another conductor model (as --model, --z, --skin).")
      .def_property_readonly("array",
                             [](const PyDocument& d) { return to_python(d.json()["array"]); })
      .def_property_readonly("model",
                             [](const PyDocument& d) { return to_python(d.json()["model"]); })
      .def_property_readonly("receptors",
                             [](const PyDocument& d) { return to_python(d.json()["receptors"]); })
      .def_property(
          "weights",
          [](const PyDocument& d) -> py::object {
            if (!d.doc.weights) return py::none();
            // A read-only copy: an item assignment would change nothing, so it raises;
            // set the whole vector (doc.weights = ...) instead.
            py::array_t<double> a(static_cast<py::ssize_t>(d.doc.weights->size()),
                                  d.doc.weights->data());
            a.attr("flags").attr("writeable") = false;
            return std::move(a);
          },
          [](PyDocument& d, std::optional<std::vector<double>> w) {
            if (w) {
              for (std::size_t i = 0; i < w->size(); ++i)
                if (!std::isfinite((*w)[i]))
                  tp::bad_input("weights item " + std::to_string(i + 1) + ": not a finite number");
              for (std::size_t i = 0; i < w->size(); ++i)
                tp::ranges::check((*w)[i], tp::ranges::weight,
                                  "weights item " + std::to_string(i + 1));
              if (w->size() != d.doc.setup.array.size())
                tp::bad_input("weights: expected " + std::to_string(d.doc.setup.array.size()) +
                              " values (one per electrode), got " + std::to_string(w->size()));
            }
            d.doc.weights = w;
          })
      .def_property_readonly("max_current_mA",
                             [](const PyDocument& d) { return d.doc.max_current_mA; })
      .def(
          "to_dict", [](const PyDocument& d) { return to_python(d.json()); },
          "The whole document as Python objects.")
      .def("__getitem__",
           [](const PyDocument& d, const std::string& key) {
             const tp::Json j = d.json();
             if (!j.contains(key)) throw py::key_error(key);
             return to_python(j[key]);
           })
      .def("__contains__",
           [](const PyDocument& d, const std::string& key) { return d.json().contains(key); })
      .def("__repr__", [](const PyDocument& d) {
        std::string mode = d.doc.extra.contains("mode") && d.doc.extra["mode"].is_string()
                               ? ", mode " + d.doc.extra["mode"].get<std::string>()
                               : "";
        return "<tactile_primaries.Document: " + d.doc.setup.array.describe() + ", " +
               d.doc.setup.conductor.model + mode + (d.doc.weights ? ", weights" : "") + ">";
      });
}

// Stimulus: a checked stimulus or a mix.
void bind_stimulus(py::module_& m) {
  py::class_<PyStimulus>(m, "Stimulus",
                         "A checked stimulus (make-pulse's) or a mix of patterns (mix-stimuli's).")
      .def_static("from_json", &PyStimulus::from_json, py::arg("text"))
      .def_static("load", &PyStimulus::load, py::arg("path"))
      .def("to_json", &PyStimulus::to_json,
           "The stimulus's JSON text, byte for byte as make-pulse prints it.")
      .def("to_dict", [](const PyStimulus& s) { return to_python(s.json()); })
      .def_property_readonly("patterns", [](const PyStimulus& s) { return s.mix.patterns.size(); })
      .def_property_readonly(
          "channels", [](const PyStimulus& s) { return s.mix.patterns[0].currents_mA.size(); })
      .def_property_readonly("duration_s",
                             [](const PyStimulus& s) {
                               double d = 0;
                               for (const auto& p : s.mix.patterns) d = std::max(d, p.duration_s());
                               return d;
                             })
      .def("__repr__", [](const PyStimulus& s) {
        const tp::Stimulus& p = s.mix.patterns[0];
        return "<tactile_primaries.Stimulus: " + std::to_string(p.currents_mA.size()) +
               " channels, " +
               (s.mix.single() ? std::to_string(p.count) + " pulses at " +
                                     tp::number_text(p.shape.frequency_hz) + " Hz"
                               : std::to_string(s.mix.patterns.size()) + " patterns") +
               ">";
      });
}

// The programs' requests: af-field, optimize-weights, fiber-threshold, make-pulse.
void bind_programs(py::module_& m) {
  m.def("_af_points", &af_points, py::arg("doc"), py::arg("x_mm"), py::arg("y_mm"),
        py::arg("z_mm") = py::none(), py::arg("amplitude_mA") = py::none());
  m.def("_af_grid_time_s", &af_grid_time_s, py::arg("doc"), py::arg("x0"), py::arg("x1"),
        py::arg("dx"), py::arg("y0"), py::arg("y1"), py::arg("dy"));
  m.def("summarize", &summarize, py::arg("doc"), py::arg("amplitude_mA") = py::none(),
        "Each receptor's largest AF and where, and every mode's ratio (af-field --summary).");
  m.def("optimize_weights", &optimize_weights, py::arg("doc"), py::arg("mode") = py::none(),
        py::kw_only(), py::arg("at") = py::none(), py::arg("radius_mm") = py::none(),
        py::arg("spill") = py::none(), py::arg("max_current_mA") = py::none(),
        py::arg("min_target_af") = 0.0, py::arg("pattern_starts") = py::none(),
        py::arg("random_starts") = py::none(), py::arg("certify") = false,
        py::arg("bank") = false, py::arg("neighbourhood") = py::none(),
        py::arg("threads") = py::none(), py::arg("modes") = py::none(),
        py::arg("objective") = "af", py::arg("fibre_model") = py::none(),
        py::arg("geometry") = "straight", py::arg("stimulus") = py::none(),
        py::arg("width_us") = py::none(), py::arg("interphase_us") = py::none(),
        py::arg("balance_width_us") = py::none(), py::arg("monophasic") = false,
        py::arg("offsets") = py::none(), py::arg("tolerance") = py::none(),
        py::arg("max_evaluations") = py::none(), py::arg("timing") = false,
        py::arg("phases") = py::none(), py::arg("population") = py::none(),
        py::arg("seed") = py::none(), py::arg("max_charge_nC") = py::none(),
        "optimize-weights: the mode's minimax weights; at=[x] or [x, z]: a pixel; bank=True: "
        "every pad's pixels (or at=[[x, z], ...]'s); objective='threshold': then the weights "
        "by a fibre model's thresholds (fibre_model=, the pulse, max_evaluations=); "
        "objective='selectivity': the weights and the pulse's shape by a sampled population's "
        "recruitment (population=, seed=, max_charge_nC=, max_evaluations=).  Returns the "
        "document the program prints.");
  m.def("fiber_threshold", &fiber_threshold, py::arg("doc"), py::kw_only(),
        py::arg("model") = "mrg", py::arg("width_us") = py::none(),
        py::arg("interphase_us") = py::none(), py::arg("balance_width_us") = py::none(),
        py::arg("monophasic") = false, py::arg("offsets") = 8, py::arg("tolerance") = py::none(),
        py::arg("threads") = 0, py::arg("at") = py::none(), py::arg("stimulus") = py::none(),
        py::arg("conductor") = py::none(), py::arg("geometry") = "straight",
        py::arg("strength_duration") = false, py::arg("widths_us") = py::none(),
        py::arg("population") = py::none(), py::arg("seed") = py::none(),
        py::arg("phases") = py::none(),
        "fiber-threshold: each receptor's threshold (mA), where it fired and the ratios; the "
        "document the program prints, as a dict (with stimulus=, threshold_multiples too).  "
        "geometry='afferent': RA as an afferent (docs/fibres.md).  strength_duration=True "
        "[widths_us=]: the strength-duration table; population=N [seed=]: N afferents of each "
        "class, {'afferents': ..., 'recruitment': ...}; a table as its columns, {name: [values]} "
        "(the program's CSV: numbers as it prints them, an empty cell None).");
  m.def("make_pulse", &make_pulse, py::arg("doc"), py::arg("amplitude_mA") = py::none(),
        py::arg("frequency_hz") = 200.0, py::kw_only(), py::arg("width_us") = py::none(),
        py::arg("balance_width_us") = py::none(), py::arg("interphase_us") = py::none(),
        py::arg("duration_s") = py::none(), py::arg("count") = py::none(),
        py::arg("profile") = py::none(), py::arg("intensity") = py::none(),
        py::arg("phases") = py::none(),
        "make-pulse: a checked, charge-balanced stimulus of the document's weights.  The pulse: "
        "width_us (200) [balance_width_us, interphase_us], or phases=[(duration_us, level), "
        "...] (up to 16, level x the amplitude), or the document's pulse when none is given.");
}

// _Stimulator: the session a Python Stimulator drives.
void bind_stimulator(py::module_& m) {
  py::class_<Stimulator>(m, "_Stimulator")
      .def(py::init<const py::object&, int, int, std::optional<py::object>, std::string,
                    std::optional<py::object>, std::optional<double>, std::string,
                    std::optional<double>, bool>(),
           py::arg("port") = "emu", py::arg("baud") = 115200, py::arg("emu_channels") = 8,
           py::arg("record") = py::none(), py::arg("backend") = "auto",
           py::arg("emu_skin") = py::none(), py::arg("emu_compliance_V") = py::none(),
           py::arg("contact_loss") = "stop", py::arg("probe_mA") = py::none(),
           py::arg("hold_sensation") = false)
      .def("open", &Stimulator::open)
      .def("deliver", &Stimulator::deliver, py::arg("stimulus"), py::arg("duration_s") = py::none())
      .def("start_live", &Stimulator::start_live, py::arg("stimulus"),
           py::arg("duration_s") = py::none())
      .def("set_currents", &Stimulator::set_currents, py::arg("currents_mA"))
      .def("set_amplitudes", &Stimulator::set_amplitudes, py::arg("amplitudes_mA"))
      .def("stop", &Stimulator::stop)
      .def("impedances", &Stimulator::impedances)
      .def("check_impedance", &Stimulator::check_impedance, py::arg("stimulus"),
           py::arg("probe_mA") = tp::host::kDefaultProbe_mA)
      .def("close", &Stimulator::close)
      .def_property_readonly("running", &Stimulator::running);
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() =
      "tactile-primaries' library: documents, fields, weights, fibre thresholds, stimuli "
      "and the stimulator (docs/python.md).";
  m.attr("__version__") = TP_VERSION;

  bind_errors(m);
  bind_document(m);
  bind_stimulus(m);
  bind_programs(m);
  bind_stimulator(m);
}
