// The selectivity design (selectivity_design.hpp): its shape family, scoring, passes.

#include "opt/selectivity_design.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/error.hpp"
#include "core/number.hpp"
#include "opt/nelder_mead.hpp"

namespace tp::fibre {

bool better(const SelectivityScore& a, const SelectivityScore& b) {
  if (a.usable() != b.usable()) return a.usable();
  if (!a.usable()) return a.fires && !b.fires;
  if (a.half.index != b.half.index) return a.half.index > b.half.index;
  return a.margin > b.margin;
}

namespace {

// ---------------------------------------------------------------------------------------
// The shape family: [prepulse] main phase at +1 [gap] recovery phase, charge balanced.

struct ShapeParams {
  double width_us = 200;    // the main phase, at +1
  double gap_us = 0;        // between the main and the recovery phase
  double asymmetry = 1;     // the recovery phase's |level| (its length keeps the charge)
  double pre_level = 0;     // a prepulse's level (either sign; 0: none), just before the main
  double pre_us = 0;
};

// The grid each parameter is searched over (docs/fibres.md, "Designed for selectivity"):
// levels in quarters, so that a device sums them exactly in units of 1/4; lengths such that
// every recovery phase is a whole number of microseconds.
constexpr double kWidths_us[] = {50, 100, 200, 400};
constexpr double kAsymmetries[] = {1, 0.5, 0.25};
constexpr double kPreLevels[] = {-0.5, -0.25, 0.25, 0.5};
constexpr double kPreLengths_us[] = {200, 500};

std::vector<Phase> shape_of(const ShapeParams& s) {
  std::vector<Phase> ph;
  if (s.pre_level != 0 && s.pre_us > 0) ph.push_back({s.pre_us, s.pre_level});
  ph.push_back({s.width_us, 1.0});
  const double net = s.width_us + s.pre_level * s.pre_us;  // level x us
  if (net == 0) return ph;
  if (s.gap_us > 0) ph.push_back({s.gap_us, 0.0});
  const double level = net > 0 ? -s.asymmetry : s.asymmetry;
  ph.push_back({std::fabs(net) / s.asymmetry, level});
  return ph;
}

// The family's parameters of a start's phases (a shorthand's: width, gap, balance), or
// the default's where the phases are not of the family.
ShapeParams params_of(const std::vector<Phase>& phases) {
  ShapeParams s;
  if (!phases.empty() && phases.front().level == 1.0) {
    s.width_us = phases.front().duration_us;
    if (phases.size() == 3 && phases[1].level == 0.0) s.gap_us = phases[1].duration_us;
    if (phases.size() >= 2) s.asymmetry = std::fabs(phases.back().level);
  }
  if (!(s.asymmetry > 0) || !same_phases(shape_of(s), phases)) return ShapeParams{};
  return s;
}

// ---------------------------------------------------------------------------------------
// Scoring.

// The least threshold of any other class's afferent over I50, logarithmic (max_mA where
// none fires): how far half the target is from the first other afferent to fire.
double margin_of(const Population& p, const std::string& target, double i50_mA, double max_mA) {
  double least = max_mA;
  for (const Afferent& a : p.afferents)
    if (a.receptor != target && a.threshold_mA) least = std::min(least, *a.threshold_mA);
  return std::log(least / i50_mA);
}

class Scorer {
 public:
  Scorer(const Setup& setup, const std::string& target, const FibreModel& model,
         const ThresholdSettings& settings, const SelectivityOptions& o)
      : setup_(setup), target_(target), model_(model), settings_(settings), o_(o),
        classes_(o.classes.empty() ? default_afferent_classes() : o.classes) {}

  const std::vector<AfferentClass>& classes() const { return classes_; }

  PopulationOptions population(std::uint64_t seed, PopulationMemo* memo) const {
    PopulationOptions po;
    po.per_class = o_.per_class;
    po.seed = seed;
    po.threads = o_.threads;
    po.memo = memo;
    return po;
  }

