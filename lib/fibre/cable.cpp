// Backward-Euler cable integration with a block-tridiagonal (Thomas) solve per step.

#include "fibre/cable.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
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
  // Condensation: runs of passive compartments between nodes (double cable, nodes in order).
  const std::size_t m = axon_.nodes.size();
  bool ordered = axon_.double_cable;
  for (std::size_t j = 0; ordered && j < m; ++j)
    ordered = axon_.nodes[j] < n_ && (j == 0 || axon_.nodes[j] > axon_.nodes[j - 1]);
  if (ordered) {
    run_after_node_.assign(m, -1);
    run_before_node_.assign(m, -1);
    long node = -1;  // the last node seen
    for (std::size_t k = 0; k < n_;) {
      if (is_node_[k]) {
        ++node;
        ++k;
        continue;
      }
      Run r{k, k, node, -1};
      while (r.q + 1 < n_ && !is_node_[r.q + 1]) ++r.q;
      if (r.q + 1 < n_) r.right = node + 1;
      const long index = static_cast<long>(runs_.size());
      if (r.left >= 0) run_after_node_[static_cast<std::size_t>(r.left)] = index;
      if (r.right >= 0) run_before_node_[static_cast<std::size_t>(r.right)] = index;
      runs_.push_back(r);
      k = r.q + 1;
    }
    slots_.resize(3);
    for (Condensed& c : slots_) {
      c.f.assign(n_, Condensed::Factors{});
      for (auto* v : {&c.s11, &c.s12, &c.s22, &c.c11, &c.c12, &c.c21, &c.c22}) v->assign(m, 0.0);
    }
    for (auto* v : {&nd11_, &nd12_, &nd22_, &nr1_, &nr2_}) v->assign(m, 0.0);
  }
  final_node_mV_.assign(axon_.nodes.size(), 0.0);
  peak_node_mV_.assign(axon_.nodes.size(), 0.0);
  cross_ms_.assign(axon_.nodes.size(), -1.0);
  keep_state();  // sized now: pausing copies without allocating
}

// The run's state into paused_ (vectors of the same sizes: no allocation).
void CableSimulator::keep_state() {
  paused_.vi = vi_;
  paused_.vp = vp_;
  paused_.gate = gate_;
  paused_.peak = peak_node_mV_;
  paused_.cross = cross_ms_;
}

void CableSimulator::reset() {
  std::fill(vp_.begin(), vp_.end(), 0.0);
  std::fill(vi_.begin(), vi_.end(), v_init_);
  for (std::size_t k = 0; k < n_; ++k)
    if (is_node_[k]) kin_.steady_state(v_init_, &gate_[k * gates_]);
}

// Compartment k's membrane at vm: its ionic (or passive) current in uA, and the current's
// derivative in vm, g (mS).
double CableSimulator::membrane(std::size_t k, double vm, double& g) const {
  const Compartment& c = axon_.compartments[k];
  if (is_node_[k]) {
    const double i = kin_.current(vm, &gate_[k * gates_], &g) * c.area_cm2 * 1e3;
    g *= c.area_cm2 * 1e3;
    return i;
  }
  g = c.g_pas_mS;
  return g * (vm - c.e_pas_mV);
}

// The factors of step length dt: from the slot that holds them, else computed into the
// least recently used slot.  Every step of a double cable is condensed, so a run's numbers
// depend on its inputs alone, not on what the simulator ran before (the factors are a
// function of dt).
const CableSimulator::Condensed* CableSimulator::condensed_for(double dt) {
  if (slots_.empty() || !condense_) return nullptr;
  ++clock_;
  Condensed* oldest = &slots_[0];
  for (Condensed& c : slots_) {
    if (c.dt == dt) {
      c.used = clock_;
      return &c;
    }
    if (c.used < oldest->used) oldest = &c;
  }
  fill(*oldest, dt);
  oldest->used = clock_;
  return oldest;
}

