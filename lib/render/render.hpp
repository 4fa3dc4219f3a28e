#pragma once
// Rendering a tactile image (issue 23; docs/rendering.md): a bank of focal pixels
// (optimize-weights --bank), a person's profile and the pads' intensities become a mix
// of patterns the device plays.
//
// The pulse budget.  Each lit (pixel, primary) is one pattern of the bank at the current
// the profile gives its intensity.  Two of a primary's patterns may fire at the same
// instant, as one device pattern (their currents summed), when they share no pad and
// neither's field reaches the other's target by more than the crosstalk bound:
//     crosstalk(A -> B) = |I_A AF_A(p_B)| / (I_B AF_B(p_B)),
// AF_X(p) the activating function of pattern X's weights (max |w| = 1) on the receptor's
// fibre at p, p_B pattern B's peak as the bank records it, I the currents.  The conflict
// graph (an edge where a pad is shared or the bound broken, in either direction) is
// coloured by DSatur (Brelaz 1979); each colour class is a group, one device pattern.
//
// The groups take turns in a frame: a cycle of C us holds J = floor(C / (L + gap)) slots
// (L the pulse's length); a primary's period is k_p x C, so one slot holds k_p of its
// groups, one in every k_p-th cycle.  No two pulses ever meet: nothing is deferred.  C and
// the k_p are chosen (plan_frame) to make every primary's rate at most the requested and
// the smallest achieved / requested as large as possible, within the slots, each
// electrode's RMS and mean current (summed over the groups) and the device's exact slip
// check.  When the image asks more than the device can deliver this lowers rates, never
// drops a lit pixel, and the plan says so.

#include <array>
#include <string>
#include <vector>

#include "io/document.hpp"
#include "pulse/mix.hpp"
#include "render/image.hpp"
#include "render/profile.hpp"
#include "render/text.hpp"

namespace tp {

// One (pixel, primary) of a bank.
struct BankEntry {
  bool present = false;  // the bank has this primary's mode
  bool feasible = false;
  std::string reason;           // why not feasible
  std::vector<double> weights;  // one per pad, max |w| = 1
  double peak_x_mm = 0, peak_y_mm = 0, peak_z_mm = 0;
};

// A bank of every pad's pixel on a grid (optimize-weights --bank without --at).
struct PixelBank {
  Document doc;  // the array, model and receptors
  int columns = 0, rows = 0;
  double pad_area_mm2 = 0;
  std::vector<std::array<BankEntry, 3>> entry;  // by pad, by primary
  std::size_t pads() const { return entry.size(); }
};
// Bad input naming the problem: not a bank, not a grid, a pixel that is not its pad's
// centre, weights that are not one per pad or not finite.
PixelBank pixel_bank_from_json(const Json& j);

struct RenderOptions {
  std::array<double, 3> rate_hz = {30.0, 200.0, 250.0};  // requested, per primary
  double width_us = 200.0, interphase_us = 0.0, balance_width_us = 200.0;
  double crosstalk = 0.1;  // the bound for firing together, [0, 1]
  double duration_s = 1.0;
  double gap_us = device::hard::min_gap_us;
  StimulusLimits limits;
  // Each electrode's RMS and mean current are planned to this share of their limits,
  // leaving room for the DAC's rounding.
  double load_margin = 0.99;
  unsigned threads = 0;  // for the fields and the conflicts, 0: every core
};
// "RA:30,SAI:200,PC:250" (any of them, each once; the others keep theirs) into rate_hz, by
// kPrimaries' index; bad input naming --rates.
void parse_rates(const std::string& text, std::array<double, 3>& rate_hz);
// "RA,PC": kPrimaries' indices in that order; bad input naming `what`.
std::vector<int> parse_primaries(const std::string& text, const std::string& what);

// Checks each option's range (docs/rendering.md); bad input naming it.  A duration is
// also checked against the plan: it must hold one pulse of every pattern (plan_render).
void check_render_options(const RenderOptions& o);

struct LitPattern {
  long pad = 0;
  int primary = 0;
  double intensity = 0;  // 0 to 1
  double current_mA = 0;
};
struct RenderGroup {
  int primary = 0;
  std::vector<std::size_t> members;  // indices into RenderPlan::lit
  int slot = 0, turn = 0;            // its slot in the cycle, its cycle modulo k
};
struct RenderPlan {
  std::vector<LitPattern> lit;
  std::vector<RenderGroup> groups;  // device pattern order
  std::array<int, 3> groups_per_primary{};
  std::array<double, 3> requested_hz{}, rate_hz{};  // rate_hz: achieved (0: nothing lit)
  double cycle_us = 0;
  std::array<long, 3> k{};     // each primary's period in cycles
  int slots = 0;               // slots per cycle
  double worst_crosstalk = 0;  // among patterns that fire together
  bool lowered = false;        // some rate is below the requested by more than 0.5 %
  // What lowered them: "the device's time" (the requested rates' pulses and gaps would
  // take more than all of it), "the frame's slots" (they would fit, but no collision-free
  // frame has those rates), or "the electrodes' RMS and mean current".
  std::string limited_by;
  double requested_utilisation = 0;  // sum over groups of (pulse + gap) x requested rate
  Mix mix;                           // empty when nothing is lit
};
// Bad input for a lit pixel whose primary has no pattern (the bank's reason), a profile
// without that primary's range, a duration shorter than one period of some pattern at its
// planned rate; a runtime failure when no frame satisfies the limits.
RenderPlan plan_render(const PixelBank& bank, const Profile& profile, const PadIntensities& image,
                       const RenderOptions& o);

// What render-tactile says on stderr about a plan: "N lit patterns in M groups, cycle C us
// of J slots, worst crosstalk X; refresh SAI 200 Hz (200 requested; 1 group)", and when
// rates were lowered, why (`what`: "image" or "sequence"; empty when not lowered).
std::string plan_summary(const RenderPlan& plan);
std::string lowered_text(const RenderPlan& plan, const std::string& what);

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

// Crosstalk of A onto B as above (exposed for tests).
double crosstalk(const PixelBank& bank, int primary, long a, double current_a_mA, long b,
                 double current_b_mA);

// The plan as JSON (render-tactile --plan): groups, rates, frame, crosstalk.
Json plan_to_json(const RenderPlan& p);

}  // namespace tp
