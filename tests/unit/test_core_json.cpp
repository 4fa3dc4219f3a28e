// JSON text (core/json): a key given twice.
#include <catch2/catch.hpp>

#include <string>

#include "core/error.hpp"
#include "core/json.hpp"

using namespace tp;

TEST_CASE("an object key given twice is refused, the same key in two objects is not",
          "[io][json]") {
  // JSON leaves a repeated key undefined and nlohmann keeps the last silently: a document
  // or a live frame with {"currents_mA": [...], "currents_mA": [...]} is ambiguous.
  const auto refused = [](const std::string& text) {
    try {
      parse_json_text(text, "test", "text");
      return std::string();
    } catch (const Error& e) {
      CHECK(e.code() == ExitCode::bad_input);
      return std::string(e.what());
    }
  };
  CHECK(refused(R"({"a": 1, "a": 2})").find("key \"a\" appears twice") != std::string::npos);
  CHECK(refused(R"({"x": {"b": [1, {"c": 1, "c": 1}]}})").find("\"c\"") != std::string::npos);
  CHECK(refused(R"({"a": {"b": 1}, "c": {"b": 2}, "b": [{"b": 1}, {"b": 2}]})").empty());
  // An object of kMaxJsonKeys keys parses; one more key is refused at once (ordered_json
  // inserts in linear time, so 200,000 keys took 100 s before the cap).
  std::string big = "{";
  for (std::size_t i = 0; i < kMaxJsonKeys; ++i)
    big += (i ? ",\"k" : "\"k") + std::to_string(i) + "\":0";
  CHECK(refused(big + "}").empty());
  CHECK(refused(big + ",\"k7\":1}").find("appears twice") == std::string::npos);
  CHECK(refused(big + ",\"k7\":1}").find("more than 1000 keys") != std::string::npos);
  std::string huge = "{";
  for (int i = 0; i < 200000; ++i) huge += (i ? ",\"k" : "\"k") + std::to_string(i) + "\":0";
  const auto t0 = std::chrono::steady_clock::now();
  CHECK(refused(huge + "}").find("more than 1000 keys") != std::string::npos);
  CHECK(std::chrono::steady_clock::now() - t0 < std::chrono::seconds(5));
  // A duplicate within the cap is still a duplicate.
  std::string dup = "{";
  for (int i = 0; i < 999; ++i) dup += (i ? ",\"k" : "\"k") + std::to_string(i) + "\":0";
  CHECK(refused(dup + ",\"k998\":1}").find("appears twice") != std::string::npos);
}