namespace {
// The inverse of the symmetric 2x2 block (d11 d12; d12 d22).
void inverse_sym(double d11, double d12, double d22, double& i11, double& i12, double& i22) {
  const double det = d11 * d22 - d12 * d12;
  i11 = d22 / det;
  i12 = -d12 / det;
  i22 = d11 / det;
}
// 2x2 products, row-major: out = a b.
void mul22(const double* a, const double* b, double* out) {
  const double o0 = a[0] * b[0] + a[1] * b[2], o1 = a[0] * b[1] + a[1] * b[3];
  const double o2 = a[2] * b[0] + a[3] * b[2], o3 = a[2] * b[1] + a[3] * b[3];
  out[0] = o0;
  out[1] = o1;
  out[2] = o2;
  out[3] = o3;
}
// out = dinv (symmetric 11, 12, 22) b.
void sym_mul22(const double* d, const double* b, double* out) {
  const double full[4] = {d[0], d[1], d[1], d[2]};
  mul22(full, b, out);
}
}  // namespace

// Each run of passive compartments p..q is a block-tridiagonal system T of its own, whose
// blocks depend on dt alone: T y = r, with the neighbouring nodes' potentials entering
// through the links G(p-1) and G(q).  So x = y + U x_left + W x_right, with U = T^-1 e_p
// G(p-1) and W = T^-1 e_q G(q) fixed, and the nodes see the Schur complements G(p-1) U_p,
// G(q) W_q on their diagonals and G(p-1) W_p as their coupling.
void CableSimulator::fill(Condensed& c, double dt) {
  const std::vector<Compartment>& cs = axon_.compartments;
  const std::size_t m = axon_.nodes.size();
  for (auto* v : {&c.s11, &c.s12, &c.s22, &c.c11, &c.c12, &c.c21, &c.c22})
    std::fill(v->begin(), v->end(), 0.0);
  for (std::size_t j = 0; j + 1 < m; ++j)
    if (axon_.nodes[j + 1] == axon_.nodes[j] + 1) {  // adjacent nodes: the link itself
      c.c11[j] = gi_link_[axon_.nodes[j]];
      c.c22[j] = gp_link_[axon_.nodes[j]];
    }
  for (std::size_t k = 0; k < n_; ++k) {
    c.f[k].c_dt = cs[k].c_uF / dt;
    c.f[k].cs_dt = cs[k].c_sheath_uF / dt;
  }
  for (const Run& r : runs_) {
    for (std::size_t k = r.p; k <= r.q; ++k) {
      Condensed::Factors& f = c.f[k];
      const Compartment& x = cs[k];
      const double a = f.c_dt + x.g_pas_mS;
      const double e = f.cs_dt + x.g_sheath_mS;
      const double pi = k > 0 ? gi_link_[k - 1] : 0.0, pp = k > 0 ? gp_link_[k - 1] : 0.0;
      double d11 = a + pi + gi_link_[k], d12 = -a, d22 = a + e + pp + gp_link_[k];
      if (k > r.p) {
        const double* q = c.f[k - 1].dinv;
        d11 -= pi * pi * q[0];
        d12 -= pi * pp * q[1];
        d22 -= pp * pp * q[2];
        f.m[0] = pi * q[0];
        f.m[1] = pi * q[1];
        f.m[2] = pp * q[1];
        f.m[3] = pp * q[2];
      }
      inverse_sym(d11, d12, d22, f.dinv[0], f.dinv[1], f.dinv[2]);
      const double gi = gi_link_[k], gp = gp_link_[k];
      f.p[0] = f.dinv[0] * gi;
      f.p[1] = f.dinv[1] * gp;
      f.p[2] = f.dinv[1] * gi;
      f.p[3] = f.dinv[2] * gp;
    }
    // U: forward from G(p-1) at p, then back.
    if (r.left >= 0) {
      Condensed::Factors& fp = c.f[r.p];
      fp.u[0] = gi_link_[r.p - 1];
      fp.u[1] = fp.u[2] = 0.0;
      fp.u[3] = gp_link_[r.p - 1];
      for (std::size_t k = r.p + 1; k <= r.q; ++k) mul22(c.f[k].m, c.f[k - 1].u, c.f[k].u);
      sym_mul22(c.f[r.q].dinv, c.f[r.q].u, c.f[r.q].u);
      for (std::size_t k = r.q; k-- > r.p;) {
        double a[4], b[4];
        sym_mul22(c.f[k].dinv, c.f[k].u, a);
        mul22(c.f[k].p, c.f[k + 1].u, b);
        for (int i = 0; i < 4; ++i) c.f[k].u[i] = a[i] + b[i];
      }
    } else {
      for (std::size_t k = r.p; k <= r.q; ++k) std::fill(c.f[k].u, c.f[k].u + 4, 0.0);
    }
    // W: G(q) at q alone, so back from q.
    if (r.right >= 0) {
      const double g[4] = {gi_link_[r.q], 0.0, 0.0, gp_link_[r.q]};
      sym_mul22(c.f[r.q].dinv, g, c.f[r.q].w);
      for (std::size_t k = r.q; k-- > r.p;) mul22(c.f[k].p, c.f[k + 1].w, c.f[k].w);
    } else {
      for (std::size_t k = r.p; k <= r.q; ++k) std::fill(c.f[k].w, c.f[k].w + 4, 0.0);
    }
    if (r.left >= 0) {
      const auto L = static_cast<std::size_t>(r.left);
      const double gi = gi_link_[r.p - 1], gp = gp_link_[r.p - 1];
      const double* u = c.f[r.p].u;
      c.s11[L] += gi * u[0];
      c.s12[L] += gi * u[1];
      c.s22[L] += gp * u[3];
      if (r.right >= 0) {
        const double* w = c.f[r.p].w;
        c.c11[L] = gi * w[0];
        c.c12[L] = gi * w[1];
        c.c21[L] = gp * w[2];
        c.c22[L] = gp * w[3];
      }
    }
    if (r.right >= 0) {
      const auto R = static_cast<std::size_t>(r.right);
      const double gi = gi_link_[r.q], gp = gp_link_[r.q];
      const double* w = c.f[r.q].w;
      c.s11[R] += gi * w[0];
      c.s12[R] += gi * w[1];
      c.s22[R] += gp * w[3];
    }
  }
  c.dt = dt;
}

