#pragma once
// Rendering a tactile image (issue 23; docs/rendering.md): a bank of focal pixels
// (optimize-weights --bank), a person's profile and the pads' intensities become a mix
// of patterns the device plays.  This header gathers the parts:
//   io/bank.hpp      the bank read (pixel_bank_from_json);
//   render/options.hpp   the options, --rates and their checks;
//   render/plan.hpp      a still's plan: lit -> groups -> frame -> mix (plan_render);
//   render/colouring.hpp the groups' colouring (DSatur);
//   render/frame.hpp     the frame scheduler (plan_frame);
//   render/sequence.hpp  sequences and their live frames.
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

#include "io/bank.hpp"
#include "render/image.hpp"
#include "render/options.hpp"
#include "render/plan.hpp"
#include "psych/profile.hpp"
#include "render/sequence.hpp"
#include "core/text.hpp"
