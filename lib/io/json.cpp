#include "io/json.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>

#include "core/error.hpp"

namespace tp {

Json read_json(const std::string& path, const std::string& what) {
  std::string text;
  if (path == "-") {
    std::ostringstream ss;
    ss << std::cin.rdbuf();
    text = ss.str();
  } else {
    std::ifstream in(path, std::ios::binary);
    if (!in) bad_input(what + ": cannot open '" + path + "': " + std::strerror(errno));
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    if (in.bad()) bad_input(what + ": cannot read '" + path + "'");
  }
  const std::string name = path == "-" ? "stdin" : "'" + path + "'";
  if (text.find_first_not_of(" \t\r\n") == std::string::npos)
    bad_input(what + ": " + name + " is empty");
  try {
    return Json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    // e.what() is "[json.exception.parse_error.101] parse error at line 1, column 2: ..."
    std::string msg = e.what();
    const auto pos = msg.find("] ");
    if (pos != std::string::npos) msg = msg.substr(pos + 2);
    bad_input(what + ": malformed JSON in " + name + ": " + msg);
  }
}

std::string dump_json(const Json& j) {
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

}  // namespace tp