// Each run's right-hand sides (rows as in step()), eliminated forward as they are formed
// and solved back: y = T^-1 r, in place.  The previous row is carried in registers: the
// elimination's chain is the step's critical path.
void CableSimulator::solve_runs(const Condensed& c, double s_old, double s_new, const double* ve) {
  const std::vector<Compartment>& cs = axon_.compartments;
  const Condensed::Factors* fk = c.f.data();
  double* y1 = y1_.data();
  double* y2 = y2_.data();
  const double* vi = vi_.data();
  const double* vp = vp_.data();
  for (const Run& r : runs_) {
    double p1 = 0.0, p2 = 0.0;  // y at k - 1
    for (std::size_t k = r.p; k <= r.q; ++k) {
      const Compartment& x = cs[k];
      const double vm = vi[k] - vp[k];
      const double g = x.g_pas_mS;
      const double i = g * (vm - x.e_pas_mV);
      const double a = fk[k].c_dt + g;
      const double b = a * vm - i;
      const double cs_dt = fk[k].cs_dt;
      const double e = cs_dt + x.g_sheath_mS;
      const double f = cs_dt * (vp[k] - s_old * ve[k]) + e * s_new * ve[k];
      double v1 = b, v2 = f - b;
      if (k > r.p) {
        const double* M = fk[k].m;
        v1 += M[0] * p1 + M[1] * p2;
        v2 += M[2] * p1 + M[3] * p2;
      }
      y1[k] = p1 = v1;
      y2[k] = p2 = v2;
    }
    double n1 = 0.0, n2 = 0.0;  // y at k + 1
    for (std::size_t k = r.q + 1; k-- > r.p;) {
      const double* d = fk[k].dinv;
      const double* P = fk[k].p;
      const double z1 = y1[k], z2 = y2[k];
      double v1 = d[0] * z1 + d[1] * z2, v2 = d[1] * z1 + d[2] * z2;
      if (k < r.q) {
        v1 += P[0] * n1 + P[1] * n2;
        v2 += P[2] * n1 + P[3] * n2;
      }
      y1[k] = n1 = v1;
      y2[k] = n2 = v2;
    }
  }
}

