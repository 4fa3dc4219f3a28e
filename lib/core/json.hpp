#pragma once
// JSON input and output shared by all programs.

#include <cstddef>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

namespace tp {

using Json = nlohmann::ordered_json;  // keeps key order, so output is stable and readable

// The largest document any program reads: 64 MiB (a design document is a few KiB; a
// receptor table or stimulus of any useful size is far below).
inline constexpr std::size_t kMaxDocumentBytes = std::size_t{64} << 20;
// The deepest nesting of arrays and objects a document may have.
inline constexpr int kMaxJsonDepth = 64;
// Keys of one object (no document of the project has more than a few dozen).
inline constexpr std::size_t kMaxJsonKeys = 1000;

// Reads one JSON document from a file, or from stdin when path is "-".  Unreadable,
// oversized (kMaxDocumentBytes), malformed input, a directory, and numbers beyond the
// range of a double are bad input (exit 2), with a one-line message.  stdin is read once
// per process: a second "-" is bad input naming both readers (never "stdin is empty").
Json read_json(const std::string& path, const std::string& what);
// The bytes of a file, or of stdin for "-" (once per process), at most kMaxDocumentBytes:
// bad input naming `what` otherwise (`kind`: what a directory is not, "a JSON file").
std::string read_input(const std::string& path, const std::string& what, const std::string& kind);
// The parsing half of read_json: `name` says where the text came from.
Json parse_json_text(const std::string& text, const std::string& what, const std::string& name);
// The parser both use: nesting deeper than kMaxJsonDepth and an object key given twice
// (JSON leaves its meaning undefined; the parser would silently keep the last) are bad
// input, "<where> ...".  Malformed text throws nlohmann::json::exception.
Json parse_json_strict(const std::string& text, const std::string& where);

// Serialises with two-space indentation and a trailing newline.
std::string dump_json(const Json& j);

// Helpers for strict field access with messages that name the field.
double json_finite(const Json& j, const std::string& what);
int json_int(const Json& j, const std::string& what);
// Bad input, "<where>: unknown key 'k'", for a key of object j outside `known`.
void reject_unknown(const Json& j, const std::set<std::string>& known, const std::string& where);

}  // namespace tp
