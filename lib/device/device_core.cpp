#include "device/device_core.hpp"

#include <algorithm>
#include <cstdlib>
#include <limits>

namespace tp::device {
namespace {

bool carries_session(Msg m) {
  return m == Msg::configure || m == Msg::set_weights || m == Msg::start || m == Msg::keepalive;
}

// Whether sequence number a comes after b: ahead by 1 to 127, modulo 256 (RFC 1982's
// serial-number arithmetic for 8 bits).
bool seq_after(std::uint8_t a, std::uint8_t b) {
  const auto d = static_cast<std::uint8_t>(a - b);
  return d != 0 && d < 128;
}

std::uint16_t saturate16(std::uint32_t v) {
  return static_cast<std::uint16_t>(std::min<std::uint32_t>(v, 0xFFFF));
}

}  // namespace

bool DeviceCore::of_session(const RxFrame& f) const {
  const auto m = static_cast<Msg>(f.type);
  return session_ != 0 && m != Msg::configure && carries_session(m) && f.payload.size() >= 4 &&
         get_u32(f.payload.data()) == session_;
}

void DeviceCore::end_session() {
  if (status_.state == State::running) {
    status_.fault = Fault::stopped;
    ++output_ends_;
  }
  status_.state = State::idle;
  session_ = 0;
  configured_ = false;
  weights_set_ = false;
}

bool DeviceCore::receive_byte(std::uint8_t byte, std::uint64_t now_us) {
  const bool complete = decoder_.push(byte);
  status_.rx_errors = saturate16(decoder_.errors());
  if (!complete) return false;
  const RxFrame& f = decoder_.frame();
  // A session whose watchdog has run out is over, even if nothing advanced the clock in
  // between: a late frame must not revive it.
  expire(now_us);
  // A repeated frame (a retransmission, or the same bytes replayed) is answered again
  // from the cache and neither executed nor allowed to feed the watchdog: only a new
  // frame shows that the host is alive.  (A retransmission follows a first copy that was
  // lost, so was never seen, or that arrived, and fed the watchdog then.)
  if (have_last_ && f.same_as(last_request_)) return true;
  // Only the running session's own frames keep its output alive: a host that did not
  // start the output (or identify/status queries) can never hold it on.  And only a frame
  // newer than the last one that fed it (its seq ahead, modulo 256, by 1 to 127): an
  // older frame of the session replayed (two keep-alives in turn) feeds nothing.
  if (status_.state == State::running && of_session(f) && seq_after(f.seq, fed_seq_)) {
    last_fed_us_ = now_us;
    fed_seq_ = f.seq;
  }
  FixedBytes<kMaxPayload> body;
  handle(f, now_us, body);
  last_reply_.clear();
  encode_frame_to(f.seq, static_cast<std::uint8_t>(Msg::ack), body.data(), body.size(),
                  [this](std::uint8_t b) { last_reply_.push_back(b); });
  last_request_ = f;
  have_last_ = true;
  return true;
}

void DeviceCore::handle(const RxFrame& f, std::uint64_t now_us, FixedBytes<kMaxPayload>& body) {
  body.clear();
  body.push_back(f.type);
  body.push_back(static_cast<std::uint8_t>(Result::ok));
  auto result = [&](Result r) {
    body.clear();
    body.push_back(f.type);
    body.push_back(static_cast<std::uint8_t>(r));
  };
  const auto type = static_cast<Msg>(f.type);
  if (type != Msg::configure && carries_session(type)) {
    if (f.payload.size() < 4) return result(Result::bad_length);
    if (!of_session(f)) return result(Result::wrong_session);
  }
  switch (type) {
    case Msg::identify:
      if (!f.payload.empty()) return result(Result::bad_length);
      put_capabilities(body, caps_);
      return;
    case Msg::configure:
      return result(configure(f.payload));
    case Msg::set_weights:
      return result(set_weights(f.payload));
    case Msg::start:
      if (f.payload.size() != 4) return result(Result::bad_length);
      if (!configured_ || !weights_set_) return result(Result::not_configured);
      if (status_.state != State::running) {
        status_.state = State::running;
        status_.fault = Fault::none;
        status_.pulses = 0;
        start_us_ = next_pulse_us_ = last_fed_us_ = now_us;
        fed_seq_ = f.seq;
      }
      return;
    case Msg::stop:
      end_session();  // always honoured, whatever the payload; disarms
      return;
    case Msg::status:
      if (!f.payload.empty()) return result(Result::bad_length);
      put_status(body, status_);
      return;
    case Msg::keepalive:
      if (f.payload.size() != 4) return result(Result::bad_length);
      put_status(body, status_);
      return;
    default:
      return result(Result::unknown_type);
  }
}

Result DeviceCore::configure(const FixedBytes<kMaxPayload>& payload) {
  if (payload.size() != 4 + kConfigSize) return Result::bad_length;
  if (status_.state == State::running || faulted_) return Result::bad_state;
  const std::uint32_t session = get_u32(payload.data());
  if (session == 0) return Result::wrong_session;
  const auto c = decode_config(payload.data() + 4, payload.size() - 4);
  if (!c) return Result::bad_length;
  if (c->channels == 0 || c->channels > caps_.channels) return Result::channel_mismatch;
  if (c->width_us < caps_.min_width_us || c->width_us > caps_.max_width_us)
    return Result::out_of_range;
  if (c->balance_width_us < c->width_us || c->balance_width_us > caps_.max_balance_width_us)
    return Result::out_of_range;
  if (c->interphase_us > caps_.max_width_us) return Result::out_of_range;
  const std::uint32_t length = std::uint32_t{c->width_us} + c->interphase_us + c->balance_width_us;
  const std::uint32_t min_period = (1000000u + caps_.max_rate_hz - 1) / caps_.max_rate_hz;
  if (c->period_us <= length || c->period_us < min_period || c->period_us > hard::max_period_us)
    return Result::out_of_range;
  // Every stretch between two edges is at least the shortest phase (min_width_us): a gap,
  // if there is one, and the time from a pulse's end to the next one's start.  The output
  // stage loads the next phase's codes in it; shorter, a pulse would come late.
  if (!phase_fits(*c, caps_)) return Result::out_of_range;
  config_ = *c;
  session_ = session;  // a new session: weights must be sent again
  configured_ = true;
  weights_set_ = false;
  return Result::ok;
}

Result DeviceCore::set_weights(const FixedBytes<kMaxPayload>& payload) {
  if (!configured_) return Result::not_configured;
  Codes codes;
  if (!decode_codes(payload.data() + 4, payload.size() - 4, codes)) return Result::bad_length;
  if (codes.count != config_.channels) return Result::channel_mismatch;
  const std::int32_t max = caps_.max_code();
  std::int32_t sum = 0;  // at most 64 codes of 16 bits: no overflow
  for (std::int16_t c : codes) {
    if (std::abs(std::int32_t{c}) > max) return Result::out_of_range;
    sum += c;
  }
  if (sum != 0) return Result::sum_not_zero;
  weights_ = codes;  // applied from the next pulse on
  weights_set_ = true;
  ++status_.weight_updates;
  return Result::ok;
}

std::uint64_t DeviceCore::deadline_us() const {
  return last_fed_us_ + std::uint64_t{caps_.watchdog_ms} * 1000u;
}

void DeviceCore::expire(std::uint64_t now_us) {
  if (status_.state == State::running && now_us >= deadline_us()) {
    end_session();
    status_.fault = Fault::watchdog;
  }
}

bool DeviceCore::begin_advance(std::uint64_t now_us) {
  if (status_.state != State::running) return false;
  // Pulses never come in a burst to catch up: slots more than kMaxLateUs in the past are
  // skipped (not delivered, not counted).  A timer-driven firmware is never that late.
  if (now_us > next_pulse_us_ + kMaxLateUs) {
    const std::uint64_t late = now_us - kMaxLateUs - next_pulse_us_;
    next_pulse_us_ += (late / config_.period_us + 1) * config_.period_us;
  }
  return true;
}

bool DeviceCore::pulse_due(std::uint64_t now_us) const {
  return status_.state == State::running && next_pulse_us_ <= now_us &&
         next_pulse_us_ < deadline_us();
}

void DeviceCore::pulse_delivered() {
  ++status_.pulses;
  next_pulse_us_ += config_.period_us;
  if (config_.max_pulses != 0 && status_.pulses >= config_.max_pulses) {
    end_session();
    status_.fault = Fault::completed;
  }
}

void DeviceCore::not_delivered(std::uint64_t start_us, std::uint32_t n) {
  if (start_us != start_us_) return;  // an earlier output's: its count is final
  status_.pulses -= std::min(n, status_.pulses);
}

void DeviceCore::output_fault() {
  const bool was_running = status_.state == State::running;
  end_session();
  faulted_ = true;
  status_.fault = Fault::output_fault;
  if (!was_running) ++output_ends_;  // the stage must stop even if nothing ran
}

void DeviceCore::link_lost() {
  const bool was_running = status_.state == State::running;
  end_session();
  if (was_running) status_.fault = Fault::link_lost;
}

std::uint64_t DeviceCore::next_event_us() const {
  if (status_.state != State::running) return std::numeric_limits<std::uint64_t>::max();
  return std::min(next_pulse_us_, deadline_us());
}

void DeviceCore::set_line_counts(std::uint32_t line_errors, std::uint32_t overruns) {
  status_.line_errors = saturate16(line_errors);
  status_.overruns = saturate16(overruns);
}

}  // namespace tp::device
