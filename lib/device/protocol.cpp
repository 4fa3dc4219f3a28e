#include "device/protocol.hpp"

#include <algorithm>
#include <cstdlib>

namespace tp::device {

const char* to_string(Result r) {
  switch (r) {
    case Result::ok:
      return "ok";
    case Result::unknown_type:
      return "unknown message type";
    case Result::bad_length:
      return "bad message length";
    case Result::out_of_range:
      return "value outside the device's limits";
    case Result::not_configured:
      return "not configured";
    case Result::sum_not_zero:
      return "channel currents do not sum to zero";
    case Result::channel_mismatch:
      return "channel count does not match the device";
    case Result::bad_state:
      return "not allowed while running";
    case Result::wrong_session:
      return "not the device's current session (another host's, or already stopped)";
    case Result::table_full:
      return "more patterns or pattern codes than the device holds";
    case Result::no_pattern:
      return "no such pattern in the table";
    case Result::charge_not_zero:
      return "the pulse shape's net charge is not zero (sum of units x duration)";
    case Result::not_supported:
      return "the device cannot deliver shaped pulses";
  }
  return "unknown result";
}

const char* to_string(Fault f) {
  switch (f) {
    case Fault::none:
      return "none";
    case Fault::watchdog:
      return "watchdog (no keep-alive)";
    case Fault::link_lost:
      return "link lost";
    case Fault::completed:
      return "completed";
    case Fault::overrun:
      return "it could not deliver a pulse on time (more than it can keep up with)";
    case Fault::stopped:
      return "stopped by the host";
    case Fault::output_fault:
      return "output stage fault (the device refuses further output until it is reset)";
    case Fault::contact:
      return "an electrode lost contact";
    case Fault::compliance:
      return "an electrode needed more than the compliance voltage";
    case Fault::density:
      return "the charge density on an electrode's contact area was above the limit";
    case Fault::stop_input:
      return "its stop input was pressed (the output is latched off until a new session)";
  }
  return "unknown fault";
}

bool decode_guards(const std::uint8_t* p, std::size_t n, Guards& out) {
  if (n != kGuardsSize) return false;
  out.area_um2 = get_u32(p);
  out.shannon_k_milli = get_u16(p + 4);
  out.lost_contact_milli = get_u16(p + 6);
  out.probe_uA = get_u16(p + 8);
  out.flags = p[10];
  return true;
}

bool guards_in_range(const Guards& g) {
  if (g.area_um2 != 0 && (g.area_um2 < kMinGuardAreaUm2 || g.area_um2 > kMaxGuardAreaUm2))
    return false;
  if (g.shannon_k_milli < 500 || g.shannon_k_milli > 2500) return false;
  if (g.probe_uA < 10 || g.probe_uA > 500 || (g.flags & ~kGuardSuspend) != 0) return false;
  return g.lost_contact_milli >= 10 && g.lost_contact_milli <= 900;
}

std::uint16_t get_u16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}
std::uint32_t get_u32(const std::uint8_t* p) {
  return std::uint32_t{p[0]} | (std::uint32_t{p[1]} << 8) | (std::uint32_t{p[2]} << 16) |
         (std::uint32_t{p[3]} << 24);
}

std::int32_t Capabilities::max_code() const {
  if (dac_step_nA == 0) return 0;
  const std::uint32_t code = std::uint32_t{max_current_uA} * 1000u / dac_step_nA;
  return static_cast<std::int32_t>(std::min<std::uint32_t>(code, hard::max_dac_code));
}

std::uint32_t PatternTiming::length_us() const {
  if (!shaped()) return std::uint32_t{width_us} + interphase_us + balance_width_us;
  std::uint32_t sum = 0;
  for (std::size_t k = 0; k < shape.n && k < kMaxPhases; ++k) sum += shape.duration_us[k];
  return sum;
}

std::int32_t PatternTiming::max_units() const {
  if (!shaped()) return 1;
  std::int32_t m = 0;
  for (std::size_t k = 0; k < shape.n && k < kMaxPhases; ++k)
    m = std::max(m, std::abs(std::int32_t{shape.units[k]}));
  return m;
}

std::uint32_t PatternTiming::edges() const {
  if (shaped()) return std::uint32_t{shape.n} + 1;
  return interphase_us != 0 ? 4 : 3;
}

