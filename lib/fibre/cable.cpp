// Backward-Euler cable integration with a block-tridiagonal (Thomas) solve per step.

#include "fibre/cable.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"

namespace tp::fibre {

double Waveform::end_ms() const {
  double t = delay_ms;
  for (const Phase& p : phases) t += p.duration_ms;
  return t;
}

double Waveform::mean_level(double t0, double t1) const {
  double t = delay_ms, acc = 0.0;
  for (const Phase& p : phases) {
    const double a = std::max(t0, t), b = std::min(t1, t + p.duration_ms);
    if (b > a) acc += p.level * (b - a);
    t += p.duration_ms;
  }
  return acc / (t1 - t0);
}

CableSimulator::CableSimulator(const FibreModel& model, Axon axon)
    : kin_(model.kinetics()),
      axon_(std::move(axon)),
      v_init_(model.initial_mV()),
      n_(axon_.compartments.size()),
      gates_(kin_.gate_count()) {
  if (n_ < 2 || axon_.nodes.empty()) failure("fibre: an axon needs at least two compartments");
  is_node_.assign(n_, 0);
  for (std::size_t k : axon_.nodes) is_node_[k] = 1;
  gi_link_.assign(n_, 0.0);
  gp_link_.assign(n_, 0.0);
  for (std::size_t k = 0; k + 1 < n_; ++k) {
    const Compartment& a = axon_.compartments[k];
    const Compartment& b = axon_.compartments[k + 1];
    gi_link_[k] = 1.0 / (a.ri_half_kohm + b.ri_half_kohm);
    if (axon_.double_cable) gp_link_[k] = 1.0 / (a.rp_half_kohm + b.rp_half_kohm);
  }
  vi_.assign(n_, 0.0);
  vp_.assign(n_, 0.0);
  gate_.assign(n_ * gates_, 0.0);
  for (auto* v : {&inv11_, &inv12_, &inv22_, &y1_, &y2_}) v->assign(n_, 0.0);
  final_node_mV_.assign(axon_.nodes.size(), 0.0);
  peak_node_mV_.assign(axon_.nodes.size(), 0.0);
  cross_ms_.assign(axon_.nodes.size(), -1.0);
}

void CableSimulator::reset() {
  std::fill(vp_.begin(), vp_.end(), 0.0);
  std::fill(vi_.begin(), vi_.end(), v_init_);
  for (std::size_t k = 0; k < n_; ++k)
    if (is_node_[k]) kin_.steady_state(v_init_, &gate_[k * gates_]);
}

// One step: the linear network at t + dt with the ionic conductance of the gates at t.
void CableSimulator::step(double dt, double s_old, double s_new, const double* ve) {
  const std::vector<Compartment>& cs = axon_.compartments;
  if (axon_.double_cable) {
    // Unknowns per compartment: intracellular u and periaxonal w.  Rows:
    //   a (u - w) + sum gi (u - u_j)                  =  b
    //  -a (u - w) + e w + sum gp (w - w_j)            = -b + f
    // a = C/dt + g_ion, b = a vm - I_ion, e = C_sheath/dt + G_sheath,
    // f = C_sheath/dt (vp - ve_old) + e ve_new.  Forward elimination, then back substitution.
    double pi = 0.0, pp = 0.0;  // link conductances to the previous compartment
    for (std::size_t k = 0; k < n_; ++k) {
      const Compartment& c = cs[k];
      const double vm = vi_[k] - vp_[k];
      double g, i;
      if (is_node_[k]) {
        i = kin_.current(vm, &gate_[k * gates_], &g) * c.area_cm2 * 1e3;  // uA
        g *= c.area_cm2 * 1e3;                                            // mS
      } else {
        g = c.g_pas_mS;
        i = g * (vm - c.e_pas_mV);
      }
      const double a = c.c_uF / dt + g;
      const double b = a * vm - i;
      const double cs_dt = c.c_sheath_uF / dt;
      const double e = cs_dt + c.g_sheath_mS;
      const double f = cs_dt * (vp_[k] - s_old * ve[k]) + e * s_new * ve[k];
      const double ni = gi_link_[k], np = gp_link_[k];
      double d11 = a + pi + ni, d12 = -a, d22 = a + e + pp + np;
      double r1 = b, r2 = f - b;
      if (k > 0) {  // subtract L M^-1 L and L M^-1 y of the previous row (L = -diag(pi, pp))
        d11 -= pi * pi * inv11_[k - 1];
        d12 -= pi * pp * inv12_[k - 1];
        d22 -= pp * pp * inv22_[k - 1];
        r1 += pi * (inv11_[k - 1] * y1_[k - 1] + inv12_[k - 1] * y2_[k - 1]);
        r2 += pp * (inv12_[k - 1] * y1_[k - 1] + inv22_[k - 1] * y2_[k - 1]);
      }
      const double det = d11 * d22 - d12 * d12;
      inv11_[k] = d22 / det;
      inv12_[k] = -d12 / det;
      inv22_[k] = d11 / det;
      y1_[k] = r1;
      y2_[k] = r2;
      pi = ni;
      pp = np;
    }
    double u_next = 0.0, w_next = 0.0;
    for (std::size_t k = n_; k-- > 0;) {
      double r1 = y1_[k], r2 = y2_[k];
      if (k + 1 < n_) {
        r1 += gi_link_[k] * u_next;
        r2 += gp_link_[k] * w_next;
      }
      u_next = inv11_[k] * r1 + inv12_[k] * r2;
      w_next = inv12_[k] * r1 + inv22_[k] * r2;
      vi_[k] = u_next;
      vp_[k] = w_next;
    }
  } else {
    // Single cable: the membrane faces ve directly (vp = ve).  Rows:
    //   a (u - ve_new) + sum gi (u - u_j) = b.
    double pi = 0.0;
    for (std::size_t k = 0; k < n_; ++k) {
      const Compartment& c = cs[k];
      const double vm = vi_[k] - vp_[k];
      double g, i;
      if (is_node_[k]) {
        i = kin_.current(vm, &gate_[k * gates_], &g) * c.area_cm2 * 1e3;
        g *= c.area_cm2 * 1e3;
      } else {
        g = c.g_pas_mS;
        i = g * (vm - c.e_pas_mV);
      }
      const double a = c.c_uF / dt + g;
      const double ni = gi_link_[k];
      double d = a + pi + ni;
      double r = a * vm - i + a * s_new * ve[k];
      if (k > 0) {
        d -= pi * pi * inv11_[k - 1];
        r += pi * inv11_[k - 1] * y1_[k - 1];
      }
      inv11_[k] = 1.0 / d;
      y1_[k] = r;
      pi = ni;
    }
    double u_next = 0.0;
    for (std::size_t k = n_; k-- > 0;) {
      double r = y1_[k];
      if (k + 1 < n_) r += gi_link_[k] * u_next;
      u_next = inv11_[k] * r;
      vi_[k] = u_next;
      vp_[k] = s_new * ve[k];
    }
  }
  for (std::size_t k = 0; k < n_; ++k)
    if (is_node_[k]) kin_.advance(vi_[k] - vp_[k], dt, &gate_[k * gates_]);
}

SimResult CableSimulator::run(const double* ve, double amplitude, const Waveform& w,
                              const SimOptions& o) {
  reset();
  const std::size_t nn = axon_.nodes.size();
  for (std::size_t j = 0; j < nn; ++j) {
    peak_node_mV_[j] = v_init_;
    cross_ms_[j] = -1.0;
  }
  // The step schedule: dt_ms, finer in the windows of short phases.
  windows_.clear();
  {
    double t = w.delay_ms;
    for (const Waveform::Phase& ph : w.phases) {
      if (ph.duration_ms < o.short_phase_ms && ph.level != 0.0 && ph.duration_ms > 0.0)
        windows_.push_back({t, t + ph.duration_ms + 0.1,
                            std::max(o.min_dt_ms, std::min(o.dt_ms, ph.duration_ms / 10.0))});
      t += ph.duration_ms;
    }
  }
  const bool uniform = windows_.empty();
  const auto uniform_steps =
      static_cast<std::size_t>(std::ceil(o.tstop_ms / o.dt_ms - 1e-9));  // as NEURON counts
  SimResult r;
  double s_old = 0.0;
  std::size_t detected = 0;
  double t1 = 0.0;
  for (std::size_t n = 0;; ++n) {
    double t0;
    if (uniform) {  // t from the step count: no rounding accumulates
      if (n >= uniform_steps) break;
      t0 = static_cast<double>(n) * o.dt_ms;
      t1 = static_cast<double>(n + 1) * o.dt_ms;
    } else {
      if (t1 >= o.tstop_ms - 1e-12) break;
      t0 = t1;
      double dt = o.dt_ms, edge = o.tstop_ms;
      for (const Window& win : windows_) {
        if (t0 >= win.from_ms - 1e-12 && t0 < win.until_ms - 1e-12) {
          dt = std::min(dt, win.dt_ms);
          edge = std::min(edge, win.until_ms);
        } else if (win.from_ms > t0 + 1e-12) {
          edge = std::min(edge, win.from_ms);
        }
      }
      t1 = std::min(t0 + dt, edge);
    }
    const double s_new = amplitude * w.mean_level(t0, t1);
    step(t1 - t0, s_old, s_new, ve);
    s_old = s_new;
    r.steps = n + 1;
    for (std::size_t j = 0; j < nn; ++j) {
      const std::size_t k = axon_.nodes[j];
      const double vm = vi_[k] - vp_[k];
      if (!std::isfinite(vm))
        failure("fibre: the simulation diverged (membrane potential not finite at node " +
                std::to_string(j) + ", amplitude " + std::to_string(amplitude) + " mA)");
      if (vm > peak_node_mV_[j]) peak_node_mV_[j] = vm;
      if (cross_ms_[j] < 0 && vm > o.detect_mV) {
        cross_ms_[j] = t1;
        if (r.first_time_ms < 0) {
          r.first_time_ms = t1;
          r.first_node = j;
        }
      }
    }
    if (trace_ && (n + 1) % trace_every_ == 0 && trace_->size() + nn + 1 <= trace_->capacity()) {
      trace_->push_back(t1);
      for (std::size_t j = 0; j < nn; ++j)
        trace_->push_back(vi_[axon_.nodes[j]] - vp_[axon_.nodes[j]]);
    }
    detected = 0;
    for (std::size_t j : o.detect) detected += cross_ms_[j] >= 0 ? 1 : 0;
    if (o.stop_when_detected && !o.detect.empty() && detected == o.detect.size()) break;
  }
  r.fired = !o.detect.empty() && detected == o.detect.size();
  for (std::size_t j = 0; j < nn; ++j)
    final_node_mV_[j] = vi_[axon_.nodes[j]] - vp_[axon_.nodes[j]];
  return r;
}

}  // namespace tp::fibre
