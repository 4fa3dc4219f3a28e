// The electrode-skin interface (device/skin_circuit.hpp, issue 41 item 1): the R || C
// voltage against its closed form for a rectangular and a biphasic pulse, and against a
// fine explicit integration of the circuit's equation; contact 0.5 doubles the interface's
// resistance; the resistance halves at j_half; no contact needs an infinite voltage.  The
// spreading resistance (rect3d, model/conductor.hpp) against a quadrature of the model's own
// surface potential, the long-strip limit and the disc bound rho / (4a) (Newman 1966).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>

#include "device/pulse_record.hpp"
#include "device/skin_circuit.hpp"
#include "model/conductor.hpp"

using namespace tp;
using namespace tp::device;

namespace {
constexpr double kPi = 3.14159265358979323846;

// dVc/dt = (I - Vc / Rp(I)) / Cp by explicit Euler steps of dt_us (the peer).
double euler_vc(const SkinInterface& s, double vc, double current_mA, double duration_us,
                double dt_us) {
  const double rp = interface_rp_kohm(s, current_mA), cp = interface_cp_nf(s);
  const auto n = static_cast<long>(std::llround(duration_us / dt_us));
  for (long k = 0; k < n; ++k) vc += dt_us * (current_mA - vc / rp) / cp;  // mA / nF = V / us
  return vc;
}
}  // namespace

TEST_CASE("skin circuit: a rectangular pulse's voltage is the closed form", "[device][skin]") {
  SkinInterface s;  // 1 kOhm + 50 kOhm || 30 nF: tau 1500 us
  SkinState st;
  const double v = phase_voltage_V(s, st, 2.0, 200.0);
  const double closed = 2.0 * 1.0 + 2.0 * 50.0 * (1 - std::exp(-200.0 / 1500.0));
  CHECK(v == Approx(closed).epsilon(1e-12));
  CHECK(st.vc_V == Approx(closed - 2.0).epsilon(1e-12));
  // A long phase reaches I (Rs + Rp); the derived impedance is Rs + Rp.
  SkinState long_st;
  const double v_long = phase_voltage_V(s, long_st, 1.0, 1e6);
  CHECK(measured_impedance_kohm(v_long, 1.0) == Approx(51.0).epsilon(1e-12));
  CHECK(measured_impedance_kohm(-v_long, -1.0) == Approx(51.0).epsilon(1e-12));
  CHECK(measured_impedance_kohm(0.0, 0.0) == 0.0);
}

TEST_CASE("skin circuit: a biphasic pulse, against the closed form and an integration",
          "[device][skin]") {
  SkinInterface s;
  s.rs_kohm = 2.0;
  s.rp_kohm = 80.0;
  s.cp_nf = 10.0;  // tau 800 us
  const double i = 1.5, w = 200, gap = 50, bw = 400;
  SkinState st;
  const double v1 = phase_voltage_V(s, st, i, w);
  const double vg = phase_voltage_V(s, st, 0.0, gap);
  const double v2 = phase_voltage_V(s, st, -i * w / bw, bw);
  const double tau = 800.0;
  const double c1 = i * 80.0 * (1 - std::exp(-w / tau));
  const double cg = c1 * std::exp(-gap / tau);
  const double target = -i * w / bw * 80.0;
  const double c2 = target + (cg - target) * std::exp(-bw / tau);
  CHECK(v1 == Approx(i * 2.0 + c1).epsilon(1e-12));
  CHECK(vg == Approx(cg).epsilon(1e-12));
  CHECK(v2 == Approx(-i * w / bw * 2.0 + c2).epsilon(1e-12));
  // The whole pulse at once: the same ends, and the peak where the balance starts (the
  // interface's charge plus the step through Rs) or where a phase ends.
  SkinState again;
  const double currents[3] = {i, 0.0, -i * w / bw}, durations[3] = {w, gap, bw};
  double ends[3];
  const double peak = pulse_peak_voltage_V(s, again, currents, durations, 3, ends);
  CHECK(ends[0] == v1);
  CHECK(ends[2] == v2);
  CHECK(again.vc_V == st.vc_V);
  CHECK(peak == Approx(std::max({std::fabs(v1), std::fabs(-i * w / bw * 2.0 + cg), std::fabs(v2)}))
                    .epsilon(1e-15));
  // The peer: explicit Euler at 0.01 us, within 1e-4 of the exact answer.
  double vc = euler_vc(s, 0.0, i, w, 0.01);
  vc = euler_vc(s, vc, 0.0, gap, 0.01);
  vc = euler_vc(s, vc, -i * w / bw, bw, 0.01);
  CHECK(st.vc_V == Approx(vc).epsilon(1e-4));
}