void CableSimulator::step_condensed(const Condensed& c, double s_old, double s_new,
                                    const double* ve) {
  const std::vector<Compartment>& cs = axon_.compartments;
  const std::size_t m = axon_.nodes.size();
  // Right-hand sides of every compartment (rows as in step()): the nodes' with their
  // diagonals, then the runs' (solve_runs).
  for (std::size_t j = 0; j < m; ++j) {
    const std::size_t k = axon_.nodes[j];
    const Compartment& x = cs[k];
    const double vm = vi_[k] - vp_[k];
    double g;
    const double i = membrane(k, vm, g);
    const double a = c.f[k].c_dt + g;
    const double b = a * vm - i;
    const double cs_dt = c.f[k].cs_dt;
    const double e = cs_dt + x.g_sheath_mS;
    const double f = cs_dt * (vp_[k] - s_old * ve[k]) + e * s_new * ve[k];
    y1_[k] = b;
    y2_[k] = f - b;
    const double pi = k > 0 ? gi_link_[k - 1] : 0.0, pp = k > 0 ? gp_link_[k - 1] : 0.0;
    nd11_[j] = a + pi + gi_link_[k] - c.s11[j];
    nd12_[j] = -a - c.s12[j];
    nd22_[j] = a + e + pp + gp_link_[k] - c.s22[j];
  }
  solve_runs(c, s_old, s_new, ve);
  // The nodes' system: B_j x_j - C_(j-1)^T x_(j-1) - C_j x_(j+1) = r_j, forward elimination.
  for (std::size_t j = 0; j < m; ++j) {
    const std::size_t k = axon_.nodes[j];
    double r1 = y1_[k], r2 = y2_[k];
    if (run_before_node_[j] >= 0) {
      const std::size_t q = runs_[static_cast<std::size_t>(run_before_node_[j])].q;
      r1 += gi_link_[q] * y1_[q];
      r2 += gp_link_[q] * y2_[q];
    }
    if (run_after_node_[j] >= 0) {
      const std::size_t p = runs_[static_cast<std::size_t>(run_after_node_[j])].p;
      r1 += gi_link_[k] * y1_[p];
      r2 += gp_link_[k] * y2_[p];
    }
    double d11 = nd11_[j], d12 = nd12_[j], d22 = nd22_[j];
    if (j > 0) {
      const double i11 = inv11_[j - 1], i12 = inv12_[j - 1], i22 = inv22_[j - 1];
      const double c11 = c.c11[j - 1], c12 = c.c12[j - 1], c21 = c.c21[j - 1], c22 = c.c22[j - 1];
      const double q11 = i11 * c11 + i12 * c21, q12 = i11 * c12 + i12 * c22;
      const double q21 = i12 * c11 + i22 * c21, q22 = i12 * c12 + i22 * c22;
      d11 -= c11 * q11 + c21 * q21;
      d12 -= c11 * q12 + c21 * q22;
      d22 -= c12 * q12 + c22 * q22;
      const double s1 = nr1_[j - 1], s2 = nr2_[j - 1];
      const double t1 = i11 * s1 + i12 * s2, t2 = i12 * s1 + i22 * s2;
      r1 += c11 * t1 + c21 * t2;
      r2 += c12 * t1 + c22 * t2;
    }
    inverse_sym(d11, d12, d22, inv11_[j], inv12_[j], inv22_[j]);
    nr1_[j] = r1;
    nr2_[j] = r2;
  }
  double x1 = 0.0, x2 = 0.0;  // node j + 1
  for (std::size_t j = m; j-- > 0;) {
    double s1 = nr1_[j], s2 = nr2_[j];
    if (j + 1 < m) {
      s1 += c.c11[j] * x1 + c.c12[j] * x2;
      s2 += c.c21[j] * x1 + c.c22[j] * x2;
    }
    x1 = inv11_[j] * s1 + inv12_[j] * s2;
    x2 = inv12_[j] * s1 + inv22_[j] * s2;
    vi_[axon_.nodes[j]] = x1;
    vp_[axon_.nodes[j]] = x2;
  }
  // The passive compartments from their nodes.
  for (const Run& r : runs_) {
    double l1 = 0.0, l2 = 0.0, q1 = 0.0, q2 = 0.0;
    if (r.left >= 0) {
      const std::size_t k = axon_.nodes[static_cast<std::size_t>(r.left)];
      l1 = vi_[k];
      l2 = vp_[k];
    }
    if (r.right >= 0) {
      const std::size_t k = axon_.nodes[static_cast<std::size_t>(r.right)];
      q1 = vi_[k];
      q2 = vp_[k];
    }
    for (std::size_t k = r.p; k <= r.q; ++k) {
      const double* U = c.f[k].u;
      const double* W = c.f[k].w;
      vi_[k] = y1_[k] + U[0] * l1 + U[1] * l2 + W[0] * q1 + W[1] * q2;
      vp_[k] = y2_[k] + U[2] * l1 + U[3] * l2 + W[2] * q1 + W[3] * q2;
    }
  }
}

