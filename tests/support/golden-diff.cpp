// golden-diff: compares an output with its golden file, numbers within a tolerance, and
// reports the first differing cell.  CSV (by header and row) or JSON (by path).
//
//   golden-diff [--rtol R] [--atol A] EXPECTED ACTUAL
//
// With TP_REGEN=1 in the environment it copies ACTUAL over EXPECTED instead
// (scripts/regen-golden), so the golden files are made by the very commands that test them.
// Exit status: 0 same, 1 different, 2 usage or unreadable file.

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace {

double rel_tol = 1e-9, abs_tol = 1e-12;

bool read_file(const std::string& path, std::string& out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream ss;
  ss << in.rdbuf();
  out = ss.str();
  return true;
}

bool parse_number(const std::string& s, double& v) {
  if (s.empty()) return false;
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size();
}

bool close(double a, double b) {
  return std::fabs(a - b) <= abs_tol + rel_tol * std::max(std::fabs(a), std::fabs(b));
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream ss(line);
  while (std::getline(ss, cell, ',')) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream ss(text);
  std::string l;
  while (std::getline(ss, l)) lines.push_back(l);
  return lines;
}

int diff_csv(const std::string& a, const std::string& b) {
  const auto ea = lines_of(a), eb = lines_of(b);
  if (ea.empty() || eb.empty()) {
    std::cerr << "golden-diff: empty CSV\n";
    return 1;
  }
  if (ea[0] != eb[0]) {
    std::cerr << "golden-diff: header differs: expected '" << ea[0] << "', got '" << eb[0] << "'\n";
    return 1;
  }
  const auto header = split(ea[0]);
  for (std::size_t r = 1; r < std::min(ea.size(), eb.size()); ++r) {
    const auto ca = split(ea[r]), cb = split(eb[r]);
    if (ca.size() != cb.size()) {
      std::cerr << "golden-diff: row " << r << ": expected " << ca.size() << " cells, got "
                << cb.size() << "\n";
      return 1;
    }
    for (std::size_t c = 0; c < ca.size(); ++c) {
      double va = 0, vb = 0;
      const bool na = parse_number(ca[c], va), nb = parse_number(cb[c], vb);
      const bool same = (na && nb) ? close(va, vb) : ca[c] == cb[c];
      if (!same) {
        std::cerr << "golden-diff: row " << r << ", column "
                  << (c < header.size() ? header[c] : std::to_string(c)) << ": expected " << ca[c]
                  << ", got " << cb[c] << "\n";
        return 1;
      }
    }
  }
  if (ea.size() != eb.size()) {
    std::cerr << "golden-diff: expected " << ea.size() - 1 << " data rows, got " << eb.size() - 1
              << "\n";
    return 1;
  }
  return 0;
}

// Keys whose values legitimately vary between runs (timings) are not compared.
bool ignored_key(const std::string& k) {
  return k == "time_s" || k == "time_ms";
}

bool diff_json(const nlohmann::ordered_json& a, const nlohmann::ordered_json& b,
               const std::string& path) {
  const std::string where = path.empty() ? "(root)" : path;
  if (a.is_number() && b.is_number()) {
    if (close(a.get<double>(), b.get<double>())) return true;
    std::cerr << "golden-diff: " << where << ": expected " << a.dump() << ", got " << b.dump()
              << "\n";
    return false;
  }
  if (a.type() != b.type()) {
    std::cerr << "golden-diff: " << where << ": expected " << a.type_name() << " " << a.dump()
              << ", got " << b.type_name() << " " << b.dump() << "\n";
    return false;
  }
  if (a.is_object()) {
    for (auto it = a.begin(); it != a.end(); ++it) {
      if (ignored_key(it.key())) continue;
      if (!b.contains(it.key())) {
        std::cerr << "golden-diff: " << (path.empty() ? "" : path + ".") << it.key()
                  << ": missing\n";
        return false;
      }
      if (!diff_json(it.value(), b[it.key()], (path.empty() ? "" : path + ".") + it.key()))
        return false;
    }
    for (auto it = b.begin(); it != b.end(); ++it)
      if (!a.contains(it.key())) {
        std::cerr << "golden-diff: " << (path.empty() ? "" : path + ".") << it.key()
                  << ": unexpected key\n";
        return false;
      }
    return true;
  }
  if (a.is_array()) {
    if (a.size() != b.size()) {
      std::cerr << "golden-diff: " << where << ": expected " << a.size() << " elements, got "
                << b.size() << "\n";
      return false;
    }
    for (std::size_t i = 0; i < a.size(); ++i)
      if (!diff_json(a[i], b[i], path + "[" + std::to_string(i) + "]")) return false;
    return true;
  }
  if (a != b) {
    std::cerr << "golden-diff: " << where << ": expected " << a.dump() << ", got " << b.dump()
              << "\n";
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if ((a == "--rtol" || a == "--atol") && i + 1 < argc) {
      (a == "--rtol" ? rel_tol : abs_tol) = std::atof(argv[++i]);
    } else {
      files.push_back(a);
    }
  }
  if (files.size() != 2) {
    std::cerr << "usage: golden-diff [--rtol R] [--atol A] EXPECTED ACTUAL\n";
    return 2;
  }
  std::string a, b;
  if (!read_file(files[1], b)) {
    std::cerr << "golden-diff: cannot read " << files[1] << "\n";
    return 2;
  }
  if (const char* regen = std::getenv("TP_REGEN"); regen && std::string(regen) == "1") {
    std::ofstream out(files[0], std::ios::binary);
    out << b;
    std::cerr << "golden-diff: wrote " << files[0] << "\n";
    return out ? 0 : 2;
  }
  if (!read_file(files[0], a)) {
    std::cerr << "golden-diff: cannot read " << files[0] << " (run scripts/regen-golden)\n";
    return 2;
  }
  const bool is_json = files[0].size() > 5 && files[0].substr(files[0].size() - 5) == ".json";
  if (is_json) {
    try {
      return diff_json(nlohmann::ordered_json::parse(a), nlohmann::ordered_json::parse(b), "") ? 0
                                                                                               : 1;
    } catch (const std::exception& e) {
      std::cerr << "golden-diff: invalid JSON: " << e.what() << "\n";
      return 1;
    }
  }
  return diff_csv(a, b);
}
