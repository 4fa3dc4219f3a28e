#pragma once
// Sequences (render-tactile --sequence and --frames; docs/rendering.md): a stimulus of
// every pattern some frame lights, uploaded once, and live amplitude frames for it.

#include <string>
#include <vector>

#include "render/plan.hpp"

namespace tp {

// The frames of a sequence as they are read (render-tactile --sequence): kept are the
// first (where the stimulus starts), which (pixel, primary) some frame lights, and which
// of them every frame lights alike (the same intensity in each: the same kin), so memory
// does not grow with the number of frames.
class SequenceFrames {
 public:
  SequenceFrames(int columns, int rows);
  // Bad input naming `where` for a frame of another size.
  void add(const PadIntensities& frame, const std::string& where);
  std::size_t count() const { return count_; }
  const PadIntensities& first() const { return first_; }
  bool lit(std::size_t pad, std::size_t primary) const { return lit_[3 * pad + primary]; }
  long kin(std::size_t pad, std::size_t primary) const { return kin_[3 * pad + primary]; }

 private:
  int columns_, rows_;
  std::size_t count_ = 0;
  PadIntensities first_;
  std::vector<char> lit_;
  std::vector<long> kin_;
};

// A sequence of frames played live (render-tactile --sequence): every (pixel, primary)
// some frame lights (no frames: every pattern the bank has that the profile has a range
// for), at its comfort current; an amplitude frame scales a whole device pattern, so only
// patterns of the same kin and the same range may fire together (those a still would
// group: no shared pad, within the crosstalk bound); without frames, each alone.  The mix
// starts from the first frame's amplitudes (none: from nothing) and lasts o.duration_s.
RenderPlan plan_sequence(const PixelBank& bank, const Profile& profile,
                         const SequenceFrames& frames, const RenderOptions& o);
RenderPlan plan_sequence(const PixelBank& bank, const Profile& profile,
                         const std::vector<PadIntensities>& frames, const RenderOptions& o);
// A sequence's stimulus document: the mix, and the bank's array it was made for.
Json sequence_to_json(const RenderPlan& sequence, const PixelBank& bank);
// The duration of a sequence's stimulus by default: its frames and one frame period more
// (bad input when that is longer than a stimulus may last).
double sequence_duration_s(std::size_t frames, double fps, const StimulusLimits& limits);

// A sequence's stimulus as the frames stage reads it (render-tactile --frames): its
// patterns, and each one's primary, pixels (pads) and the current each pixel was made at.
struct Sequence {
  Mix mix;
  std::vector<int> primary;
  std::vector<std::vector<long>> pads;
  std::vector<std::vector<double>> made_mA;
};
// Reads a sequence's stimulus and checks that it fits: made for the bank's array (the
// same grid, pitch and pads), one pattern per pixel and primary at most, and the
// profile's comfort for each pixel no higher than the current it was made at, nor, for
// pixels that fire as one pattern, in another proportion.  Bad input naming `what`, the
// problem and the fix.
Sequence sequence_from_json(const Json& j, const PixelBank& bank, const Profile& profile,
                            const std::string& what);
// A frame's amplitudes (mA, one per pattern of the sequence): each pattern's members'
// currents under the profile, as a share of those it was made at, times its amplitude (0
// where dark).  Bad input naming `where` when the frame lights a pixel the stimulus has no
// pattern for, lights the pixels of one pattern unlike, or asks more than a pattern holds.
std::vector<double> frame_amplitudes(const Sequence& sequence, const Profile& profile,
                                     const PadIntensities& frame, const std::string& where);
// A frame given as a JSON line, {"rgb": [[R, G, B], ...]}: columns x rows pixels in the
// image's order (row-major from the top), whole numbers 0 to 255.  Bad input naming `where`.
PadIntensities frame_from_json(const Json& j, int columns, int rows, const std::string& where);

}  // namespace tp
