#pragma once
// User text in messages.  A message is one line for a terminal and for Python (which needs
// UTF-8): whatever a person typed or a file held is shown, byte for byte, but a byte that a
// terminal would act on or that is not UTF-8 is shown escaped.

#include <cstddef>
#include <string>
#include <string_view>

namespace tp {

// `text` with every control character (C0, DEL, C1: \n, \r and \t as themselves escaped,
// the others \xNN), and every byte of an invalid UTF-8 sequence (a stray continuation
// byte, a truncated, overlong or surrogate sequence, above U+10FFFF) written as \xNN;
// valid printable UTF-8 is kept.  A backslash is kept as it is, so printable(printable(s))
// is printable(s).
inline std::string printable(std::string_view text) {
  static const char kHex[] = "0123456789ABCDEF";
  std::string out;
  out.reserve(text.size());
  auto escape = [&](unsigned char b) {
    out += "\\x";
    out += kHex[b >> 4];
    out += kHex[b & 15];
  };
  const std::size_t n = text.size();
  for (std::size_t i = 0; i < n;) {
    const auto b = static_cast<unsigned char>(text[i]);
    if (b >= 0x20 && b < 0x7F) {
      out += static_cast<char>(b);
      ++i;
      continue;
    }
    if (b == '\n' || b == '\r' || b == '\t') {
      out += b == '\n' ? "\\n" : b == '\r' ? "\\r" : "\\t";
      ++i;
      continue;
    }
    // A UTF-8 sequence: its length from the lead byte, and the range of its second byte
    // (narrower after E0, ED, F0 and F4: no overlong form, surrogate or code point above
    // U+10FFFF).
    std::size_t len = 0;
    unsigned char lo = 0x80, hi = 0xBF;
    if (b >= 0xC2 && b <= 0xDF) {
      len = 2;
    } else if (b >= 0xE0 && b <= 0xEF) {
      len = 3;
      if (b == 0xE0) lo = 0xA0;
      if (b == 0xED) hi = 0x9F;
    } else if (b >= 0xF0 && b <= 0xF4) {
      len = 4;
      if (b == 0xF0) lo = 0x90;
      if (b == 0xF4) hi = 0x8F;
    }
    bool valid = len > 0 && i + len <= n;
    for (std::size_t k = 1; valid && k < len; ++k) {
      const auto c = static_cast<unsigned char>(text[i + k]);
      valid = k == 1 ? c >= lo && c <= hi : c >= 0x80 && c <= 0xBF;
    }
    // C1 controls (U+0080 to U+009F: C2 80 to C2 9F) act on terminals too.
    const bool c1 = valid && b == 0xC2 && static_cast<unsigned char>(text[i + 1]) <= 0x9F;
    if (valid && !c1) {
      out.append(text.data() + i, len);
      i += len;
    } else if (c1) {
      escape(b);
      escape(static_cast<unsigned char>(text[i + 1]));
      i += 2;
    } else {
      escape(b);  // the next byte starts afresh: one bad byte hides nothing after it
      ++i;
    }
  }
  return out;
}

// User text quoted for a message (not std::quoted): 'text', escaped by printable().
inline std::string quoted_text(std::string_view text) {
  return "'" + printable(text) + "'";
}

// n and the noun, plural (noun + "s") unless n is 1: "1 slot", "2 slots", "0 frames".
inline std::string count_text(std::size_t n, const std::string& noun) {
  return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

}  // namespace tp
