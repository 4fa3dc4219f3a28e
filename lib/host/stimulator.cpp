#include "host/stimulator.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <numeric>
#include <string>

#include <sys/random.h>

#include "core/error.hpp"
#include "core/number.hpp"
#include "pulse/shape.hpp"

namespace tp::host {
namespace {
std::int64_t now_ns() {
  return monotonic_ns();
}
const char* msg_name(device::Msg m) {
  switch (m) {
    case device::Msg::identify:
      return "identify";
    case device::Msg::configure:
      return "configure";
    case device::Msg::set_weights:
      return "set-weights";
    case device::Msg::start:
      return "start";
    case device::Msg::stop:
      return "stop";
    case device::Msg::status:
      return "status";
    case device::Msg::keepalive:
      return "keep-alive";
    case device::Msg::configure_table:
      return "configure-table";
    case device::Msg::set_pattern:
      return "set-pattern";
    case device::Msg::set_codes:
      return "set-codes";
    case device::Msg::set_amplitudes:
      return "set-amplitudes";
    case device::Msg::set_shape:
      return "set-shape";
    case device::Msg::set_guards:
      return "set-guards";
    case device::Msg::set_hold:
      return "set-hold";
    case device::Msg::measurements:
      return "measurements";
    default:
      return "message";
  }
}
}  // namespace

StimulatorClient::Reply StimulatorClient::exchange(device::Msg type,
                                                   const std::vector<std::uint8_t>& payload) {
  const std::uint8_t seq = ++seq_;
  std::vector<std::uint8_t> bytes;
  device::encode_frame(device::Frame{seq, static_cast<std::uint8_t>(type), payload}, bytes);
  std::uint8_t buf[512];
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    if (attempt == 0)
      last_write_ns_ = now_ns();
    else
      ++retransmissions_;
    t_.write(bytes.data(), bytes.size());
    const std::int64_t deadline = now_ns() + std::int64_t{kAckTimeoutMs} * 1000000;
    while (true) {
      const std::int64_t left_ms = (deadline - now_ns()) / 1000000;
      if (left_ms < 0) break;
      const std::size_t n =
          t_.read(buf, sizeof buf, static_cast<int>(std::max<std::int64_t>(left_ms, 1)));
      for (std::size_t i = 0; i < n; ++i) {
        if (!decoder_.push(buf[i])) continue;
        const device::RxFrame& f = decoder_.frame();
        // Only the acknowledgement of this request counts; stale ones are ignored.
        if (f.type != static_cast<std::uint8_t>(device::Msg::ack) || f.seq != seq ||
            f.payload.size() < 2 || f.payload[0] != static_cast<std::uint8_t>(type))
          continue;
        return Reply{static_cast<device::Result>(f.payload[1]),
                     std::vector<std::uint8_t>(f.payload.begin() + 2, f.payload.end())};
      }
    }
  }
  failure(std::string("device not responding on ") + t_.name() + " (no acknowledgement of " +
          msg_name(type) + " after " + std::to_string(kAttempts) + " attempts)");
}

std::vector<std::uint8_t> StimulatorClient::request(device::Msg type,
                                                    const std::vector<std::uint8_t>& payload) {
  Reply r = exchange(type, payload);
  if (r.result != device::Result::ok)
    failure(std::string("device refused ") + msg_name(type) + ": " + device::to_string(r.result));
  return std::move(r.body);
}