Result check_shape(const Shape& s, const Capabilities& caps) {
  if (!caps.shaped_pulses()) return Result::not_supported;
  if (s.n == 0 || s.n > kMaxPhases || s.n > caps.max_phases) return Result::bad_length;
  std::int32_t peak = 0;
  for (std::size_t k = 0; k < s.n; ++k) {
    const std::int32_t u = std::abs(std::int32_t{s.units[k]});
    if (u > hard::max_units) return Result::out_of_range;
    if (s.duration_us[k] < caps.min_width_us || s.duration_us[k] > caps.max_balance_width_us)
      return Result::out_of_range;
    peak = std::max(peak, u);
  }
  if (peak == 0) return Result::out_of_range;  // delivers nothing
  // |units| <= 1024 and durations <= 65535 over 16 phases: < 2^31, but in 64 bits all the same.
  std::int64_t charge = 0;
  for (std::size_t k = 0; k < s.n; ++k) {
    if (std::abs(std::int32_t{s.units[k]}) == peak && s.duration_us[k] > caps.max_width_us)
      return Result::out_of_range;  // the strongest phases are main phases: at most max_width
    charge += std::int64_t{s.units[k]} * s.duration_us[k];
  }
  return charge == 0 ? Result::ok : Result::charge_not_zero;
}

void shape_codes(const std::int16_t* base, std::size_t n, const Shape& s, std::size_t k,
                 std::int16_t* out) {
  const std::int32_t u = k < s.n && k < kMaxPhases ? s.units[k] : 0;
  for (std::size_t c = 0; c < n; ++c)
    out[c] = static_cast<std::int16_t>(std::int32_t{base[c]} * u);
}

bool decode_shape_pattern(const std::uint8_t* p, std::size_t n, PatternTiming& out) {
  if (n < kShapeHeadSize) return false;
  const std::size_t phases = p[12];
  if (phases == 0 || phases > kMaxPhases || n != kShapeHeadSize + 4 * phases) return false;
  PatternTiming t;
  t.period_us = get_u32(p);
  t.phase_us = get_u32(p + 4);
  t.max_pulses = get_u32(p + 8);
  t.width_us = t.interphase_us = t.balance_width_us = 0;
  t.shape.n = static_cast<std::uint8_t>(phases);
  for (std::size_t k = 0; k < phases; ++k) {
    t.shape.duration_us[k] = get_u16(p + kShapeHeadSize + 4 * k);
    t.shape.units[k] = static_cast<std::int16_t>(get_u16(p + kShapeHeadSize + 4 * k + 2));
  }
  out = t;
  return true;
}

bool phase_fits(const PatternTiming& t, const Capabilities& caps) {
  // A shape's phases, gaps included, are each at least min_width (check_shape).
  if (!t.shaped() && t.interphase_us != 0 && t.interphase_us < caps.min_width_us) return false;
  const std::uint64_t length = t.length_us();
  return t.period_us > length && t.period_us - length >= caps.min_width_us;
}

PatternTiming timing_of(const PulseConfig& c) {
  PatternTiming t;
  t.period_us = c.period_us;
  t.phase_us = 0;
  t.width_us = c.width_us;
  t.interphase_us = c.interphase_us;
  t.balance_width_us = c.balance_width_us;
  t.max_pulses = c.max_pulses;
  return t;
}

std::optional<PatternTiming> decode_timing(const std::uint8_t* p, std::size_t n) {
  if (n != kTimingSize) return std::nullopt;
  PatternTiming t;
  t.period_us = get_u32(p);
  t.phase_us = get_u32(p + 4);
  t.width_us = get_u16(p + 8);
  t.interphase_us = get_u16(p + 10);
  t.balance_width_us = get_u16(p + 12);
  t.max_pulses = get_u32(p + 14);
  return t;
}

bool decode_sparse(const std::uint8_t* p, std::size_t n, SparseCodes& out) {
  if (n == 0 || p[0] > kMaxChannels || n != 1 + 3 * std::size_t{p[0]}) return false;
  out.count = p[0];
  for (std::size_t i = 0; i < out.count; ++i) {
    out.channel[i] = p[1 + 3 * i];
    out.code[i] = static_cast<std::int16_t>(get_u16(p + 2 + 3 * i));
    if (i > 0 && out.channel[i] <= out.channel[i - 1]) return false;
  }
  return true;
}

void scale_codes(const std::int16_t* in, std::size_t n, std::uint16_t scale, std::int16_t* out) {
  std::int32_t rem[kMaxChannels] = {};
  std::int32_t sum = 0;
  n = std::min<std::size_t>(n, kMaxChannels);
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t exact = std::int32_t{in[i]} * scale;  // in units of 1/kFullScale
    const std::int32_t q = exact / kFullScale;               // toward zero
    rem[i] = exact - q * kFullScale;                         // same sign as exact
    out[i] = static_cast<std::int16_t>(q);
    sum += q;
  }
  // The exact values sum to zero (the inputs do): -sum codes move away from zero, on the
  // side that makes up the difference, where the remainders are largest.
  const int dir = sum < 0 ? 1 : -1;
  for (std::int32_t k = sum < 0 ? -sum : sum; k > 0; --k) {
    std::size_t best = n;
    for (std::size_t i = 0; i < n; ++i)
      if (rem[i] * dir > 0 && (best == n || rem[i] * dir > rem[best] * dir)) best = i;
    if (best == n) break;
    out[best] = static_cast<std::int16_t>(out[best] + dir);
    rem[best] = 0;
  }
}

