#pragma once
// A live session's frames: stimctl --live's JSON lines, Python's set_currents and
// set_amplitudes, a watched trial's end (docs/document-format.md, "Live frames").
//
//  - A frame is {"currents_mA": [...]} (a single stimulus: its new currents) or
//    {"amplitudes": [...]} (one per pattern), nothing else: an unknown or repeated key is
//    refused, and a frame is told by its key, never by the text of the line.
//  - An amplitude is the current of a weight-1 electrode of the pattern in force: the
//    stimulus's own (amplitude_mA, or its largest current when it has none), or, after a
//    currents frame, that frame's pattern, whose amplitude is its largest current (its
//    weights are the currents over it).  So {"amplitudes": [a]} after {"currents_mA": c}
//    delivers c x a / max|c|, never more than c (docs/safety.md, "Live amplitudes").
//  - Every frame is checked, in order, against the pattern in force as the frames before it
//    left it.  Frames that arrive together are folded: a later frame supersedes an earlier
//    one not yet sent (a currents frame supersedes both kinds), so the device gets at most
//    one currents frame and one amplitude frame a turn, the last, and a fade's last frame
//    (a stop or a lower amplitude) is never queued behind the ones it replaces.

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "device/protocol.hpp"
#include "host/line_reader.hpp"
#include "pulse/mix.hpp"

namespace tp::host {

struct LiveFrame {
  enum class Kind { currents, amplitudes };
  Kind kind = Kind::currents;
  std::vector<double> values_mA;
  std::string where;  // for messages: "input line 3", "set_amplitudes"
};

// One line of JSON; bad input naming `where` when it is not exactly one frame.
LiveFrame parse_live_line(const std::string& line, const std::string& where);

class LiveState {
 public:
  // limits: the host's, already narrowed to the device's (plan_session).
  LiveState(const Mix& m, const StimulusLimits& limits, const device::Capabilities& caps);

  // Checks a frame against the pattern in force and folds it into the pending update;
  // bad input naming f.where (nothing changed) when it breaks a limit.
  void add(const LiveFrame& f);

  struct Update {
    std::optional<std::vector<std::int16_t>> codes;    // pattern 0's new codes, sent first
    std::optional<std::vector<std::uint16_t>> scales;  // then every pattern's scale
    std::uint32_t frames = 0;                          // the frames folded into it
    bool empty() const { return !codes && !scales; }
  };
  // The pending update, and none after it until the next frame.
  Update take();

  const Mix& in_force() const { return mix_; }

 private:
  Mix mix_;
  StimulusLimits limits_;
  device::Capabilities caps_;
  Update pending_;
};

// Where a session's frames come from.
class FrameSource {
 public:
  virtual ~FrameSource() = default;
  // Waits up to timeout_ms for input, and adds every frame available now to `state`, in
  // order (bad input ends the session).  False once the input has ended and every frame
  // in it has been added.
  virtual bool pump(LiveState& state, int timeout_ms) = 0;
};

// JSON lines from a file descriptor (stimctl --live's stdin); blank lines are skipped, and
// a flood is taken at most 1 MiB and timeout_ms (at least kMinTurnMs) a turn, so that it
// never starves the keep-alive on however slow a machine: the lines not taken stay for the
// next pump.
class LineSource final : public FrameSource {
 public:
  static constexpr int kMinTurnMs = 5;
  explicit LineSource(int fd) : reader_(fd) {}
  bool pump(LiveState& state, int timeout_ms) override;

 private:
  // Complete lines until none is left or deadline_ns (monotonic_ns()) has passed; true: at
  // least one line was complete.
  bool take_lines(LiveState& state, std::int64_t deadline_ns);
  LineReader reader_;
};

// Frames pushed by another thread (Python's Stimulator, a watched trial); close() ends the
// input.  Thread-safe.
class FrameQueue final : public FrameSource {
 public:
  void push(LiveFrame f);
  void close();
  bool closed() const;
  bool pump(LiveState& state, int timeout_ms) override;

 private:
  mutable std::mutex m_;
  std::condition_variable cv_;
  std::deque<LiveFrame> frames_;
  bool closed_ = false;
};

}  // namespace tp::host
