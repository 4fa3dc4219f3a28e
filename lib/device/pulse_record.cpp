#include "device/pulse_record.hpp"

#include <algorithm>
#include <cstdint>

namespace tp::device {

void balance_codes(CodeSpan main, std::uint16_t width_us, std::uint16_t balance_width_us,
                   std::int16_t* out) {
  // In 32-bit arithmetic (|code| x width <= 32768 x 65535 < 2^31): the firmware does this
  // for every pulse, and a Cortex-M4 divides 64-bit integers in a library routine.
  const std::int32_t bw = balance_width_us == 0 ? 1 : balance_width_us;
  std::int32_t rem[kMaxChannels] = {};
  std::int64_t sum = 0;
  const std::size_t n = std::min<std::size_t>(main.size(), kMaxChannels);
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t exact = -std::int32_t{main[i]} * width_us;  // in units of 1/bw codes
    std::int32_t q = exact / bw;
    if (exact % bw != 0 && exact < 0) --q;  // floor
    rem[i] = exact - q * bw;                // 0 .. bw-1
    out[i] = static_cast<std::int16_t>(q);
    sum += q;
  }
  // The exact values sum to zero (the main codes do), so -sum channels go up by one.
  for (std::int64_t k = -sum; k > 0; --k) {
    std::size_t best = n;
    for (std::size_t i = 0; i < n; ++i)
      if (rem[i] > 0 && (best == n || rem[i] > rem[best])) best = i;
    if (best == n) break;
    ++out[best];
    rem[best] = 0;
  }
}

namespace {

class Writer {
 public:
  explicit Writer(char* out) : out_(out) {}
  void text(const char* s) {
    while (*s) out_[n_++] = *s++;
  }
  // In 32-bit arithmetic wherever the value allows: a Cortex-M4 divides 32-bit integers in
  // hardware but 64-bit ones in a library routine, and the firmware formats a line for
  // every pulse (at 1 kHz, 8 channels, the 64-bit version took most of the main loop).
  void uint(std::uint64_t v) {
    if (v > UINT32_MAX) {  // the digits above the last nine, then those nine
      const std::uint64_t hi = v / 1000000000u;
      uint(hi);
      pad9(static_cast<std::uint32_t>(v - hi * 1000000000u));
    } else {
      uint32(static_cast<std::uint32_t>(v));
    }
  }
  // v x 1e-6 in decimal, exactly, without trailing zeros: "-1.000448", "0.005", "0"
  void micro(std::int64_t v) {
    if (v < 0) out_[n_++] = '-';
    const std::uint64_t a =
        v < 0 ? 0 - static_cast<std::uint64_t>(v) : static_cast<std::uint64_t>(v);
    std::uint64_t whole = 0;
    std::uint32_t frac = 0;
    if (a <= UINT32_MAX) {
      whole = static_cast<std::uint32_t>(a) / 1000000u;
      frac = static_cast<std::uint32_t>(a) % 1000000u;
    } else {
      whole = a / 1000000u;
      frac = static_cast<std::uint32_t>(a - whole * 1000000u);
    }
    uint(whole);
    if (frac == 0) return;
    out_[n_++] = '.';
    for (std::uint32_t div = 100000; frac != 0; div /= 10) {
      out_[n_++] = static_cast<char>('0' + frac / div);
      frac %= div;
    }
  }
  // (a x b) x 1e-6 exactly, for |a| < 2^31 and |b| < 2^40 (whose product a 64-bit integer
  // may not hold): b's millions and its remainder, each times a.
  void micro_product(std::int64_t a, std::int64_t b) {
    const bool negative = (a < 0) != (b < 0) && a != 0 && b != 0;
    const auto ua = static_cast<std::uint64_t>(a < 0 ? -a : a);
    const auto ub = static_cast<std::uint64_t>(b < 0 ? -b : b);
    const std::uint64_t low = ua * (ub % 1000000u);  // < 2^31 x 10^6
    const std::uint64_t whole = ua * (ub / 1000000u) + low / 1000000u;
    if (negative) out_[n_++] = '-';
    uint(whole);
    std::uint32_t frac = static_cast<std::uint32_t>(low % 1000000u);
    if (frac == 0) return;
    out_[n_++] = '.';
    for (std::uint32_t div = 100000; frac != 0; div /= 10) {
      out_[n_++] = static_cast<char>('0' + frac / div);
      frac %= div;
    }
  }
  void sint(std::int64_t v) {
    if (v < 0) out_[n_++] = '-';
    uint(v < 0 ? 0 - static_cast<std::uint64_t>(v) : static_cast<std::uint64_t>(v));
  }
  std::size_t size() const { return n_; }