  // The design on the population of `seed` (memo: that population's), and whether it can
  // be delivered at its I50 within the limits and the comfort bound.
  SelectivityScore score(const SelectivityDesign& d, std::uint64_t seed, PopulationMemo& memo,
                         double max_charge_nC) const {
    PulseSpec pulse;
    pulse.phases = d.phases;
    const Population p = sample_population(setup_, d.weights, model_, pulse, settings_, classes_,
                                           population(seed, &memo));
    SelectivityScore s;
    const auto h = selectivity_at_half(p, target_);
    if (!h) {
      s.refused = "fewer than half of " + target_ + " fire below " +
                  number_text(settings_.max_mA) + " mA";
      return s;
    }
    s.fires = true;
    s.half = *h;
    s.margin = margin_of(p, target_, h->i50_mA, settings_.max_mA);
    s.charge_nC = h->i50_mA * shape_sums(d.phases).max_run_charge_us();
    s.refused = refusal(d, h->i50_mA, s.charge_nC, max_charge_nC);
    return s;
  }

 private:
  // Why the design cannot be delivered at I50 (every limit a stimulus is checked against;
  // the comfort bound when it is set), or empty.
  std::string refusal(const SelectivityDesign& d, double i50_mA, double charge_nC,
                      double max_charge_nC) const {
    Stimulus s;
    for (double w : d.weights) s.currents_mA.push_back(w * i50_mA);
    s.shape.phases = d.phases;
    s.shape.frequency_hz = o_.frequency_hz;
    s.count = 1;
    s.electrode_area_mm2 = o_.electrode_area_mm2;
    s.max_current_mA = o_.limits.max_current_mA;
    s.amplitude_mA = i50_mA;
    try {
      check_stimulus(s, o_.limits);
    } catch (const Error& e) {
      return e.what();
    }
    if (max_charge_nC > 0 && charge_nC > max_charge_nC)
      return "charge per phase " + number_text(charge_nC) + " nC above the comfort bound " +
             number_text(max_charge_nC) + " nC";
    return "";
  }

  const Setup& setup_;
  std::string target_;
  const FibreModel& model_;
  ThresholdSettings settings_;
  const SelectivityOptions& o_;
  std::vector<AfferentClass> classes_;
};

// ---------------------------------------------------------------------------------------
// The search.

struct Candidate {
  SelectivityDesign design;
  ShapeParams shape;
  SelectivityScore score;
};

// The longest pulse of the family (the work bound is checked for it).
std::vector<Phase> longest_shape() {
  ShapeParams s;
  s.width_us = kWidths_us[3];
  s.asymmetry = kAsymmetries[2];
  s.pre_level = kPreLevels[3];
  s.pre_us = kPreLengths_us[1];
  return shape_of(s);
}

class Search {
 public:
  Search(const Scorer& scorer, const SelectivityOptions& o, SelectivityResult& out)
      : scorer_(scorer), o_(o), out_(out) {}

  // Scores a design (once: a design seen before keeps its score); the best so far kept.
  const SelectivityScore& consider(const SelectivityDesign& d, const ShapeParams& shape,
                                   const std::string& stage) {
    for (const Candidate& c : seen_)
      if (c.design.weights == d.weights && same_phases(c.design.phases, d.phases)) return c.score;
    Candidate c{d, shape, scorer_.score(d, o_.seed, memo_, out_.max_charge_nC)};
    ++out_.evaluations;
    if (o_.progress) o_.progress(out_.evaluations, stage);
    seen_.push_back(std::move(c));
    if (best_ < 0 || better(seen_.back().score, seen_[static_cast<std::size_t>(best_)].score))
      best_ = static_cast<long>(seen_.size()) - 1;
    return seen_.back().score;
  }
  bool spent() const { return out_.evaluations >= o_.max_evaluations; }
  const Candidate& best() const { return seen_[static_cast<std::size_t>(best_)]; }
  const std::vector<Candidate>& seen() const { return seen_; }
  PopulationMemo& memo() { return memo_; }

  // One parameter of the best's shape at a time over its grid; true when the best moved.
  bool shape_pass() {
    const long before = best_;
    polarity();
    vary([](ShapeParams& s, double v) { s.width_us = v; }, kWidths_us);
    vary([](ShapeParams& s, double v) { s.asymmetry = v; }, kAsymmetries);
    prepulse();
    return best_ != before;
  }

