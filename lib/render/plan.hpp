#pragma once
// A still image's plan (render/render.hpp says how it renders): four named steps, each
// testable alone, that plan_render runs in order:
//   lit     the (pixel, primary) the image lights, at the profile's currents (lit_patterns);
//   groups  which of them fire together as one device pattern (group_patterns: the
//           conflict graph over LitReach's crosstalk, coloured by DSatur);
//   frame   the cycle, its slots and each primary's period (frame_for over
//           render/frame.hpp's scheduler);
//   mix     the groups as the frame placed them, as a mix the device plays (build_mix).

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/json.hpp"
#include "pulse/mix.hpp"
#include "io/bank.hpp"
#include "render/frame.hpp"
#include "render/image.hpp"
#include "render/options.hpp"
#include "psych/profile.hpp"

namespace tp {

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
// The same, where only patterns of the same kin may fire together: kin by 3 x pad +
// primary (empty: every pattern the same kin).  A sequence's plan (render/sequence.hpp).
RenderPlan plan_with_kin(const PixelBank& bank, const Profile& profile, const PadIntensities& image,
                         const RenderOptions& o, const std::vector<long>& kin);

// What render-tactile says on stderr about a plan: "N lit patterns in M groups, cycle C us
// of J slots, worst crosstalk X; refresh SAI 200 Hz (200 requested; 1 group)", and when
// rates were lowered, why (`what`: "image" or "sequence"; empty when not lowered).
std::string plan_summary(const RenderPlan& plan);
std::string lowered_text(const RenderPlan& plan, const std::string& what);

// The plan as JSON (render-tactile --plan): groups, rates, frame, crosstalk.
Json plan_to_json(const RenderPlan& p);

// ---- The steps ----

// Before any step: the options' ranges, a profile calibrated on another array, an image
// of another size than the bank's; bad input naming them.
void check_plan_inputs(const PixelBank& bank, const Profile& profile, const PadIntensities& image,
                       const RenderOptions& o);

// lit: the patterns an image lights (intensity above 0), pixel-major then by primary, at
// the profile's currents; bad input for one the bank has no pattern for, or above the
// current limit.
std::vector<LitPattern> lit_patterns(const PixelBank& bank, const Profile& profile,
                                     const PadIntensities& image, const RenderOptions& o);

// The bank's pattern of a lit pattern.
const BankEntry& entry_of(const PixelBank& bank, const LitPattern& l);

// How the lit patterns reach one another: the pads each uses, and each one's activating
// function at every lit pattern's peak, on that pattern's receptor.  One field per pad a
// pattern uses (at 1 mA, evaluated at every peak): a pattern's AF is its weights' sum of
// those, the field being linear in the currents.
class LitReach {
 public:
  LitReach(const PixelBank& bank, const std::vector<LitPattern>& lit, unsigned threads);
  bool share_pad(std::size_t i, std::size_t j) const;
  // Pattern i's weights' (max |w| = 1) AF at pattern j's peak.
  double af(std::size_t i, std::size_t j) const;
  // Crosstalk of i onto j at their currents, |I_i AF_i(p_j)| / (I_j AF_j(p_j)); infinite
  // when j's own AF at its peak is not positive.
  double crosstalk(std::size_t i, std::size_t j) const;

 private:
  const PixelBank& bank_;
  const std::vector<LitPattern>& lit_;
  std::vector<std::vector<std::uint64_t>> uses_;  // by pattern: a bit per pad
  std::vector<std::vector<double>> unit_;         // by pad, by pattern
  std::vector<double> own_;                       // af(j, j)
};

// The conflicts among `nodes` (indices into lit): an edge where two share a pad, are of
// another kin (kin as plan_with_kin takes it), or either's crosstalk onto the other is
// above `bound`.  By node: its neighbours' places in `nodes`, ascending.
std::vector<std::vector<std::size_t>> conflict_graph(const LitReach& reach,
                                                     const std::vector<LitPattern>& lit,
                                                     const std::vector<std::size_t>& nodes,
                                                     const std::vector<long>& kin, double bound,
                                                     unsigned threads);

// groups: per primary, the conflict graph of its lit patterns coloured by DSatur, each
// colour a group (members ascending).  Sets the plan's groups (by primary, then colour),
// groups_per_primary and worst_crosstalk from plan.lit.
void group_patterns(const PixelBank& bank, const RenderOptions& o, const std::vector<long>& kin,
                    RenderPlan& plan);

// Each group's currents, by group, by pad: its members' currents times their weights.
std::vector<std::vector<double>> group_currents(const PixelBank& bank, const RenderPlan& plan);

// frame: the scheduler's problem for the groups' currents (the requested periods, the
// slot, each electrode's load per primary, within o.load_margin of the limits).
FrameProblem frame_problem(const RenderOptions& o, const std::vector<std::vector<double>>& currents,
                           const RenderPlan& plan);
// The best frame (plan_frame): sets the plan's cycle, slots, periods, rates and whether (and
// by what) they were lowered.  A runtime failure when no frame keeps the limits.
Frame frame_for(const RenderOptions& o, const std::vector<std::vector<double>>& currents,
                RenderPlan& plan);

// Each pattern's pulses in o.duration_s at its period; bad input naming --duration when the
// duration holds none (it is never stretched to one).
long pulse_count(const RenderOptions& o, int primary, double period_us);

// mix: each group's slot and turn as the frame placed it, and its pattern in the plan's
// mix (its currents, the pulse, its period, count and phase; its pixels carried).
void build_mix(const PixelBank& bank, const RenderOptions& o,
               const std::vector<std::vector<double>>& currents, const Frame& frame,
               RenderPlan& plan);

}  // namespace tp
