// The simulated board's skin block (skin_block.hpp).

#include "device/skin_block.hpp"

#include <cmath>
#include <cstring>

#include "device/frame.hpp"
#include "device/protocol.hpp"

namespace tp::device {
namespace {

// A little writer and reader over a byte array (the block's fields, little-endian).
struct Writer {
  std::uint8_t* p;
  std::size_t n = 0;
  void u(std::uint64_t v, int bytes) {
    for (int i = 0; i < bytes; ++i) p[n++] = static_cast<std::uint8_t>((v >> (8 * i)) & 0xFF);
  }
  void f64(double v) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &v, 8);
    u(bits, 8);
  }
};

struct Reader {
  const std::uint8_t* p;
  std::size_t size;
  std::size_t n = 0;
  bool ok = true;
  std::uint64_t u(int bytes) {
    if (n + static_cast<std::size_t>(bytes) > size) {
      ok = false;
      return 0;
    }
    std::uint64_t v = 0;
    for (int i = 0; i < bytes; ++i) v |= std::uint64_t{p[n++]} << (8 * i);
    return v;
  }
  double f64() {
    const std::uint64_t bits = u(8);
    double v = 0;
    std::memcpy(&v, &bits, 8);
    if (!std::isfinite(v) || v < 0) ok = false;
    return v;
  }
};

// The ranges a skin file's values have (skin_circuit.hpp; docs/skin.md), so that a block
// carries nothing the emulators' files could not.
bool within(double v, double lo, double hi) { return v >= lo && v <= hi; }
bool field_ok(SkinField f, double v) {
  switch (f) {
    case SkinField::rs_kohm: return within(v, 0.01, 1000);
    case SkinField::rp_kohm: return within(v, 0.1, 10000);
    case SkinField::cp_nf: return within(v, 0.01, 10000);
    case SkinField::j_half_mA_mm2: return v == 0 || within(v, 0.001, 1000);
    case SkinField::contact: return within(v, 0, 1);
  }
  return false;
}

// The header's fields after magic, version and size: the compliance, area and starting
// values, into s (null: only checked).
bool read_start(Reader& r, SkinScenario* s, double& compliance_V) {
  compliance_V = static_cast<double>(r.u(4)) * 1e-3;
  const double area = r.f64();
  const std::size_t channels = static_cast<std::size_t>(r.u(1));
  if (channels == 0 || channels > kMaxChannels || !within(compliance_V, 1, kSkinBlockMaxComplianceV) ||
      !within(area, 0.01, 10000))
    return false;
  if (s) {
    SkinInterface base;
    base.area_mm2 = area;
    s->reset(base);
  }
  for (std::size_t c = 0; c < channels; ++c)
    for (std::size_t f = 0; f < kSkinFields; ++f) {
      const double v = r.f64();
      if (!field_ok(static_cast<SkinField>(f), v)) return false;
      if (s) s->set_override(c, static_cast<SkinField>(f), v);
    }
  return r.ok;
}

bool read_events(Reader& r, SkinScenario* s) {
  const std::size_t events = static_cast<std::size_t>(r.u(2));
  const std::size_t stops = static_cast<std::size_t>(r.u(1));
  if (events > SkinScenario::kMaxEvents || stops > SkinScenario::kMaxStopInputs) return false;
  for (std::size_t k = 0; k < events && r.ok; ++k) {
    SkinEvent e;
    e.t_us = r.u(8);
    e.ramp_us = r.u(8);
    e.channels = r.u(8);
    const std::uint64_t field = r.u(1);
    e.target = r.f64();
    if (field >= kSkinFields) return false;
    e.field = static_cast<SkinField>(field);
    if (!field_ok(e.field, e.target)) return false;
    if (s) s->add_event(e);  // within kMaxEvents: checked above
  }
  for (std::size_t k = 0; k < stops && r.ok; ++k) {
    const std::uint64_t t_us = r.u(8);
    if (s) s->add_stop_input(t_us);
  }
  return r.ok;
}

}  // namespace

std::size_t encode_skin_block(const SkinScenario& s, std::size_t channels, double compliance_V,
                              std::uint8_t* out) {
  if (channels == 0 || channels > kMaxChannels || !(compliance_V >= 1) ||
      compliance_V > kSkinBlockMaxComplianceV)
    return 0;
  Writer w{out};
  w.u(kSkinBlockMagic, 4);
  w.u(1, 2);
  w.u(0, 4);  // the size, below
  w.u(static_cast<std::uint64_t>(std::floor(compliance_V * 1000 + 0.5)), 4);
  w.f64(s.area_mm2());
  w.u(channels, 1);
  for (std::size_t c = 0; c < channels; ++c)
    for (std::size_t f = 0; f < kSkinFields; ++f) w.f64(s.start_value(c, static_cast<SkinField>(f)));
  w.u(s.events(), 2);
  w.u(s.stop_inputs(), 1);
  for (std::size_t k = 0; k < s.events(); ++k) {
    const SkinEvent& e = s.event(k);
    w.u(e.t_us, 8);
    w.u(e.ramp_us, 8);
    w.u(e.channels, 8);
    w.u(static_cast<std::uint64_t>(e.field), 1);
    w.f64(e.target);
  }
  for (std::size_t k = 0; k < s.stop_inputs(); ++k) w.u(s.stop_input(k), 8);
  const std::size_t size = w.n + 2;
  Writer at_size{out + 6};
  at_size.u(size, 4);
  w.u(crc16(out, w.n), 2);
  return size;
}

bool decode_skin_block(const std::uint8_t* block, std::size_t max_size, SkinScenario& s,
                       double& compliance_V) {
  Reader r{block, max_size};
  if (r.u(4) != kSkinBlockMagic || r.u(2) != 1) return false;
  const std::size_t size = static_cast<std::size_t>(r.u(4));
  if (!r.ok || size < 12 || size > max_size || crc16(block, size - 2) != get_u16(block + size - 2))
    return false;
  r.size = size - 2;
  // Checked whole first, so that a bad block leaves s as it was; then read into s.
  const std::size_t body = r.n;
  double v = 0;
  if (!read_start(r, nullptr, v) || !read_events(r, nullptr) || r.n != r.size) return false;
  r.n = body;
  read_start(r, &s, v);
  read_events(r, &s);
  compliance_V = v;
  return true;
}

}  // namespace tp::device