namespace {
// The largest balancing code balance_codes can give a main code of magnitude a.
std::uint64_t balance_bound(std::uint64_t a, const PatternTiming& t) {
  const std::uint64_t bw = t.balance_width_us == 0 ? 1 : t.balance_width_us;
  return (a * t.width_us + bw - 1) / bw;
}
}  // namespace

namespace {
// A share too large to count: above every bound (ChannelLoad::first_over's limits are below
// 2^57).  The device never keeps one (it refuses such codes before their load), so the
// one a trial sum may hold does not wrap it.
constexpr std::uint64_t kOverQ16 = std::uint64_t{1} << 62;

// ceil(e x 2^16 / period), without overflow: kOverQ16 when it would be that large.
std::uint64_t q16_up(std::uint64_t e, std::uint32_t period) {
  const std::uint64_t q = e / period, r = e % period;
  if (q >= (std::uint64_t{1} << 46)) return kOverQ16;
  return (q << 16) + ((r << 16) + period - 1) / period;
}

// A shaped pattern's share: sum over its phases of (a |u_k|)^power x d_k (power 1 or 2).
// Each a |u_k| <= 32768 (else kOverQ16): terms below 2^46, sums below 2^50.
std::uint64_t shaped_share(std::uint32_t a, const PatternTiming& t, int power) {
  if (std::uint64_t{a} * static_cast<std::uint32_t>(t.max_units()) > 32768u) return kOverQ16;
  std::uint64_t e = 0;
  for (std::size_t k = 0; k < t.shape.n && k < kMaxPhases; ++k) {
    const std::uint64_t c = std::uint64_t{a} * static_cast<std::uint32_t>(
                                                    std::abs(std::int32_t{t.shape.units[k]}));
    e += (power == 2 ? c * c : c) * t.shape.duration_us[k];
  }
  return q16_up(e, t.period_us);
}
}  // namespace

// a <= 32768, widths <= 65535, and bw >= w (check_timing; the host's check_stimulus), so
// b <= a: a^2 w + b^2 bw < 2^47, shifted by 16 < 2^63.
std::uint64_t ChannelLoad::ms_share(std::uint32_t a, const PatternTiming& t) {
  if (t.period_us == 0) return 0;
  if (t.shaped()) return shaped_share(a, t, 2);
  const std::uint64_t b = balance_bound(a, t);
  const std::uint64_t e = std::uint64_t{a} * a * t.width_us + b * b * t.balance_width_us;
  return ((e << 16) + t.period_us - 1) / t.period_us;
}

std::uint64_t ChannelLoad::mean_share(std::uint32_t a, const PatternTiming& t) {
  if (t.period_us == 0) return 0;
  if (t.shaped()) return shaped_share(a, t, 1);
  const std::uint64_t b = balance_bound(a, t);
  const std::uint64_t q = std::uint64_t{a} * t.width_us + b * t.balance_width_us;
  return ((q << 16) + t.period_us - 1) / t.period_us;
}

void ChannelLoad::add(const std::uint8_t* channel, const std::int16_t* code, std::size_t n,
                      const PatternTiming& t, int sign) {
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t ch = channel[k];
    if (ch >= kMaxChannels) continue;
    const auto a = static_cast<std::uint32_t>(code[k] < 0 ? -std::int32_t{code[k]} : code[k]);
    const std::uint64_t ms = ms_share(a, t), mean = mean_share(a, t);
    if (sign > 0) {
      ms_q16[ch] += ms;
      mean_q16[ch] += mean;
    } else {
      ms_q16[ch] -= ms;
      mean_q16[ch] -= mean;
    }
  }
}

std::size_t ChannelLoad::first_over(const Capabilities& caps) const {
  const std::uint64_t step = caps.dac_step_nA == 0 ? 1 : caps.dac_step_nA;
  // Never above the compile-time bounds, whatever a device reports (and no overflow below).
  const std::uint64_t rms = std::uint64_t{std::min(caps.max_rms_uA, hard::max_rms_uA)} * 1000u;
  // In codes^2 and codes, x 2^16: (R / step)^2 and M / step, rounded down.
  const std::uint64_t ms_limit = (rms * rms << 16) / (step * step);
  const std::uint64_t mean_limit =
      (std::uint64_t{std::min(caps.max_mean_uA, hard::max_mean_uA)} * 1000u << 16) / step;
  for (std::size_t i = 0; i < kMaxChannels; ++i)
    if (ms_q16[i] > ms_limit || mean_q16[i] > mean_limit) return i;
  return kMaxChannels;
}