TEST_CASE("skin circuit: contact scales the interface, density lowers its resistance",
          "[device][skin]") {
  SkinInterface s;
  s.area_mm2 = 2.0;
  const double full = interface_rp_kohm(s, 0.0);
  s.contact = 0.5;
  CHECK(interface_rp_kohm(s, 0.0) == Approx(2 * full).epsilon(1e-15));  // half the area
  CHECK(interface_cp_nf(s) == Approx(15.0).epsilon(1e-15));
  CHECK(series_rs_kohm(s) == Approx(std::sqrt(2.0)).epsilon(1e-15));  // a disc's, 1/sqrt(area)
  // Rp halves where the density through the touching area is j_half: 1 mA on 0.5 x 2 mm^2.
  s.j_half_mA_mm2 = 1.0;
  CHECK(interface_rp_kohm(s, 1.0) == Approx(0.5 * interface_rp_kohm(s, 0.0)).epsilon(1e-15));
  CHECK(interface_rp_kohm(s, -1.0) == interface_rp_kohm(s, 1.0));
  CHECK(interface_rp_kohm(s, 3.0) < interface_rp_kohm(s, 1.0));
  // The same current on half the contact: twice the density, so a lower factor.
  SkinInterface whole = s;
  whole.contact = 1.0;
  CHECK(interface_rp_kohm(s, 1.0) / (2 * interface_rp_kohm(whole, 1.0)) ==
        Approx((1.0 + 0.5) / (1.0 + 1.0)).epsilon(1e-15));
  // Lifted: any current needs an infinite voltage; none, none.
  s.contact = 0.0;
  SkinState st{3.0};
  CHECK(std::isinf(phase_voltage_V(s, st, 0.1, 100)));
  CHECK(phase_voltage_V(s, st, 0.0, 100) == 0.0);
  CHECK(st.vc_V == 0.0);
  CHECK(phase_voltage_V(s, st, -0.1, 100) == -std::numeric_limits<double>::infinity());
  // A contact too small for a double's range is none (no NaN carried on): 5e-324.
  s.contact = 5e-324;
  SkinState tiny{1.0};
  CHECK(std::isinf(phase_voltage_V(s, tiny, 0.1, 100)));
  s.contact = 1.0;
  CHECK(std::isfinite(phase_voltage_V(s, tiny, 0.1, 100)));
}

TEST_CASE("skin circuit: the compliance rail takes the voltage's sign", "[device][skin]") {
  // The interface's charge can make the main phase's end voltage oppose its current (a
  // shaped pulse whose strongest phase follows a long one of the other polarity).
  CHECK(rail_voltage_V(-1309.7, 2.0, 100) == -100);
  CHECK(rail_voltage_V(536.0, -2.0, 100) == 100);
  CHECK(rail_voltage_V(42.5, -2.0, 100) == 42.5);
  CHECK(rail_voltage_V(-100, 2.0, 100) == -100);
  // Not finite (a lifted pad): the current's sign.
  CHECK(rail_voltage_V(std::numeric_limits<double>::infinity(), -1.0, 20) == -20);
  CHECK(rail_voltage_V(std::nan(""), 1.0, 20) == 20);
}

TEST_CASE("spreading resistance: rect3d's closed form against its own potential and limits",
          "[model][skin]") {
  for (const auto& [w, l] : {std::pair{1.0, 1.0}, std::pair{0.5, 2.0}, std::pair{2.0, 0.3}}) {
    const ElectrodeArray a = ElectrodeArray::grid_of(1, 1, 3.0, 3.0, w, l);
    const auto c = make_rect3d(a, 3.0, 0.0);
    const std::optional<double> r = c->spreading_resistance_kohm(0);
    REQUIRE(r);
    // The mean of the model's surface potential over the pad (1 mA): a midpoint rule.
    const int n = 200;
    double sum = 0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        double psi = 0;
        c->unit_potentials_3d(-w / 2 + (i + 0.5) * w / n, 1e-9, -l / 2 + (j + 0.5) * l / n, &psi);
        sum += psi;
      }
    CHECK(*r == Approx(-sum / (n * n)).epsilon(2e-3));  // cathodic: the pad is negative
  }
  // A square: 0.4732 rho / w, 6.8 % above the disc of its area.
  const auto square = make_rect3d(ElectrodeArray::grid_of(1, 1, 3.0, 3.0, 1.0, 1.0), 1.0, 0.0);
  CHECK(*square->spreading_resistance_kohm(0) == Approx(0.473201).epsilon(1e-5));
  // A long strip, L >> w: rho / (pi L) (ln(2 L / w) + 1/2).
  const auto strip =
      make_rect3d(ElectrodeArray::grid_of(1, 1, 100.0, 100.0, 0.05, 50.0), 1.0, 0.0);
  CHECK(*strip->spreading_resistance_kohm(0) ==
        Approx(1.0 / (kPi * 50.0) * (std::log(2 * 50.0 / 0.05) + 0.5)).epsilon(2e-4));  // + O(w / L)
  // The models without it say so.
  ConductorParams p;
  p.model = "line2d";
  CHECK(!make_conductor(p, ElectrodeArray::paper())->spreading_resistance_kohm(0));
}

