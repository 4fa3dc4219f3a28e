#pragma once
// The simulated board's skin block: a skin scenario (skin_scenario.hpp) and the output
// stage's compliance, in binary, for the firmware under QEMU (docs/skin.md, "The firmware's
// simulated board").  scripts/firmware-emu --skin writes it (stim-emu --skin-block) into
// flash beside the configuration block, at 0x080E1000; the emulated board reads it at
// start-up and measures every pulse on it.  A real board ignores it: its ADC measures.
// Little-endian:
//
//   magic u32 "TPSK" | version u16 (1) | size u32 (the whole block) | compliance_mV u32 |
//   area_mm2 f64 | channels u8 (C) | C x 5 starting values f64 (rs_kohm, rp_kohm, cp_nf,
//   j_half_mA_mm2, contact) | events u16 (N) | stop inputs u8 (S) |
//   N x (t_us u64, ramp_us u64, channels u64, field u8, target f64) | S x t_us u64 |
//   crc16 u16 (CRC-16/CCITT-FALSE of every byte before it)
//
// Portable (no heap): the firmware decodes it in place.

#include <cstddef>
#include <cstdint>

#include "device/skin_scenario.hpp"

namespace tp::device {

inline constexpr std::uint32_t kSkinBlockMagic = 0x4B535054;  // "TPSK"
inline constexpr std::size_t kSkinEventSize = 33;
// The largest block: every channel, every event and stop input.
inline constexpr std::size_t kSkinBlockMaxSize = 4 + 2 + 4 + 4 + 8 + 1 +
                                                 kMaxChannels * kSkinFields * 8 + 2 + 1 +
                                                 SkinScenario::kMaxEvents * kSkinEventSize +
                                                 SkinScenario::kMaxStopInputs * 8 + 2;
// The compliance a block may give, V: 1 to 1000, as stim-emu --compliance-v.
inline constexpr double kSkinBlockMaxComplianceV = 1000;

// Writes the scenario's first `channels` channels and the compliance into out (capacity
// kSkinBlockMaxSize); returns the block's size, 0 when the values cannot be written (no
// channels, or a compliance outside [1, kSkinBlockMaxComplianceV]).
std::size_t encode_skin_block(const SkinScenario& s, std::size_t channels, double compliance_V,
                              std::uint8_t* out);

// Reads a block of at most max_size bytes into s and compliance_V; false when it is not one
// (erased flash, a bad magic, version, size or CRC, a value outside a skin file's ranges,
// a field or channel count out of range): s is then as it was.
bool decode_skin_block(const std::uint8_t* block, std::size_t max_size, SkinScenario& s,
                       double& compliance_V);

}  // namespace tp::device