bool phase_fits(const PulseConfig& c, const Capabilities& caps) {
  if (c.interphase_us != 0 && c.interphase_us < caps.min_width_us) return false;
  const std::uint64_t length = std::uint64_t{c.width_us} + c.interphase_us + c.balance_width_us;
  return c.period_us > length && c.period_us - length >= caps.min_width_us;
}

std::uint64_t pulse_rate_mHz(const PatternTiming* t, std::size_t n) {
  std::uint64_t sum = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (t[i].period_us != 0) sum += (1000000000ull + t[i].period_us - 1) / t[i].period_us;
  return sum;
}

std::uint64_t edge_rate_mHz(const PatternTiming* t, std::size_t n) {
  std::uint64_t sum = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (t[i].period_us != 0)
      sum += (1000000000ull + t[i].period_us - 1) / t[i].period_us * t[i].edges();
  return sum;
}

Capabilities within_hard_limits(Capabilities c) {
  c.protocol = kProtocolVersion;
  c.channels = static_cast<std::uint8_t>(std::clamp<std::size_t>(c.channels, 1, kMaxChannels));
  c.max_current_uA = std::min(c.max_current_uA, hard::max_current_uA);
  c.dac_step_nA = std::max<std::uint16_t>(c.dac_step_nA, 1);
  c.min_width_us = std::max(c.min_width_us, hard::min_width_us);
  c.max_width_us = std::min(c.max_width_us, hard::max_width_us);
  c.max_balance_width_us = std::min(c.max_balance_width_us, hard::max_balance_width_us);
  c.max_rate_hz = std::clamp<std::uint16_t>(c.max_rate_hz, 1, hard::max_rate_hz);
  c.watchdog_ms = std::clamp(c.watchdog_ms, hard::min_watchdog_ms, hard::max_watchdog_ms);
  c.max_patterns = std::clamp<std::uint16_t>(c.max_patterns, 1, kMaxPatterns);
  c.code_pool = std::min(c.code_pool, static_cast<std::uint16_t>(kCodePool));
  c.min_gap_us = std::max(c.min_gap_us, hard::min_gap_us);
  c.max_slip_us = std::min(c.max_slip_us, hard::max_slip_us);
  c.max_rms_uA = std::min(c.max_rms_uA, hard::max_rms_uA);
  c.max_mean_uA = std::min(c.max_mean_uA, hard::max_mean_uA);
  c.max_pulse_rate_hz = std::clamp<std::uint16_t>(c.max_pulse_rate_hz, 1, hard::max_pulse_rate_hz);
  c.max_phases = static_cast<std::uint8_t>(std::min<std::size_t>(c.max_phases, kMaxPhases));
  c.features &= kFeatureShapedPulses | kFeatureMeasures;  // only the features this code knows
  c.max_edge_rate_hz = std::clamp<std::uint32_t>(c.max_edge_rate_hz, 1, hard::max_edge_rate_hz);
  return c;
}

std::optional<PulseConfig> decode_config(const std::uint8_t* p, std::size_t n) {
  if (n != kConfigSize) return std::nullopt;
  PulseConfig c;
  c.period_us = get_u32(p);
  c.width_us = get_u16(p + 4);
  c.interphase_us = get_u16(p + 6);
  c.balance_width_us = get_u16(p + 8);
  c.channels = p[10];
  c.max_pulses = get_u32(p + 11);
  return c;
}

bool decode_codes(const std::uint8_t* p, std::size_t n, Codes& out) {
  if (n == 0 || p[0] > kMaxChannels || n != 1 + 2 * std::size_t{p[0]}) return false;
  out.count = p[0];
  for (std::size_t i = 0; i < out.count; ++i)
    out.code[i] = static_cast<std::int16_t>(get_u16(p + 1 + 2 * i));
  return true;
}

std::uint32_t dac_step_nA(std::uint16_t max_current_uA, int dac_bits) {
  if (dac_bits < 2 || dac_bits > 16) return 0;
  const std::uint64_t codes = (std::uint64_t{1} << (dac_bits - 1)) - 1;
  const std::uint64_t na = std::uint64_t{max_current_uA} * 1000u;
  // round(na / codes), halves away from zero, in integers
  std::uint64_t step = std::max<std::uint64_t>(1, (2 * na + codes) / (2 * codes));
  if (na / step > codes) step = (na + codes - 1) / codes;
  return step > 65535 ? 0 : static_cast<std::uint32_t>(step);
}

}  // namespace tp::device
