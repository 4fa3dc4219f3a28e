#include "fibre/population.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <exception>
#include <mutex>
#include <thread>

#include "core/error.hpp"
#include "core/splitmix.hpp"
#include "core/number.hpp"
#include "model/conductor.hpp"

namespace tp::fibre {

std::vector<AfferentClass> default_afferent_classes() {
  return {
      // Johansson & Vallbo 1979 (densities); Kajimoto et al., Table 1 (diameters, depths).
      {"RA", 140.0, 3.0, 5.0, 0.7, 0.7},
      {"SAI", 70.0, 7.0, 12.0, 0.9, 0.9},
      // PC: Table 1 "2.0 ~"; the bottom, 3.0 mm, is our assumption (docs/fibres.md).
      {"PC", 25.0, 5.0, 13.0, 2.0, 3.0},
  };
}

namespace {
// Uniform in [lo, hi] from the project's portable stream (core/splitmix.hpp).
double uniform(SplitMix64& rng, double lo, double hi) {
  return lo + (hi - lo) * rng.unit();
}

// One fibre of the population: its receptor and settings.
struct Job {
  Receptor receptor;
  ThresholdSettings settings;
};

// Each fibre's search on its own thread's turn; the results by index into p.afferents, so
// the output does not depend on the threads.  The failure of the lowest index is rethrown
// once every thread has joined.
void run_jobs(const Setup& setup, const Conductor& conductor, const std::vector<double>& weights,
              const FibreModel& model, const Waveform& waveform, const std::vector<Job>& jobs,
              unsigned threads, const PopulationOptions& o, Population& p) {
  std::atomic<std::size_t> next{0};
  std::mutex m;
  std::exception_ptr error;
  std::size_t error_index = jobs.size();
  std::size_t done = 0;  // searches ended, for o.progress (under m)
  // With a memo: how far each class's thresholds moved from the memo's (log of new over old)
  // in the searches ended so far (under m).  A search starts from its memo's threshold
  // moved by its class's median (else every class's): a closer guess, fewer probes; the
  // answer does not depend on the guess (search.hpp).
  std::vector<std::vector<double>> moved(jobs.size());  // by the first job of the class
  std::vector<double> all_moved;
  std::vector<std::size_t> class_of(jobs.size());
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    class_of[i] = i;
    for (std::size_t q = 0; q < i; ++q)
      if (jobs[q].receptor.name == jobs[i].receptor.name) {
        class_of[i] = class_of[q];
        break;
      }
  }
  auto median = [](std::vector<double> v) {
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
  };
  auto worker = [&] {
    for (;;) {
      const std::size_t i = next.fetch_add(1);
      if (i >= jobs.size()) return;
      try {
        PotentialCache local;
        PotentialCache* cache = o.memo ? &o.memo->caches[i] : &local;
        ThresholdSettings settings = jobs[i].settings;
        const double old_mA = o.memo ? o.memo->start_mA[i] : 0.0;
        if (old_mA > 0) {
          double shift = 0.0;
          {
            std::lock_guard<std::mutex> lock(m);
            const std::vector<double>& mine = moved[class_of[i]];
            if (!mine.empty())
              shift = median(mine);
            else if (!all_moved.empty())
              shift = median(all_moved);
          }
          settings.start_mA = {old_mA * std::exp(shift)};
        }
        const ReceptorThreshold t = receptor_threshold(
            model, setup, conductor, weights, jobs[i].receptor, waveform, settings, cache);
        if (o.memo) o.memo->start_mA[i] = t.threshold_mA.value_or(0.0);
        if (old_mA > 0 && t.threshold_mA) {
          std::lock_guard<std::mutex> lock(m);
          const double d = std::log(*t.threshold_mA / old_mA);
          moved[class_of[i]].push_back(d);
          all_moved.push_back(d);
        }
        p.afferents[i].threshold_mA = t.threshold_mA;
        p.afferents[i].at_cut_end = t.threshold_mA && t.at_cut_end;
        if (o.progress) {
          std::lock_guard<std::mutex> lock(m);
          o.progress(++done, jobs.size());
        }
      } catch (...) {
        std::lock_guard<std::mutex> lock(m);
        if (i < error_index) {
          error_index = i;
          error = std::current_exception();
        }
        return;
      }
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}
}  // namespace

namespace {
// The afferents sampled, each one's search, and their estimated work (checked, bad input
// before any work).
struct Plan {
  Population p;
  std::vector<Job> jobs;
  double work = 0;
};

Plan plan_population(const Setup& setup, const Conductor& conductor_ref, const FibreModel& model,
                     const PulseSpec& pulse, const ThresholdSettings& settings,
                     const std::vector<AfferentClass>& classes, const PopulationOptions& o) {
  const Conductor* conductor = &conductor_ref;
  if (!(o.per_class >= 1 && o.per_class <= static_cast<std::size_t>(kMaxPopulation)))
    bad_input("--population: " + std::to_string(o.per_class) + " outside [1, " +
              std::to_string(kMaxPopulation) + "]");
  const double margin = setup.lateral_margin_mm;
  double x0 = setup.array.x_min_mm() - margin, x1 = setup.array.x_max_mm() + margin;
  const bool two_d = setup.array.two_d();
  double z0 = two_d ? setup.array.z_min_mm() - margin : 0.0;
  double z1 = two_d ? setup.array.z_max_mm() + margin : 0.0;
  if (o.region_mm) {
    const std::array<double, 4>& g = *o.region_mm;
    if (!two_d) bad_input("--population: a region applies to a 2-D array only");
    if (!(std::isfinite(g[0]) && std::isfinite(g[1]) && std::isfinite(g[2]) &&
          std::isfinite(g[3]) && g[0] < g[1] && g[2] < g[3]))
      bad_input("--population: an empty region");
    x0 = g[0], x1 = g[1], z0 = g[2], z1 = g[3];
  }
  Plan plan;
  Population& p = plan.p;
  p.two_d = two_d;
  // The placed area: a 1-D array's extent and margin along x by the electrodes' length
  // across; a 2-D array's pads and margin in x and z.
  p.area_cm2 = (x1 - x0) * (two_d ? z1 - z0 : setup.array.length_mm) / 100.0;

  // Every fibre's receptor and settings, checked (and its work counted) before any work.
  std::vector<Job>& jobs = plan.jobs;
  double& work = plan.work;
  SplitMix64 rng{o.seed};
  const Waveform waveform = waveform_of(pulse, settings.delay_ms);
  for (const AfferentClass& c : classes) {
    const Receptor* base = nullptr;
    for (const Receptor& r : setup.receptors)
      if (r.name == c.receptor) base = &r;
    if (!base) bad_input("--population: no receptor " + c.receptor + " in the document");
    if (!(c.diameter_min_um > 0 && c.diameter_min_um <= c.diameter_max_um && c.depth_min_mm > 0 &&
          c.depth_min_mm <= c.depth_max_mm))
      bad_input("--population: class " + c.receptor + ": an empty or negative range");
    p.classes.push_back(c.receptor);
    p.expected.push_back(c.density_per_cm2 * p.area_cm2);
    const bool vertical = base->fibre.orientation == Orientation::vertical;
    for (std::size_t k = 0; k < o.per_class; ++k) {
      Afferent a;
      a.receptor = c.receptor;
      a.vertical = vertical;
      a.diameter_um = uniform(rng, c.diameter_min_um, c.diameter_max_um);
      a.depth_mm = uniform(rng, c.depth_min_mm, c.depth_max_mm);
      const double place = uniform(rng, 0.0, 1.0);
      Job j{*base, settings};
      j.receptor.fibre.diameter_um = a.diameter_um;
      j.receptor.depth_min_mm = a.depth_mm;
      if (vertical) {
        if (!(a.depth_mm < base->depth_max_mm))
          bad_input("--population: class " + c.receptor + ": a top at " +
                    number_beside(a.depth_mm, base->depth_max_mm) +
                    " mm, not above the fibre's bottom (" + number_text(base->depth_max_mm) +
                    " mm)");
        a.x_mm = x0 + (x1 - x0) * place;
        j.settings.fixed_x_mm = a.x_mm;
        if (settings.geometry ==
            Geometry::afferent) {  // a draw only then: straight keeps its bytes
          a.stem = uniform(rng, 0.0, 1.0) < 0.5 ? -1 : 1;
          j.settings.fixed_direction = a.stem;
        }
      } else {
        j.receptor.depth_max_mm = a.depth_mm;
        a.offset_mm = model.internode_um(a.diameter_um) * 1e-3 * place;
        j.settings.fixed_offset_mm = a.offset_mm;
      }
      if (two_d) {  // a draw only then: a 1-D array's samples keep their bytes
        a.z_mm = z0 + (z1 - z0) * uniform(rng, 0.0, 1.0);
        // Vertical: the fibre at (x, z); horizontal: along x at z (its x is not used).
        j.settings.through_mm = std::array<double, 2>{vertical ? a.x_mm : 0.5 * (x0 + x1), a.z_mm};
      }
      j.settings.threads = 1;  // the fibres run in parallel instead
      check_model_depth(setup, vertical ? j.receptor.depth_max_mm : a.depth_mm,
                        "--population: class " + c.receptor + "'s depth");
      work += threshold_work(model, setup, *conductor, j.receptor, waveform, j.settings);
      p.afferents.push_back(a);
      jobs.push_back(std::move(j));
    }
  }
  return plan;
}
}  // namespace

double population_work(const Setup& setup, const FibreModel& model, const PulseSpec& pulse,
                       const ThresholdSettings& settings,
                       const std::vector<AfferentClass>& classes, const PopulationOptions& o) {
  const auto conductor = make_conductor(setup.conductor, setup.array);
  return plan_population(setup, *conductor, model, pulse, settings, classes, o).work;
}

Population sample_population(const Setup& setup, const std::vector<double>& weights,
                             const FibreModel& model, const PulseSpec& pulse,
                             const ThresholdSettings& settings,
                             const std::vector<AfferentClass>& classes,
                             const PopulationOptions& o) {
  const auto conductor = make_conductor(setup.conductor, setup.array);
  Plan plan = plan_population(setup, *conductor, model, pulse, settings, classes, o);
  const std::vector<Job>& jobs = plan.jobs;
  Population& p = plan.p;
  check_threshold_work(plan.work, kMaxThresholdWork, "--population",
                       "fewer afferents, a larger --tolerance, a shorter pulse");

  if (o.memo && o.memo->caches.size() != jobs.size()) {
    o.memo->caches.assign(jobs.size(), PotentialCache{});
    o.memo->start_mA.assign(jobs.size(), 0.0);
  }
  const unsigned threads = std::min<unsigned>(
      settings.threads ? settings.threads : std::max(1u, std::thread::hardware_concurrency()),
      static_cast<unsigned>(jobs.size()));
  run_jobs(setup, *conductor, weights, model, waveform_of(pulse, settings.delay_ms), jobs, threads,
           o, p);
  return std::move(p);
}

std::optional<HalfSelectivity> selectivity_at_half(const Population& p,
                                                   const std::string& target) {
  const auto t_it = std::find(p.classes.begin(), p.classes.end(), target);
  if (t_it == p.classes.end()) return std::nullopt;
  const auto t = static_cast<std::size_t>(t_it - p.classes.begin());
  const std::size_t nc = p.classes.size();
  std::vector<std::vector<double>> th(nc);
  std::vector<std::size_t> total(nc, 0);
  for (const Afferent& a : p.afferents) {
    const auto k = static_cast<std::size_t>(
        std::find(p.classes.begin(), p.classes.end(), a.receptor) - p.classes.begin());
    ++total[k];
    if (a.threshold_mA) th[k].push_back(*a.threshold_mA);
  }
  std::sort(th[t].begin(), th[t].end());
  const std::size_t half = (total[t] + 1) / 2;  // at least half of the class
  if (total[t] == 0 || th[t].size() < half) return std::nullopt;
  HalfSelectivity h;
  h.i50_mA = th[t][half - 1];
  double worst = 0;
  for (std::size_t k = 0; k < nc; ++k) {
    const auto n = std::count_if(th[k].begin(), th[k].end(), [&](double v) { return v <= h.i50_mA; });
    h.fraction.push_back(total[k] ? static_cast<double>(n) / static_cast<double>(total[k]) : 0.0);
    if (k != t && (h.worst.empty() || h.fraction[k] > worst)) {
      worst = h.fraction[k];
      h.worst = p.classes[k];
    }
  }
  h.index = 1.0 - 2.0 * worst;
  return h;
}

std::string recruitment_csv(const Population& p) {
  const std::size_t nc = p.classes.size();
  std::vector<std::vector<double>> th(nc);
  for (const Afferent& a : p.afferents) {
    const auto it = std::find(p.classes.begin(), p.classes.end(), a.receptor);
    if (a.threshold_mA)
      th[static_cast<std::size_t>(it - p.classes.begin())].push_back(*a.threshold_mA);
  }
  std::vector<std::size_t> total(nc, 0);
  for (const Afferent& a : p.afferents)
    ++total[static_cast<std::size_t>(std::find(p.classes.begin(), p.classes.end(), a.receptor) -
                                     p.classes.begin())];
  std::vector<double> currents{0.0};
  for (auto& t : th) {
    std::sort(t.begin(), t.end());
    currents.insert(currents.end(), t.begin(), t.end());
  }
  std::sort(currents.begin(), currents.end());
  currents.erase(std::unique(currents.begin(), currents.end()), currents.end());
  std::string out = "current_mA";
  for (const std::string& c : p.classes) out += ",recruited_" + c;
  for (const std::string& c : p.classes) out += ",si_" + c;
  out += "\n";
  for (double i : currents) {
    std::vector<double> f(nc);
    for (std::size_t k = 0; k < nc; ++k) {
      const auto n = std::upper_bound(th[k].begin(), th[k].end(), i) - th[k].begin();
      f[k] = total[k] ? static_cast<double>(n) / static_cast<double>(total[k]) : 0.0;
    }
    out += number_text(i);
    for (double v : f) out += "," + number_text(v);
    for (std::size_t k = 0; k < nc; ++k) {
      double others = 0;
      for (std::size_t q = 0; q < nc; ++q)
        if (q != k) others += f[q];
      const double si = nc > 1 ? f[k] - others / static_cast<double>(nc - 1) : f[k];
      out += "," + number_text(si);
    }
    out += "\n";
  }
  return out;
}

std::string population_csv(const Population& p) {
  // Under a 2-D array a column z_mm; afferents (fibres with a stem) a last column, the
  // stem's side.
  // A last column at_cut_end (0 or 1) where any fired first at a cut end of its fibre.
  bool stems = false, cuts = false;
  for (const Afferent& a : p.afferents) {
    stems = stems || a.stem != 0;
    cuts = cuts || a.at_cut_end;
  }
  std::string out = "class,x_mm,offset_mm,depth_mm,diameter_um,threshold_mA";
  out += p.two_d ? ",z_mm" : "";
  out += stems ? ",stem" : "";
  out += cuts ? ",at_cut_end\n" : "\n";
  for (const Afferent& a : p.afferents) {
    const bool vertical = a.vertical;
    out += a.receptor + ",";
    out += vertical ? number_text(a.x_mm) : "";
    out += ",";
    out += vertical ? "" : number_text(a.offset_mm);
    out += "," + number_text(a.depth_mm) + "," + number_text(a.diameter_um) + ",";
    if (a.threshold_mA) out += number_text(*a.threshold_mA);
    if (p.two_d) out += "," + number_text(a.z_mm);
    if (stems) out += a.stem < 0 ? ",-x" : a.stem > 0 ? ",+x" : ",";
    if (cuts) out += a.at_cut_end ? ",1" : ",0";
    out += "\n";
  }
  return out;
}

}  // namespace tp::fibre
