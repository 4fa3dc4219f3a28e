#pragma once
// Skin files for an emulator (issue 41, item 2; docs/skin.md, "Skin scenarios"): the
// electrode-skin interface of every channel, per-channel overrides and a script of timed
// events, read into a device::SkinScenario.  The format is the skin file's
// ("tactile-primaries/skin/1"); a file may also carry the layered conductor's `layers`
// (model/skin.hpp reads those, and this reader leaves them).

#include <optional>
#include <string>

#include "core/json.hpp"
#include "device/skin_scenario.hpp"
#include "host/transport.hpp"

namespace tp::host {

// The ranges of a skin file's interface values (docs/skin.md).
namespace skin_file_ranges {
inline constexpr double max_time_s = 86400;  // t_s and ramp_s: a day
}

// The scenario a skin document gives for an emulator of `channels` channels (1 to 64);
// bad input naming the field (`where` first, "--skin FILE") for anything out of range,
// unknown, or naming a channel the emulator does not have.
device::SkinScenario skin_scenario_from_json(const Json& j, std::size_t channels,
                                             const std::string& where);

// An emulator's skin from its flags: the skin file at `path` (- for stdin) for `channels`
// channels, and the output stage's compliance (1 to 1000 V [100]); `skin_flag` and
// `compliance_flag` name them in messages.  An empty path: no skin (an ideal load), and a
// compliance given then is refused (it would do nothing).
EmulatorSkin emulator_skin(const std::string& path, std::optional<double> compliance_V,
                           std::size_t channels, const std::string& skin_flag,
                           const std::string& compliance_flag);

}  // namespace tp::host
