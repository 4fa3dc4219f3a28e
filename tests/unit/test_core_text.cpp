// User text in messages (core/text): printable.
#include <catch2/catch.hpp>

#include <string>

#include "core/error.hpp"
#include "core/text.hpp"
#include "error_support.hpp"

using namespace tp;
using tp::test::message_of;

TEST_CASE("user text in a message is printable: control and non-UTF-8 bytes escaped",
          "[io][text]") {
  using namespace std::string_literals;
  CHECK(printable("plain text, 'quoted' (1/2) \\ kept") == "plain text, 'quoted' (1/2) \\ kept");
  CHECK(printable("a\nb\rc\td") == "a\\nb\\rc\\td");
  CHECK(printable("nul\0here"s) == "nul\\x00here");
  CHECK(printable("\x1b[2J\x07\x7f") == "\\x1B[2J\\x07\\x7F");
  // UTF-8: kept when valid (2, 3 and 4 bytes), escaped byte by byte when not.
  CHECK(printable("\xc2\xb5m \xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80") ==
        "\xc2\xb5m \xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80");
  CHECK(printable("\xff\xfe") == "\\xFF\\xFE");
  CHECK(printable("\x80") == "\\x80");                             // a stray continuation byte
  CHECK(printable("\xc3") == "\\xC3");                             // truncated at the end
  CHECK(printable("\xc3(") == "\\xC3(");                           // truncated before ASCII
  CHECK(printable("\xc0\xaf") == "\\xC0\\xAF");                    // overlong '/'
  CHECK(printable("\xe0\x80\xaf") == "\\xE0\\x80\\xAF");           // overlong, 3 bytes
  CHECK(printable("\xed\xa0\x80") == "\\xED\\xA0\\x80");           // a surrogate
  CHECK(printable("\xf4\x90\x80\x80") == "\\xF4\\x90\\x80\\x80");  // above U+10FFFF
  CHECK(printable("\xc2\x9b"
                  "1m") == "\\xC2\\x9B1m");    // C1 control (CSI)
  CHECK(printable("\xc2\xa0") == "\xc2\xa0");  // U+00A0 is not a control
  // Escaping is idempotent (a message escaped twice reads the same), quoting adds quotes.
  const std::string once = printable("x\x01\xff\n");
  CHECK(printable(once) == once);
  CHECK(quoted_text("a\x1b") == "'a\\x1B'");
  // Every byte string gives printable ASCII and valid UTF-8 only.
  std::mt19937_64 rng(38);
  for (int i = 0; i < 2000; ++i) {
    std::string bytes(static_cast<std::size_t>(rng() % 24), '\0');
    for (char& c : bytes) c = static_cast<char>(rng() & 0xff);
    const std::string t = printable(bytes);
    for (std::size_t k = 0; k < t.size(); ++k) {
      const auto b = static_cast<unsigned char>(t[k]);
      REQUIRE((b >= 0x20 && b != 0x7f));
    }
    REQUIRE(printable(t) == t);
  }
  // tp::Error keeps its message printable, whoever built it.
  CHECK(message_of([] { bad_input("--model: unknown conductor model '\x1b[31m\xff'"); }) ==
        "--model: unknown conductor model '\\x1B[31m\\xFF'");
}