device::Capabilities StimulatorClient::identify() {
  const Reply r = exchange(device::Msg::identify, {});
  if (r.result != device::Result::ok)
    failure(std::string("device refused identify: ") + device::to_string(r.result));
  // Version 5 devices too: their capabilities decode with no shaped pulses.
  if (r.body.empty() || r.body[0] < device::kOldestProtocolVersion ||
      r.body[0] > device::kProtocolVersion)
    failure("device speaks protocol version " + (r.body.empty() ? "?" : std::to_string(r.body[0])) +
            "; stimctl speaks versions " + std::to_string(device::kOldestProtocolVersion) + " to " +
            std::to_string(device::kProtocolVersion));
  const auto caps = device::decode_capabilities(r.body, 0);
  if (!caps) failure("device sent malformed capabilities");
  return *caps;
}
void StimulatorClient::configure(const device::PulseConfig& c) {
  const std::uint32_t token = new_session_token();
  request(device::Msg::configure, device::with_session(token, device::encode(c)));
  session_ = token;
}
void StimulatorClient::set_weights(const std::vector<std::int16_t>& codes) {
  request(device::Msg::set_weights, device::with_session(session_, device::encode_weights(codes)));
}
void StimulatorClient::configure_table(std::uint16_t patterns, std::uint8_t channels,
                                       std::uint16_t gap_us) {
  const std::uint32_t token = new_session_token();
  std::vector<std::uint8_t> b;
  device::put_u16(b, patterns);
  b.push_back(channels);
  device::put_u16(b, gap_us);
  request(device::Msg::configure_table, device::with_session(token, b));
  session_ = token;
}
void StimulatorClient::set_pattern(std::uint16_t index, const device::PatternTiming& t) {
  std::vector<std::uint8_t> b;
  device::put_u16(b, index);
  device::put_timing(b, t);
  request(device::Msg::set_pattern, device::with_session(session_, b));
}
void StimulatorClient::set_shape(std::uint16_t index, const device::PatternTiming& t) {
  std::vector<std::uint8_t> b;
  device::put_u16(b, index);
  device::put_shape_pattern(b, t);
  request(device::Msg::set_shape, device::with_session(session_, b));
}
void StimulatorClient::set_hold(std::uint16_t index, std::uint64_t energy_ref) {
  std::vector<std::uint8_t> b;
  device::put_u16(b, index);
  device::put_u32(b, static_cast<std::uint32_t>(energy_ref & 0xFFFFFFFFu));
  device::put_u32(b, static_cast<std::uint32_t>(energy_ref >> 32));
  request(device::Msg::set_hold, device::with_session(session_, b));
}
void StimulatorClient::set_guards(const device::Guards& g) {
  request(device::Msg::set_guards, device::with_session(session_, device::encode(g)));
}
device::Measurements StimulatorClient::measurements(std::size_t channels) {
  device::Measurements all;
  for (std::size_t first = 0; first < channels || first == 0;) {
    const auto n = static_cast<std::uint8_t>(
        std::min(channels - first, device::kMeasurementsPerReply));
    const auto body = request(device::Msg::measurements,
                              {static_cast<std::uint8_t>(first), n});
    const auto page = device::decode_measurements(body, 0);
    if (!page || page->head.first != first || page->head.n != n)
      failure("device sent malformed measurements");
    all.head = page->head;
    all.channels.insert(all.channels.end(), page->channels.begin(), page->channels.end());
    first += n;
    if (n == 0) break;
  }
  all.head.first = 0;
  all.head.n = static_cast<std::uint8_t>(all.channels.size());
  return all;
}
void StimulatorClient::set_codes(std::uint16_t index, const std::vector<std::int16_t>& dense) {
  std::vector<std::uint8_t> b;
  device::put_u16(b, index);
  const auto sparse = device::encode_sparse(dense);
  b.insert(b.end(), sparse.begin(), sparse.end());
  request(device::Msg::set_codes, device::with_session(session_, b));
}
std::vector<std::uint8_t> StimulatorClient::amplitudes_payload(
    const std::vector<std::uint16_t>& scales, std::size_t first) {
  // At most 96 a frame (the payload's 200 bytes): a long table in several frames.
  const std::size_t n = std::min<std::size_t>(96, scales.size() - first);
  std::vector<std::uint8_t> b;
  device::put_u16(b, static_cast<std::uint16_t>(first));
  b.push_back(static_cast<std::uint8_t>(n));
  for (std::size_t k = 0; k < n; ++k) device::put_u16(b, scales[first + k]);
  return b;
}
void StimulatorClient::set_amplitudes(const std::vector<std::uint16_t>& scales) {
  for (std::size_t first = 0; first < scales.size(); first += 96)
    request(device::Msg::set_amplitudes,
            device::with_session(session_, amplitudes_payload(scales, first)));
}
bool StimulatorClient::session_request(device::Msg type, const std::vector<std::uint8_t>& payload) {
  const Reply r = exchange(type, payload);
  if (r.result == device::Result::wrong_session) return false;
  if (r.result != device::Result::ok)
    failure(std::string("device refused ") + msg_name(type) + ": " + device::to_string(r.result));
  return true;
}
bool StimulatorClient::set_weights_live(const std::vector<std::int16_t>& codes) {
  return session_request(device::Msg::set_weights,
                         device::with_session(session_, device::encode_weights(codes)));
}
bool StimulatorClient::set_amplitudes_live(const std::vector<std::uint16_t>& scales) {
  for (std::size_t first = 0; first < scales.size(); first += 96)
    if (!session_request(device::Msg::set_amplitudes,
                         device::with_session(session_, amplitudes_payload(scales, first))))
      return false;
  return true;
}
void StimulatorClient::start() {
  request(device::Msg::start, device::with_session(session_, {}));
}
void StimulatorClient::stop() {
  request(device::Msg::stop, device::with_session(session_, {}));
  session_ = 0;
}
device::Status StimulatorClient::keepalive() {
  const Reply r = exchange(device::Msg::keepalive, device::with_session(session_, {}));
  if (r.result == device::Result::wrong_session) {  // the device ended our session
    const device::Status s = status();
    if (s.state == device::State::running)
      failure("the device is running another session's output: ours was taken over");
    return s;
  }
  if (r.result != device::Result::ok)
    failure(std::string("device refused keep-alive: ") + device::to_string(r.result));
  const auto s = device::decode_status(r.body, 0);
  if (!s) failure("device sent a malformed status");
  return *s;
}
device::Status StimulatorClient::status() {
  const auto body = request(device::Msg::status, {});
  const auto s = device::decode_status(body, 0);
  if (!s) failure("device sent a malformed status");
  return *s;
}