 private:
  void uint32(std::uint32_t v) {
    char digits[10];
    int k = 0;
    do {
      digits[k++] = static_cast<char>('0' + v % 10);
      v /= 10;
    } while (v != 0);
    while (k > 0) out_[n_++] = digits[--k];
  }
  void pad9(std::uint32_t v) {  // exactly nine digits, leading zeros included
    for (int k = 8; k >= 0; --k) {
      out_[n_ + static_cast<std::size_t>(k)] = static_cast<char>('0' + v % 10);
      v /= 10;
    }
    n_ += 9;
  }
  char* out_;
  std::size_t n_ = 0;
};

void write_head(Writer& w, const PulseRecord& r) {
  w.text("{\"pattern\": ");
  w.uint(r.pattern);
  w.text(", \"t_s\": ");
  w.micro(static_cast<std::int64_t>(r.t_us));
  w.text(", \"slip_us\": ");
  w.uint(r.slip_us);
}

// "voltage_V": [..], "impedance_kohm": [..], null where a channel carried no current (its
// impedance null too where no current flowed: a lifted pad, its voltage at the rail).
void write_electrical(Writer& w, const PulseRecord& r) {
  const std::size_t n = std::min<std::size_t>(r.channels, kMaxChannels);
  const ElectricalRecord& e = *r.electrical;
  // One list: each channel's value x 1e-3 (mV to V, ohm to kOhm), or null.
  auto list = [&](const char* head, auto value, bool open_is_null) {
    w.text(head);
    for (std::size_t i = 0; i < n; ++i) {
      if (i) w.text(", ");
      if (e.carried[i] && !(open_is_null && e.impedance_ohm[i] == kOpenOhm))
        w.micro(std::int64_t{value(i)} * 1000);
      else
        w.text("null");
    }
    w.text("]");
  };
  list(", \"voltage_V\": [", [&](std::size_t i) { return e.voltage_mV[i]; }, false);
  list(", \"impedance_kohm\": [", [&](std::size_t i) { return e.impedance_ohm[i]; }, true);
}

void write_tail(Writer& w, const PulseRecord& r) {
  if (r.electrical) write_electrical(w, r);
  if (r.measured) {
    w.text(", \"start_us\": ");
    w.uint(r.start_us);
  }
  if (r.dropped_before) {
    w.text(", \"dropped_before\": ");
    w.uint(r.dropped_before);
  }
  w.text("}\n");
}

// Each channel's main-phase current (a shaped pulse's unit current), mA: "a, b, ...".
void write_main_currents(Writer& w, const PulseRecord& r, std::size_t n, std::int64_t step) {
  for (std::size_t i = 0; i < n; ++i) {
    if (i) w.text(", ");
    w.micro(r.main[i] * step);  // nA = 1e-6 mA
  }
}

// A shaped pulse: its phases, the base codes' currents, and each channel's net charge.
void write_shaped(Writer& w, const PulseRecord& r) {
  const std::size_t n = std::min<std::size_t>(r.channels, kMaxChannels);
  const std::size_t phases = std::min<std::size_t>(r.shape.n, kMaxPhases);
  const auto step = static_cast<std::int64_t>(r.step_nA);
  w.text(", \"phases\": [");
  std::int64_t charge_units = 0;  // sum units x duration, in units x us: |.| < 2^36
  for (std::size_t k = 0; k < phases; ++k) {
    w.text(k ? ", {\"duration_us\": " : "{\"duration_us\": ");
    w.uint(r.measured ? r.measured_duration_us[k] : r.shape.duration_us[k]);
    w.text(", \"units\": ");
    w.sint(r.shape.units[k]);
    w.text("}");
    charge_units += std::int64_t{r.shape.units[k]} * r.shape.duration_us[k];
  }
  w.text("], \"unit_currents_mA\": [");
  write_main_currents(w, r, n, step);
  w.text("], \"net_charge_nC\": [");
  for (std::size_t i = 0; i < n; ++i) {
    if (i) w.text(", ");
    w.micro_product(r.main[i] * step, charge_units);  // nA x us = fC = 1e-6 nC
  }
  w.text("]");
}

}  // namespace

std::size_t format_record(const PulseRecord& r, char* out) {
  Writer w(out);
  write_head(w, r);
  if (r.shape.n != 0) {
    write_shaped(w, r);
    write_tail(w, r);
    return w.size();
  }
  const std::size_t n = std::min<std::size_t>(r.channels, kMaxChannels);
  const auto step = static_cast<std::int64_t>(r.step_nA);
  w.text(", \"width_us\": ");
  w.uint(r.measured ? r.measured_width_us : r.width_us);
  w.text(", \"interphase_us\": ");
  w.uint(r.measured ? r.measured_interphase_us : r.interphase_us);
  w.text(", \"balance_width_us\": ");
  w.uint(r.measured ? r.measured_balance_us : r.balance_width_us);
  w.text(", \"currents_mA\": [");
  write_main_currents(w, r, n, step);
  w.text("], \"net_charge_nC\": [");
  for (std::size_t i = 0; i < n; ++i) {
    if (i) w.text(", ");
    // nA x us = fC = 1e-6 nC
    w.micro(r.main[i] * step * r.width_us + r.balance[i] * step * r.balance_width_us);
  }
  w.text("]");
  write_tail(w, r);
  return w.size();
}

PulseRecord record_of(const DeliveredPulse& p) {
  PulseRecord r;
  r.pattern = p.pattern;
  r.t_us = p.t_us - p.start_us;
  r.slip_us = p.slip_us;
  r.channels = static_cast<std::uint8_t>(p.codes.size());
  for (std::size_t c = 0; c < p.codes.size() && c < kMaxChannels; ++c) r.main[c] = p.codes[c];
  r.step_nA = p.caps.dac_step_nA;
  if (p.timing.shaped()) {
    r.shape = p.timing.shape;
  } else {
    balance_codes(p.codes, p.timing.width_us, p.timing.balance_width_us, r.balance);
    r.width_us = p.timing.width_us;
    r.interphase_us = p.timing.interphase_us;
    r.balance_width_us = p.timing.balance_width_us;
  }
  return r;
}

}  // namespace tp::device
