#pragma once
// JSON input and output shared by all programs.

#include <string>

#include <nlohmann/json.hpp>

namespace tp {

using Json = nlohmann::ordered_json;  // keeps key order, so output is stable and readable

// Reads one JSON document from a file, or from stdin when path is "-".
// Unreadable or malformed input is bad input (exit 2), with a one-line message.
Json read_json(const std::string& path, const std::string& what);

// Serialises with two-space indentation and a trailing newline.
std::string dump_json(const Json& j);

// Helpers for strict field access with messages that name the field.
double json_finite(const Json& j, const std::string& what);
int json_int(const Json& j, const std::string& what);

}  // namespace tp