// A disc of radius a made of small square pads: driven at one potential (the currents that
// make every pad's mean potential equal), its resistance approaches rho / (4 a) (Newman
// 1966, an equipotential disc on a half-space); loaded uniformly, 8 rho / (3 pi^2 a) (the
// mean potential of a uniformly loaded disc).  The pads' own resistances are the closed
// form; each pair's, the mean over a pad of the other's potential (3 x 3 Gauss points).
TEST_CASE("spreading resistance: a disc of pads against rho / (4 a)", "[model][skin]") {
  const double h = 0.1, rho = 1.0;
  std::vector<double> x, z;
  for (int i = -9; i < 9; ++i)
    for (int j = -9; j < 9; ++j) {
      const double cx = (i + 0.5) * h, cz = (j + 0.5) * h;
      if (std::hypot(cx, cz) < 0.88) {
        x.push_back(cx);
        z.push_back(cz);
      }
    }
  const std::size_t n = x.size();
  REQUIRE(n <= 256);
  const double a = std::sqrt(static_cast<double>(n) * h * h / kPi);  // the same area
  const auto c = make_rect3d(ElectrodeArray::pads(x, z, h, h), rho, 0.0);
  Eigen::MatrixXd m(n, n);
  const double g[3] = {-std::sqrt(0.6) / 2, 0.0, std::sqrt(0.6) / 2}, gw[3] = {5 / 18., 8 / 18., 5 / 18.};
  std::vector<double> psi(n);
  m.setZero();
  for (std::size_t i = 0; i < n; ++i) {
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 3; ++q) {
        c->unit_potentials_3d(x[i] + g[p] * h, 1e-9, z[i] + g[q] * h, psi.data());
        for (std::size_t j = 0; j < n; ++j) m(i, j) -= gw[p] * gw[q] * psi[j];
      }
    m(i, i) = *c->spreading_resistance_kohm(i);
  }
  m = 0.5 * (m + m.transpose()).eval();  // reciprocity, up to the quadrature
  const double equipotential = 1.0 / (m.ldlt().solve(Eigen::VectorXd::Ones(n))).sum();
  const double uniform = m.sum() / static_cast<double>(n * n);
  CAPTURE(n, a, equipotential, uniform);
  // 248 pads: +0.4 % and -0.3 % (the staircase edge).
  CHECK(equipotential == Approx(rho / (4 * a)).epsilon(0.01));
  CHECK(uniform == Approx(8 * rho / (3 * kPi * kPi * a)).epsilon(0.01));
  CHECK(equipotential < uniform);  // Thomson: the free distribution dissipates least
}


TEST_CASE("pulse records: an electrical record's voltages and impedances", "[device][skin]") {
  device::PulseRecord r;
  r.channels = 3;
  r.step_nA = 1000;
  r.main[0] = 500;
  r.main[1] = -500;
  r.width_us = r.balance_width_us = 200;
  r.balance[0] = -500;
  r.balance[1] = 500;
  device::ElectricalRecord e;
  e.carried[0] = e.carried[1] = true;
  e.voltage_mV[0] = 3622;
  e.voltage_mV[1] = -100000;
  e.impedance_ohm[0] = 7244;
  e.impedance_ohm[1] = 200000;
  r.electrical = &e;
  char line[device::kMaxElectricalRecordLine];
  const std::string text(line, device::format_record(r, line));
  CHECK(text.find(", \"voltage_V\": [3.622, -100, null], \"impedance_kohm\": [7.244, 200, null]}\n") !=
        std::string::npos);
  // The widest: 64 channels, every value at its extreme, within the bound.
  device::PulseRecord big = r;
  device::ElectricalRecord extreme;
  big.electrical = &extreme;
  big.channels = device::kMaxChannels;
  for (std::size_t c = 0; c < device::kMaxChannels; ++c) {
    big.main[c] = -32768;
    big.balance[c] = -32768;
    extreme.carried[c] = true;
    extreme.voltage_mV[c] = INT32_MIN;
    extreme.impedance_ohm[c] = UINT32_MAX;
  }
  big.step_nA = 65535;
  big.width_us = big.balance_width_us = 65535;
  big.t_us = UINT64_MAX;
  big.slip_us = UINT32_MAX;
  big.measured = true;
  big.start_us = UINT64_MAX;
  big.dropped_before = UINT32_MAX;
  const std::size_t len = device::format_record(big, line);
  CHECK(len <= device::kMaxElectricalRecordLine);
  CHECK(std::string(line, len).find("[-2147483.648, ") != std::string::npos);
}