std::uint32_t new_session_token() {
  std::uint32_t t = 0;
  while (t == 0) {
    if (::getrandom(&t, sizeof t, 0) != static_cast<ssize_t>(sizeof t))
      failure(std::string("no random session token: ") + std::strerror(errno));
  }
  return t;
}

std::int32_t limit_code(double limit_mA, const device::Capabilities& caps) {
  const std::int32_t max_code = caps.max_code();
  if (!(limit_mA >= 0.0) || caps.dac_step_nA == 0) return 0;
  const double step_mA = caps.dac_step_nA * 1e-6;
  if (limit_mA >= static_cast<double>(max_code) * step_mA) return max_code;
  // The largest whole code whose current is within the limit: floor, then checked
  // against the limit itself (a quotient that lands a hair above a whole number).
  auto code = static_cast<std::int32_t>(std::floor(limit_mA / step_mA));
  while (code > 0 && static_cast<double>(code) * step_mA > limit_mA) --code;
  return std::min(code, max_code);
}

std::vector<std::int16_t> quantize_currents(const std::vector<double>& currents_mA,
                                            const device::Capabilities& caps, double limit_mA) {
  const double step_mA = caps.dac_step_nA * 1e-6;
  const long max_code = caps.max_code();
  const long lim_code = limit_code(limit_mA, caps);
  const double lim_mA = std::min(limit_mA, static_cast<double>(max_code) * step_mA);
  std::vector<std::int16_t> codes;
  std::vector<double> err;  // exact - quantised, in codes
  long sum = 0;
  for (double c : currents_mA) {
    const double exact = c / step_mA;
    // Range first, then the conversion: lround of a huge or non-finite value is undefined.
    if (!(std::fabs(exact) <= static_cast<double>(max_code) + 0.5) ||
        std::labs(std::lround(exact)) > max_code)
      bad_input("current " +
                number_beside(c, (c < 0 ? -1.0 : 1.0) * static_cast<double>(max_code) * step_mA) +
                " mA exceeds the device's limit of " +
                number_text(static_cast<double>(max_code) * step_mA) + " mA (" +
                std::to_string(max_code) + " DAC steps of " + std::to_string(caps.dac_step_nA) +
                " nA)");
    // Against the limit in force itself: the device's largest code (which may lie a hair
    // below it, 2047 x 977 nA = 1.999919 mA) caps the code below, it does not refuse.
    if (!(std::fabs(c) <= limit_mA + 1e-12))
      bad_input("current " + number_beside(c, c < 0 ? -limit_mA : limit_mA) +
                " mA exceeds the limit of " + number_text(limit_mA) + " mA");
    // The nearest code, or the next one toward zero where the nearest would cross the
    // limit: no code is ever above the limit.
    long code = std::lround(exact);
    if (std::labs(code) > lim_code) code = static_cast<long>(std::trunc(exact));
    if (std::labs(code) > lim_code) code = code > 0 ? lim_code : -lim_code;
    codes.push_back(static_cast<std::int16_t>(code));
    err.push_back(exact - static_cast<double>(code));
    sum += code;
  }
  // Move the sum to zero one code at a time, where quantising erred most in that
  // direction, never taking a code beyond the limit.
  std::vector<std::size_t> order(codes.size());
  while (sum != 0) {
    const int dir = sum > 0 ? -1 : 1;
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return dir * err[a] > dir * err[b]; });
    bool moved = false;
    for (std::size_t i : order) {
      if (std::abs(codes[i] + dir) > lim_code) continue;
      codes[i] = static_cast<std::int16_t>(codes[i] + dir);
      err[i] -= dir;
      sum += dir;
      moved = true;
      break;
    }
    if (!moved)
      bad_input("currents cannot be made to sum to zero within the limit of " +
                number_text(lim_mA) + " mA");
  }
  // Currents asked for, none delivered: every one is below what the DAC can make within
  // the limit (a limit under one step, or currents under half a step).
  const bool asked =
      std::any_of(currents_mA.begin(), currents_mA.end(), [](double c) { return c != 0.0; });
  const bool any = std::any_of(codes.begin(), codes.end(), [](std::int16_t k) { return k != 0; });
  if (asked && !any)
    bad_input("every current rounds to 0 DAC codes (one step is " +
              number_text(caps.dac_step_nA * 1e-6) + " mA, the limit " + number_text(lim_mA) +
              " mA): nothing would be delivered");
  return codes;
}

std::vector<std::int16_t> pattern_codes(const Stimulus& s, const device::Capabilities& caps,
                                        double limit_mA) {
  if (!s.shape.shaped()) return quantize_currents(s.currents_mA, caps, limit_mA);
  const ShapeUnits u = shape_units(s.shape.phases);
  int max_units = 1;
  for (int v : u.units) max_units = std::max(max_units, std::abs(v));
  std::vector<double> unit_mA;
  for (double c : s.currents_mA) unit_mA.push_back(c / u.unit);
  return quantize_currents(unit_mA, caps, limit_mA / max_units);
}

Stimulus delivered_stimulus(const Stimulus& s, const std::vector<std::int16_t>& codes,
                            const device::Capabilities& caps) {
  Stimulus d = s;
  const double step_mA = caps.dac_step_nA * 1e-6;
  const double unit = s.shape.shaped() ? shape_units(s.shape.phases).unit : 1;
  for (std::size_t i = 0; i < d.currents_mA.size() && i < codes.size(); ++i)
    d.currents_mA[i] = static_cast<double>(codes[i]) * unit * step_mA;
  return d;
}

}  // namespace tp::host