// One step: the linear network at t + dt with the ionic conductance of the gates at t.
void CableSimulator::step(double dt, double s_old, double s_new, const double* ve) {
  const std::vector<Compartment>& cs = axon_.compartments;
  if (const Condensed* cond = axon_.double_cable ? condensed_for(dt) : nullptr) {
    step_condensed(*cond, s_old, s_new, ve);
  } else if (axon_.double_cable) {
    // Unknowns per compartment: intracellular u and periaxonal w.  Rows:
    //   a (u - w) + sum gi (u - u_j)                  =  b
    //  -a (u - w) + e w + sum gp (w - w_j)            = -b + f
    // a = C/dt + g_ion, b = a vm - I_ion, e = C_sheath/dt + G_sheath,
    // f = C_sheath/dt (vp - ve_old) + e ve_new.  Forward elimination, then back substitution.
    double pi = 0.0, pp = 0.0;  // link conductances to the previous compartment
    for (std::size_t k = 0; k < n_; ++k) {
      const Compartment& c = cs[k];
      const double vm = vi_[k] - vp_[k];
      double g;
      const double i = membrane(k, vm, g);
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
      inverse_sym(d11, d12, d22, inv11_[k], inv12_[k], inv22_[k]);
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
      double g;
      const double i = membrane(k, vm, g);
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
  schedule(w, o);
  // The waveform's onset: where mean_level() first adds a phase's level (its own sum).
  double onset = w.delay_ms, t = w.delay_ms;
  bool any = false;
  for (const Waveform::Phase& ph : w.phases) {
    if (ph.level != 0.0 && ph.duration_ms > 0.0) {
      onset = t;
      any = true;
      break;
    }
    t += ph.duration_ms;
  }
  const bool cacheable = any && !trace_ && std::isfinite(amplitude);
  if (cacheable && rest_matches(o, onset)) {
    vi_ = rest_.vi;  // the same sizes: no allocation
    vp_ = rest_.vp;
    gate_ = rest_.gate;
    peak_node_mV_ = rest_.peak;
    cross_ms_ = rest_.cross;
    return integrate(ve, amplitude, w, o, o.stop_when_settled, rest_.n, rest_.t1, 0.0);
  }
  if (cacheable) {
    rest_.valid = false;
    rest_.windows = windows_;
    rest_.dt_ms = o.dt_ms;
    rest_.tstop_ms = o.tstop_ms;
    rest_.detect_mV = o.detect_mV;
    rest_.onset_ms = onset;
    rest_.condense = condense_;
  }
  return integrate(ve, amplitude, w, o, o.stop_when_settled, 0, 0.0, 0.0, cacheable);
}

bool CableSimulator::rest_matches(const SimOptions& o, double onset_ms) const {
  if (!rest_.valid || rest_.dt_ms != o.dt_ms || rest_.tstop_ms != o.tstop_ms ||
      rest_.detect_mV != o.detect_mV || rest_.onset_ms != onset_ms || rest_.condense != condense_ ||
      rest_.windows.size() != windows_.size())
    return false;
  for (std::size_t i = 0; i < windows_.size(); ++i)
    if (rest_.windows[i].from_ms != windows_[i].from_ms ||
        rest_.windows[i].until_ms != windows_[i].until_ms ||
        rest_.windows[i].dt_ms != windows_[i].dt_ms)
      return false;
  return true;
}

SimResult CableSimulator::resume(const double* ve, double amplitude, const Waveform& w,
                                 const SimOptions& o) {
  if (!paused_.valid || amplitude != paused_.amplitude)
    failure("fibre: no run at this amplitude is paused");
  paused_.valid = false;
  vi_ = paused_.vi;  // the same sizes: no allocation
  vp_ = paused_.vp;
  gate_ = paused_.gate;
  peak_node_mV_ = paused_.peak;
  cross_ms_ = paused_.cross;
  schedule(w, o);
  return integrate(ve, amplitude, w, o, false, paused_.n, paused_.t1, paused_.s_old);
}

std::optional<double> CableSimulator::paused_amplitude() const {
  if (!paused_.valid) return std::nullopt;
  return paused_.amplitude;
}

// The step schedule: dt_ms, finer in the windows of short phases.
void CableSimulator::schedule(const Waveform& w, const SimOptions& o) {
  windows_.clear();
  double t = w.delay_ms;
  for (const Waveform::Phase& ph : w.phases) {
    if (ph.duration_ms < o.short_phase_ms && ph.level != 0.0 && ph.duration_ms > 0.0)
      windows_.push_back({t, t + ph.duration_ms + 0.1,
                          std::max(o.min_dt_ms, std::min(o.dt_ms, ph.duration_ms / 10.0))});
    t += ph.duration_ms;
  }
}

SimResult CableSimulator::integrate(const double* ve, double amplitude, const Waveform& w,
                                    const SimOptions& o, bool settle, std::size_t n0, double t1,
                                    double s_old, bool keep_rest) {
  const std::size_t nn = axon_.nodes.size();
  const bool uniform = windows_.empty();
  const auto uniform_steps =
      static_cast<std::size_t>(std::ceil(o.tstop_ms / o.dt_ms - 1e-9));  // as NEURON counts
  const double end_ms = w.end_ms();
  SimResult r;
  r.steps = n0;
  std::size_t detected = 0;
  // Since the waveform ended: the nodes' largest distance from rest and largest rise above
  // it, the most each has been and at the last step.
  double far = 0.0, high = 0.0;
  double last_far = std::numeric_limits<double>::infinity(), last_high = last_far;
  for (std::size_t n = n0;; ++n) {
    double t0, h;
    if (uniform) {  // t from the step count: no rounding accumulates
      if (n >= uniform_steps) break;
      t0 = static_cast<double>(n) * o.dt_ms;
      t1 = static_cast<double>(n + 1) * o.dt_ms;
      h = o.dt_ms;
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
      h = t0 + dt <= edge ? dt : edge - t0;
    }
    const double s_new = amplitude * w.mean_level(t0, t1);
    if (keep_rest && s_new != 0.0) {  // the first step with a level: the state before it
      keep_rest = false;
      if (s_old == 0.0 && r.first_time_ms < 0 && t0 <= rest_.onset_ms && t1 > rest_.onset_ms) {
        rest_.vi = vi_;
        rest_.vp = vp_;
        rest_.gate = gate_;
        rest_.peak = peak_node_mV_;
        rest_.cross = cross_ms_;
        rest_.n = n;
        rest_.t1 = t0;
        rest_.valid = true;
      }
    }
    // The step's length: dt itself (t1 - t0 differs from it in the last bits), or what is
    // left before an edge.
    step(h, s_old, s_new, ve);
    s_old = s_new;
    r.steps = n + 1;
    double distance = 0.0, rise = -std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < nn; ++j) {
      const std::size_t k = axon_.nodes[j];
      const double vm = vi_[k] - vp_[k];
      if (!std::isfinite(vm))
        failure("fibre: the simulation diverged (membrane potential not finite at node " +
                std::to_string(j) + ", amplitude " + std::to_string(amplitude) + " mA)");
      if (vm > peak_node_mV_[j]) peak_node_mV_[j] = vm;
      distance = std::max(distance, std::fabs(vm - v_init_));
      rise = std::max(rise, vm - v_init_);
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
    if (t1 < end_ms + o.settle_after_ms) continue;
    far = std::max(far, distance);
    high = std::max(high, rise);
    if (settle && r.first_time_ms < 0 && distance <= o.settle_fraction * far &&
        distance < last_far && rise <= o.settle_fraction * high && rise < last_high) {
      keep_state();
      paused_.amplitude = amplitude;
      paused_.t1 = t1;
      paused_.s_old = s_old;
      paused_.n = n + 1;
      paused_.valid = true;
      r.settled = true;
      break;
    }
    last_far = distance;
    last_high = rise;
  }
  r.fired = !r.settled && !o.detect.empty() && detected == o.detect.size();
  for (std::size_t j = 0; j < nn; ++j)
    final_node_mV_[j] = vi_[axon_.nodes[j]] - vp_[axon_.nodes[j]];
  return r;
}

}  // namespace tp::fibre