  // Nelder-Mead over the zero-sum weights at the best's shape, up to 3 x the electrodes'
  // number of populations; true when the best moved.
  bool weights_pass() {
    const long before = best_;
    const Candidate start = best();
    const std::vector<double>& w = start.design.weights;
    if (w.size() < 2) return false;
    const std::vector<double> z0(w.begin(), w.end() - 1);
    const std::size_t cap = std::min(o_.max_evaluations, out_.evaluations + 3 * w.size());
    nelder_mead(
        z0, key(start.score), 0.25, cap,
        [&](const std::vector<double>& z) {
          const std::vector<double> wz = zero_sum_weights(z);
          if (wz.empty() || spent()) return std::numeric_limits<double>::infinity();
          return key(consider({wz, start.design.phases}, start.shape, "weights"));
        },
        [&] { return out_.evaluations; });
    return best_ != before;
  }

 private:
  // Nelder-Mead's value (lower is better), in better()'s order: the index, then the margin
  // (within half the smallest step of the index), then the designs that are not usable.
  static double key(const SelectivityScore& s) {
    if (!s.usable()) return s.fires ? 10.0 : 20.0;
    return -(s.half.index + 1e-3 * std::tanh(s.margin));
  }

  void try_shape(const ShapeParams& shape) {
    if (spent()) return;
    consider({best().design.weights, shape_of(shape)}, shape, "shape");
  }

  void polarity() {
    if (spent()) return;
    Candidate c = best();
    for (double& w : c.design.weights) w = -w;
    consider(c.design, c.shape, "shape");
  }

  template <class Set, std::size_t N>
  void vary(Set set, const double (&grid)[N]) {
    const ShapeParams from = best().shape;
    for (double v : grid) {
      ShapeParams s = from;
      set(s, v);
      try_shape(s);
    }
  }

  void prepulse() {
    const ShapeParams from = best().shape;
    ShapeParams none = from;
    none.pre_level = 0;
    none.pre_us = 0;
    try_shape(none);
    for (double level : kPreLevels)
      for (double length : kPreLengths_us) {
        ShapeParams s = from;
        s.pre_level = level;
        s.pre_us = length;
        try_shape(s);
      }
  }

