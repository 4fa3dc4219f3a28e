#include "core/json.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>
#include <string>
#include <unordered_set>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error.hpp"
#include "core/text.hpp"

namespace tp {

namespace {

// Reads all of fd, at most kMaxDocumentBytes; bad input past that.
std::string read_capped(int fd, const std::string& what, const std::string& name) {
  std::string text;
  char chunk[65536];
  while (true) {
    const ssize_t n = ::read(fd, chunk, sizeof chunk);
    if (n < 0) {
      if (errno == EINTR) continue;
      bad_input(what + ": cannot read " + name + ": " + std::strerror(errno));
    }
    if (n == 0) return text;
    if (text.size() + static_cast<std::size_t>(n) > kMaxDocumentBytes)
      bad_input(what + ": " + name + " is larger than " + std::to_string(kMaxDocumentBytes >> 20) +
                " MiB");
    text.append(chunk, static_cast<std::size_t>(n));
  }
}

}  // namespace

std::string read_input(const std::string& path, const std::string& what, const std::string& kind) {
  const std::string name = path == "-" ? "stdin" : quoted_text(path);
  std::string text;
  if (path == "-") {
    // stdin can be read once: a second reader would find it empty, and say so wrongly.
    static std::string first_reader;
    if (!first_reader.empty())
      bad_input(what + " - and " + first_reader +
                " - both read stdin, which can be read once: give one of them as a file");
    first_reader = what;
    return read_capped(0, what, name);
  }
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) bad_input(what + ": cannot open " + name + ": " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0 || S_ISDIR(st.st_mode)) {
    ::close(fd);
    bad_input(what + ": " + name + " is a directory, not " + kind);
  }
  try {
    text = read_capped(fd, what, name);
  } catch (...) {
    ::close(fd);
    throw;
  }
  ::close(fd);
  return text;
}

Json read_json(const std::string& path, const std::string& what) {
  const std::string name = path == "-" ? "stdin" : quoted_text(path);
  const std::string text = read_input(path, what, "a JSON file");
  return parse_json_text(text, what, name);
}

Json parse_json_strict(const std::string& text, const std::string& where) {
  // No document of the project nests deeper than 4 levels; 64 leaves room for any
  // extension while a 64 MiB "[[[[..." cannot build millions of nested values.  The keys
  // of each open object are kept in a hash set for the duplicate check.  An object has at
  // most kMaxJsonKeys keys: the ordered object of nlohmann's ordered_json finds a key by a
  // linear search, so inserting n keys costs n^2 (200,000 keys took 100 s).
  std::vector<std::unordered_set<std::string>> open_objects;
  const auto check = [&](int depth, Json::parse_event_t event, Json& parsed) {
    if (depth >= kMaxJsonDepth)  // depth counts from 0
      bad_input(where + " nests deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    switch (event) {
      case Json::parse_event_t::object_start:
        open_objects.emplace_back();
        break;
      case Json::parse_event_t::object_end:
        if (!open_objects.empty()) open_objects.pop_back();
        break;
      case Json::parse_event_t::key:
        if (!open_objects.empty() && open_objects.back().size() >= kMaxJsonKeys)
          bad_input(where + ": an object has more than " + std::to_string(kMaxJsonKeys) + " keys");
        if (!open_objects.empty() && !open_objects.back().insert(parsed.get<std::string>()).second)
          bad_input(where + ": key \"" + parsed.get<std::string>().substr(0, 64) +
                    "\" appears twice in one object");
        break;
      default:
        break;
    }
    return true;
  };
  return Json::parse(text, check);
}

Json parse_json_text(const std::string& text, const std::string& what, const std::string& name) {
  if (text.size() > kMaxDocumentBytes)
    bad_input(what + ": " + name + " is larger than " + std::to_string(kMaxDocumentBytes >> 20) +
              " MiB");
  if (text.find_first_not_of(" \t\r\n") == std::string::npos)
    bad_input(what + ": " + name + " is empty");
  try {
    return parse_json_strict(text, what + ": " + name);
  } catch (const nlohmann::json::exception& e) {
    // e.what() is "[json.exception.parse_error.101] parse error at line 1, column 2: ...";
    // a number beyond double range is "[json.exception.out_of_range.406] number overflow ...".
    std::string msg = e.what();
    const auto pos = msg.find("] ");
    if (pos != std::string::npos) msg = msg.substr(pos + 2);
    bad_input(what + ": malformed JSON in " + name + ": " + msg);
  }
}

namespace {
bool all_finite(const Json& j) {
  if (j.is_number_float()) return std::isfinite(j.get<double>());
  if (j.is_structured())
    for (const auto& v : j)
      if (!all_finite(v)) return false;
  return true;
}
}  // namespace

std::string dump_json(const Json& j) {
  // The parameter ranges keep every result finite; a non-finite one is never printed.
  if (!all_finite(j)) failure("a result is not finite (NaN or infinity); nothing printed");
  return j.dump(2) + "\n";
}

double json_finite(const Json& j, const std::string& what) {
  if (!j.is_number()) bad_input(what + ": expected a number");
  const double v = j.get<double>();
  if (!std::isfinite(v)) bad_input(what + ": non-finite number");
  return v;
}

int json_int(const Json& j, const std::string& what) {
  if (!j.is_number_integer() &&
      !(j.is_number_float() && std::floor(j.get<double>()) == j.get<double>()))
    bad_input(what + ": expected an integer");
  const double v = j.get<double>();
  if (std::fabs(v) > 1e9) bad_input(what + ": out of range");
  return static_cast<int>(v);
}

void reject_unknown(const Json& j, const std::set<std::string>& known, const std::string& where) {
  for (auto it = j.begin(); it != j.end(); ++it)
    if (!known.count(it.key())) bad_input(where + ": unknown key " + quoted_text(it.key()));
}

}  // namespace tp
