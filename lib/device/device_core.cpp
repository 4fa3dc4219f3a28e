#include "device/device_core.hpp"

#include <algorithm>
#include <cstdlib>
#include <limits>

namespace tp::device {
namespace {

bool carries_session(Msg m) {
  return m == Msg::configure || m == Msg::set_weights || m == Msg::start || m == Msg::keepalive ||
         m == Msg::configure_table || m == Msg::set_pattern || m == Msg::set_codes ||
         m == Msg::set_amplitudes || m == Msg::set_shape || m == Msg::set_guards ||
         m == Msg::set_hold;
}
bool opens_session(Msg m) {
  return m == Msg::configure || m == Msg::configure_table;
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
  return session_ != 0 && !opens_session(m) && carries_session(m) && f.payload.size() >= 4 &&
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
  patterns_ = 0;
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
  if (!opens_session(type) && carries_session(type)) {
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
    case Msg::configure_table:
      return result(configure_table(f.payload));
    case Msg::set_weights:
      return result(set_weights(f.payload));
    case Msg::set_pattern:
      return result(set_pattern(f.payload));
    case Msg::set_codes:
      return result(set_codes(f.payload));
    case Msg::set_amplitudes:
      return result(set_amplitudes(f.payload));
    case Msg::set_shape:
      return result(set_shape(f.payload));
    case Msg::set_guards:
      return result(set_guards(f.payload));
    case Msg::set_hold:
      return result(set_hold(f.payload));
    case Msg::measurements: {
      const Result r = measurements(f.payload, body);
      if (r != Result::ok) result(r);
      return;
    }
    case Msg::start: {
      if (f.payload.size() != 4) return result(Result::bad_length);
      const bool was_running = status_.state == State::running;
      const Result r = start(now_us);
      if (r == Result::ok && !was_running) fed_seq_ = f.seq;
      return result(r);
    }
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

void DeviceCore::open_table(std::uint32_t session, std::uint16_t n, std::uint8_t channels,
                            std::uint16_t gap_us) {
  session_ = session;  // a new session: the table must be sent again
  configured_ = true;
  patterns_ = n;
  channels_ = channels;
  pool_used_ = 0;
  load_ = ChannelLoad{};
  for (std::uint16_t i = 0; i < n; ++i) {
    pattern_[i] = Pattern{};
    hold_ref_[i] = 0;
  }
  sched_.set_table(n, gap_us);
  guards_ = Guards{};  // a new session sets its own
  density_limit_uC2_ = 0;
}

Result DeviceCore::check_widths(const PatternTiming& t) const {
  if (t.shaped()) return check_shape(t.shape, caps_);  // its phases, and its charge
  if (t.width_us < caps_.min_width_us || t.width_us > caps_.max_width_us)
    return Result::out_of_range;
  if (t.balance_width_us < t.width_us || t.balance_width_us > caps_.max_balance_width_us)
    return Result::out_of_range;
  if (t.interphase_us > caps_.max_width_us) return Result::out_of_range;
  return Result::ok;
}

Result DeviceCore::check_timing(const PatternTiming& t) const {
  const Result widths = check_widths(t);
  if (widths != Result::ok) return widths;
  const std::uint32_t min_period = (1000000u + caps_.max_rate_hz - 1) / caps_.max_rate_hz;
  if (t.period_us <= t.length_us() || t.period_us < min_period ||
      t.period_us > hard::max_period_us || t.phase_us >= t.period_us)
    return Result::out_of_range;
  // Every stretch between two edges is at least the shortest phase (min_width_us): a gap,
  // if there is one, and the time from a pulse's end to the next one's start.  The output
  // stage loads the next phase's codes in it; shorter, a pulse would come late.
  if (!phase_fits(t, caps_)) return Result::out_of_range;
  return Result::ok;
}

void DeviceCore::load(std::uint16_t i, int sign) {
  const Pattern& p = pattern_[i];
  if (p.timing_set && p.codes_set)
    load_.add(pool_channel_ + p.first, pool_code_ + p.first, p.count, timing_[i], sign);
}

bool DeviceCore::peak_fits(std::uint16_t i, const PatternTiming& t) const {
  const Pattern& p = pattern_[i];
  if (!p.codes_set) return true;
  std::int32_t largest = 0;
  for (std::size_t k = 0; k < p.count; ++k)
    largest = std::max(largest, std::abs(std::int32_t{pool_code_[p.first + k]}));
  return largest * t.max_units() <= caps_.max_code();
}

Result DeviceCore::put_timing(std::uint16_t i, const PatternTiming& t) {
  const Result r = check_timing(t);
  if (r != Result::ok) return r;
  // The pattern's codes at this shape's strongest phase: within the largest code.
  if (!peak_fits(i, t)) return Result::out_of_range;
  const Pattern old = pattern_[i];
  const PatternTiming old_timing = timing_[i];
  load(i, -1);
  timing_[i] = t;
  pattern_[i].timing_set = true;
  sched_.set_timing(i, t.period_us, t.phase_us, t.length_us(), t.max_pulses);
  load(i, +1);
  // Across the table: the output stage's time (utilisation at most 1) and each
  // electrode's load.
  if (sched_.utilisation_q20() > Scheduler::kOneQ20 || !load_.within(caps_)) {
    load(i, -1);
    pattern_[i] = old;
    timing_[i] = old_timing;
    sched_.set_timing(i, old.timing_set ? old_timing.period_us : 0, old_timing.phase_us,
                      old_timing.length_us(), old_timing.max_pulses);
    load(i, +1);
    return Result::out_of_range;
  }
  return Result::ok;
}

Result DeviceCore::put_codes(std::uint16_t i, const SparseCodes& c, std::uint8_t reserve) {
  // Base codes of a shaped pattern: the peak is |code| x its largest units.
  const std::int32_t units = pattern_[i].timing_set ? timing_[i].max_units() : 1;
  const std::int32_t max = caps_.max_code() / (units > 0 ? units : 1);
  std::int32_t sum = 0;  // at most 64 codes of 16 bits: no overflow
  for (std::size_t k = 0; k < c.count; ++k) {
    if (c.channel[k] >= channels_) return Result::channel_mismatch;
    if (std::abs(std::int32_t{c.code[k]}) > max) return Result::out_of_range;
    sum += c.code[k];
  }
  if (sum != 0) return Result::sum_not_zero;
  // Across the table: each electrode's load with these codes in place of the old ones.
  ChannelLoad trial = load_;
  const Pattern& p = pattern_[i];
  if (p.timing_set) {
    if (p.codes_set)
      trial.add(pool_channel_ + p.first, pool_code_ + p.first, p.count, timing_[i], -1);
    trial.add(c.channel.data(), c.code.data(), c.count, timing_[i], +1);
    if (!trial.within(caps_)) return Result::out_of_range;
  }
  // Room: its own place when the codes fit it, else new room at the pool's end.
  Pattern next = p;
  if (c.count > p.room) {
    const auto room = static_cast<std::uint32_t>(c.count > reserve ? c.count : reserve);
    if (pool_used_ + room > caps_.code_pool) return Result::table_full;
    next.first = static_cast<std::uint16_t>(pool_used_);
    next.room = static_cast<std::uint8_t>(room);
    pool_used_ += room;
  }
  next.count = static_cast<std::uint8_t>(c.count);
  next.codes_set = true;
  next.scale = kFullScale;  // new codes are delivered as sent (a live weight frame's currents)
  for (std::size_t k = 0; k < c.count; ++k) {
    pool_channel_[next.first + k] = c.channel[k];
    pool_code_[next.first + k] = c.code[k];
  }
  pattern_[i] = next;
  hold_ref_[i] = 0;  // the held energy was of the old codes
  load_ = trial;
  ++status_.weight_updates;
  return Result::ok;
}

Result DeviceCore::configure(const FixedBytes<kMaxPayload>& payload) {
  if (payload.size() != 4 + kConfigSize) return Result::bad_length;
  if (status_.state == State::running || faulted_) return Result::bad_state;
  const std::uint32_t session = get_u32(payload.data());
  if (session == 0) return Result::wrong_session;
  const auto c = decode_config(payload.data() + 4, payload.size() - 4);
  if (!c) return Result::bad_length;
  if (c->channels == 0 || c->channels > caps_.channels) return Result::channel_mismatch;
  const PatternTiming t = timing_of(*c);
  const Result r = check_timing(t);
  if (r != Result::ok) return r;
  open_table(session, 1, c->channels, caps_.min_gap_us);
  return put_timing(0, t);
}

Result DeviceCore::configure_table(const FixedBytes<kMaxPayload>& payload) {
  if (payload.size() != 9) return Result::bad_length;
  if (status_.state == State::running || faulted_) return Result::bad_state;
  const std::uint32_t session = get_u32(payload.data());
  if (session == 0) return Result::wrong_session;
  const std::uint16_t n = get_u16(payload.data() + 4);
  const std::uint8_t channels = payload[6];
  const std::uint16_t gap = get_u16(payload.data() + 7);
  if (n == 0 || n > caps_.max_patterns) return Result::table_full;
  if (channels == 0 || channels > caps_.channels) return Result::channel_mismatch;
  // The gap is a stretch between two edges too: at least the shortest phase (phase_fits).
  if (gap < caps_.min_gap_us || gap < caps_.min_width_us || gap > caps_.max_slip_us)
    return Result::out_of_range;
  open_table(session, n, channels, gap);
  return Result::ok;
}

Result DeviceCore::set_pattern(const FixedBytes<kMaxPayload>& payload) {
  if (!configured_) return Result::not_configured;
  if (payload.size() != 6 + kTimingSize) return Result::bad_length;
  if (status_.state == State::running) return Result::bad_state;
  const std::uint16_t i = get_u16(payload.data() + 4);
  if (i >= patterns_) return Result::no_pattern;
  const auto t = decode_timing(payload.data() + 6, kTimingSize);
  if (!t) return Result::bad_length;
  return put_timing(i, *t);
}

Result DeviceCore::set_shape(const FixedBytes<kMaxPayload>& payload) {
  if (!configured_) return Result::not_configured;
  if (payload.size() < 6 + kShapeHeadSize) return Result::bad_length;
  if (status_.state == State::running) return Result::bad_state;
  const std::uint16_t i = get_u16(payload.data() + 4);
  PatternTiming t;
  if (!decode_shape_pattern(payload.data() + 6, payload.size() - 6, t)) return Result::bad_length;
  if (i >= patterns_) return Result::no_pattern;
  return put_timing(i, t);
}

Result DeviceCore::set_codes(const FixedBytes<kMaxPayload>& payload) {
  if (!configured_) return Result::not_configured;
  if (payload.size() < 7) return Result::bad_length;
  const std::uint16_t i = get_u16(payload.data() + 4);
  SparseCodes c;
  if (!decode_sparse(payload.data() + 6, payload.size() - 6, c)) return Result::bad_length;
  if (i >= patterns_) return Result::no_pattern;
  return put_codes(i, c, 0);
}

Result DeviceCore::set_weights(const FixedBytes<kMaxPayload>& payload) {
  if (!configured_) return Result::not_configured;
  Codes codes;
  if (!decode_codes(payload.data() + 4, payload.size() - 4, codes)) return Result::bad_length;
  if (codes.count != channels_) return Result::channel_mismatch;
  // Pattern 0's codes, dense: kept sparse in room for every channel, so that a live
  // stream of weights never runs the pool out.
  SparseCodes c;
  for (std::size_t k = 0; k < codes.count; ++k)
    if (codes[k] != 0) {
      c.channel[c.count] = static_cast<std::uint8_t>(k);
      c.code[c.count++] = codes[k];
    }
  return put_codes(0, c, channels_);  // applied from the next pulse on
}

Result DeviceCore::set_amplitudes(const FixedBytes<kMaxPayload>& payload) {
  if (!configured_) return Result::not_configured;
  if (payload.size() < 7) return Result::bad_length;
  const std::uint16_t first = get_u16(payload.data() + 4);
  const std::size_t n = payload[6];
  if (n == 0 || payload.size() != 7 + 2 * n) return Result::bad_length;
  if (std::size_t{first} + n > patterns_) return Result::no_pattern;
  for (std::size_t k = 0; k < n; ++k)
    if (get_u16(payload.data() + 7 + 2 * k) > kFullScale) return Result::out_of_range;
  // Only ever down from the codes as checked: applied from each pattern's next pulse.
  for (std::size_t k = 0; k < n; ++k)
    pattern_[first + k].scale = get_u16(payload.data() + 7 + 2 * k);
  ++status_.weight_updates;  // a live update, as set_weights is
  return Result::ok;
}

Result DeviceCore::start(std::uint64_t now_us) {
  if (!configured_) return Result::not_configured;
  for (std::uint16_t i = 0; i < patterns_; ++i)
    if (!pattern_[i].timing_set || !pattern_[i].codes_set) return Result::not_configured;
  if (status_.state == State::running) return Result::ok;
  // No more pulses a second than the device delivers on time (its measured throughput).
  if (!within_pulse_rate(pulse_rate_mHz(timing_, patterns_), caps_)) return Result::out_of_range;
  // Nor more edges a second (a shaped pulse's phases) than its output stage makes on time.
  if (!within_edge_rate(edge_rate_mHz(timing_, patterns_), caps_)) return Result::out_of_range;
  // The table's worst slip, from the closed bound or its exact schedule (scheduler.hpp).
  if (sched_.worst_slip(caps_.max_slip_us, kMaxCheckedPulses) > caps_.max_slip_us)
    return Result::out_of_range;
  status_.state = State::running;
  status_.fault = Fault::none;
  status_.pulses = 0;
  status_.max_slip_us = 0;
  status_.deferred = 0;
  start_us_ = last_fed_us_ = now_us;
  sched_.reset(now_us);
  for (ChannelMeasurement& m : reading_) m = ChannelMeasurement{};  // new readings, baselines
  readings_ = MeasurementsHead{};
  pending_trip_ = Fault::none;
  suspended_ = 0;
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
  sched_.skip_late(now_us, kMaxLateUs);
  return true;
}

bool DeviceCore::pulse_due(std::uint64_t now_us) const {
  if (status_.state != State::running || sched_.done()) return false;
  const std::uint64_t t = sched_.next().start_us;
  return t <= now_us && t < deadline_us();
}

CodeSpan DeviceCore::pulse_codes(std::uint16_t i) {
  const Pattern& p = pattern_[i];
  for (std::size_t c = 0; c < channels_; ++c) dense_[c] = 0;
  for (std::size_t k = 0; k < p.count; ++k)
    dense_[pool_channel_[p.first + k]] = pool_code_[p.first + k];
  std::uint16_t scale = hold_ref_[i] != 0 ? hold_scale(i) : p.scale;
  if (suspended_ != 0 && touches_suspended(i)) {  // a pad without contact: only its probe
    ++readings_.suspended;
    const std::uint16_t probe = probe_scale(i);
    if (probe < scale) scale = probe;
  }
  if (scale == kFullScale) return CodeSpan{dense_, channels_};
  scale_codes(dense_, channels_, scale, scaled_);
  return CodeSpan{scaled_, channels_};
}

bool DeviceCore::touches_suspended(std::uint16_t i) const {
  const Pattern& p = pattern_[i];
  for (std::size_t k = 0; k < p.count; ++k)
    if (((suspended_ >> pool_channel_[p.first + k]) & 1u) != 0) return true;
  return false;
}

std::uint16_t DeviceCore::probe_scale(std::uint16_t i) const {
  const Pattern& p = pattern_[i];
  std::uint32_t largest = 0;
  for (std::size_t k = 0; k < p.count; ++k) {
    const std::int32_t c = pool_code_[p.first + k];
    largest = std::max<std::uint32_t>(largest, static_cast<std::uint32_t>(c < 0 ? -c : c));
  }
  // The probe in whole codes of the strongest phase (its units x the step), rounded down:
  // the largest code scaled to at most that, and scale_codes, which moves single codes by
  // one away from zero to keep the sum, never takes a code past a whole number it is under.
  const std::uint64_t unit_nA =
      static_cast<std::uint64_t>(timing_[i].max_units()) * caps_.dac_step_nA;
  const std::uint64_t probe_codes = std::uint64_t{guards_.probe_uA} * 1000u / unit_nA;
  if (largest <= probe_codes) return kFullScale;  // already at most the probe: as it is
  return static_cast<std::uint16_t>(probe_codes * kFullScale / largest);  // rounded down
}

void DeviceCore::pulse_delivered() {
  const ScheduledPulse p = sched_.next();
  const auto slip = static_cast<std::uint32_t>(p.start_us - p.slot_us);
  if (slip > 0) ++status_.deferred;
  if (slip > status_.max_slip_us) status_.max_slip_us = slip;
  ++status_.pulses;
  sched_.delivered();
  if (sched_.done()) {
    end_session();
    status_.fault = Fault::completed;
  }
}

void DeviceCore::not_delivered(std::uint64_t start_us, std::uint32_t n) {
  if (start_us != start_us_) return;  // an earlier output's: its count is final
  status_.pulses -= std::min(n, status_.pulses);
}

void DeviceCore::overrun(std::uint64_t start_us, std::uint32_t n) {
  if (start_us != start_us_) return;  // an earlier output's
  not_delivered(start_us, n);
  if (status_.state != State::running) return;
  end_session();
  status_.fault = Fault::overrun;
}

void DeviceCore::output_fault() {
  const bool was_running = status_.state == State::running;
  end_session();
  faulted_ = true;
  status_.fault = Fault::output_fault;
  if (!was_running) ++output_ends_;  // the stage must stop even if nothing ran
}

void DeviceCore::stop_input(std::uint64_t now_us) {
  const bool was_running = status_.state == State::running;
  if (was_running) {
    readings_.trip = Fault::stop_input;
    readings_.trip_channel = kNoChannel;
    const std::uint64_t t_us = now_us > start_us_ ? now_us - start_us_ : 0;
    readings_.trip_t_us = t_us > 0xFFFFFFFFu ? 0xFFFFFFFFu : static_cast<std::uint32_t>(t_us);
    readings_.trip_ohm = kOpenOhm;
  }
  pending_trip_ = Fault::none;
  end_session();
  // Idle, it does not hide why the last output ended (a guard, a fault, the watchdog).
  const Fault f = status_.fault;
  if (was_running || f == Fault::none || f == Fault::completed || f == Fault::stopped)
    status_.fault = Fault::stop_input;
  if (!was_running) ++output_ends_;  // the stage must stop (and stay off) even if idle
}

void DeviceCore::link_lost() {
  const bool was_running = status_.state == State::running;
  end_session();
  if (was_running) status_.fault = Fault::link_lost;
}

std::uint64_t DeviceCore::next_event_us() const {
  if (status_.state != State::running) return std::numeric_limits<std::uint64_t>::max();
  if (sched_.done()) return deadline_us();
  return std::min(sched_.next().start_us, deadline_us());
}

void DeviceCore::set_line_counts(std::uint32_t line_errors, std::uint32_t overruns) {
  status_.line_errors = saturate16(line_errors);
  status_.overruns = saturate16(overruns);
}

}  // namespace tp::device