  const Scorer& scorer_;
  const SelectivityOptions& o_;
  SelectivityResult& out_;
  PopulationMemo memo_;
  std::vector<Candidate> seen_;
  long best_ = -1;
};

// The front: usable designs in ascending charge, each better than every one of less charge.
std::vector<FrontPoint> front_of(const std::vector<Candidate>& seen) {
  std::vector<const Candidate*> usable;
  for (const Candidate& c : seen)
    if (c.score.usable()) usable.push_back(&c);
  std::stable_sort(usable.begin(), usable.end(), [](const Candidate* a, const Candidate* b) {
    if (a->score.charge_nC != b->score.charge_nC) return a->score.charge_nC < b->score.charge_nC;
    return better(a->score, b->score);
  });
  std::vector<FrontPoint> front;
  const Candidate* top = nullptr;
  for (const Candidate* c : usable) {
    if (top && !better(c->score, top->score)) continue;
    top = c;
    front.push_back({c->score.charge_nC, c->score.half.index, c->score.half.i50_mA,
                     c->design.phases});
  }
  return front;
}

void check_options(const Setup& setup, const std::string& target, const FibreModel& model,
                   const ThresholdSettings& settings, const SelectivityOptions& o,
                   const Scorer& scorer) {
  if (!(o.per_class >= 1 && o.per_class <= 1000))
    bad_input("--population: " + std::to_string(o.per_class) + " outside [1, 1000]");
  if (!(o.max_evaluations >= 4 && o.max_evaluations <= 1000))
    bad_input("--max-evaluations: " + std::to_string(o.max_evaluations) + " outside [4, 1000]");
  if (!(o.max_charge_nC >= 0 && o.max_charge_nC <= 1e5))
    bad_input("--max-charge: " + number_text(o.max_charge_nC) + " nC outside [0, 100000] nC");
  bool known = false;
  for (const AfferentClass& c : scorer.classes()) known = known || c.receptor == target;
  if (!known) bad_input("--mode: " + target + " is not a class of afferents (RA, SAI, PC)");
  // The whole design's work, before any of it: every population scored at the family's
  // longest pulse, the held-out check's included.
  PulseSpec longest;
  longest.phases = longest_shape();
  const double one = population_work(setup, model, longest, settings, scorer.classes(),
                                     scorer.population(o.seed, nullptr));
  check_threshold_work(one * static_cast<double>(o.max_evaluations + 4), kMaxSearchWork,
                       "--objective selectivity (" + std::to_string(o.max_evaluations) +
                           " populations of " + std::to_string(o.per_class) + " a class)",
                       "fewer --max-evaluations or --population, a larger --tolerance");
}

// The held-out population's score of each design (each distinct design once).
void hold_out(const Scorer& scorer, const SelectivityOptions& o, SelectivityResult& r) {
  PopulationMemo memo;
  std::size_t checked = 0;
  std::vector<ScoredDesign*> all{&r.best};
  for (ScoredDesign& s : r.starts) all.push_back(&s);
  for (std::size_t k = 0; k < all.size(); ++k) {
    bool done = false;
    for (std::size_t q = 0; q < k && !done; ++q)
      if (all[q]->design.weights == all[k]->design.weights &&
          same_phases(all[q]->design.phases, all[k]->design.phases)) {
        all[k]->held_out = all[q]->held_out;
        done = true;
      }
    if (done) continue;
    all[k]->held_out = scorer.score(all[k]->design, o.held_out_seed, memo, r.max_charge_nC);
    if (o.progress) o.progress(r.evaluations + ++checked, "held-out check");
  }
}

}  // namespace

void check_selectivity(const Setup& setup, const std::string& target, const FibreModel& model,
                       const ThresholdSettings& settings, const SelectivityOptions& o) {
  check_options(setup, target, model, settings, o, Scorer(setup, target, model, settings, o));
}

SelectivityResult design_for_selectivity(const Setup& setup, const std::string& target,
                                         const std::vector<ScoredDesign>& starts,
                                         const FibreModel& model, const ThresholdSettings& settings,
                                         const SelectivityOptions& o) {
  if (starts.empty()) bad_input("selectivity design: no start");
  const Scorer scorer(setup, target, model, settings, o);
  check_options(setup, target, model, settings, o, scorer);
  SelectivityResult r;
  r.max_charge_nC = o.max_charge_nC;
  Search search(scorer, o, r);
  // 1. The starts, the first (the AF optimum) setting the comfort bound when none is given.
  for (std::size_t k = 0; k < starts.size(); ++k) {
    ScoredDesign s = starts[k];
    s.score = search.consider(s.design, params_of(s.design.phases), "starts");
    if (k == 0 && r.max_charge_nC == 0 && s.score.fires) r.max_charge_nC = 2 * s.score.charge_nC;
    r.starts.push_back(s);
  }
  // 2. Turns of a shape pass and a weights pass, until neither moves the best.
  while (!search.spent()) {
    ++r.turns;
    const bool shape = search.shape_pass();
    const bool weights = !search.spent() && search.weights_pass();
    if (!shape && !weights) break;
  }
  const Candidate& best = search.best();
  r.improved = true;
  for (const ScoredDesign& s : r.starts)
    if (s.design.weights == best.design.weights && same_phases(s.design.phases, best.design.phases))
      r.improved = false;
  r.best = {"designed", best.design, best.score, {}};
  r.front = front_of(search.seen());
  // 3. The held-out check.
  hold_out(scorer, o, r);
  return r;
}

std::string selectivity_summary(const SelectivityResult& r, const std::string& target) {
  auto index = [](const SelectivityScore& s) {
    return s.fires ? number_text(s.half.index) : std::string("none");
  };
  std::string out = target + " selectivity " + index(r.best.score);
  if (r.best.score.fires) out += " at I50 " + number_text(r.best.score.half.i50_mA) + " mA";
  out += " (" + std::string(r.starts.empty() ? "" : "AF optimum: " + index(r.starts[0].score)) +
         "; held out: " + index(r.best.held_out) + ")";
  return out;
}

}  // namespace tp::fibre
