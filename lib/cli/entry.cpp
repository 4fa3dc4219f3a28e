#include "cli/entry.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <new>

#include "core/error.hpp"
#include "version.hpp"

namespace tp::cli {
namespace {

// One line: newlines inside a message become "; ".
std::string one_line(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  for (std::size_t p; (p = s.find('\n')) != std::string::npos;) s.replace(p, 1, "; ");
  return s;
}

int report(const std::string& program, const std::string& message, ExitCode code) {
  std::fflush(stdout);
  std::fprintf(stderr, "%s: %s\n", program.c_str(), one_line(message).c_str());
  return static_cast<int>(code);
}

}  // namespace

int run(CLI::App& app, int argc, char** argv, const std::function<void()>& body) {
  const std::string program = app.get_name();
  app.set_version_flag("--version", program + " " + TP_VERSION);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return 0;
  } catch (const CLI::CallForAllHelp&) {
    std::cout << app.help("", CLI::AppFormatMode::All);
    return 0;
  } catch (const CLI::CallForVersion& e) {
    std::cout << e.what() << "\n";
    return 0;
  } catch (const CLI::ParseError& e) {
    return report(program, std::string(e.what()) + " (see --help)", ExitCode::bad_input);
  }
  try {
    body();
    if (std::fflush(stdout) != 0 || std::ferror(stdout))
      failure(std::string("write error on stdout: ") + std::strerror(errno));
    return 0;
  } catch (const Error& e) {
    return report(program, e.what(), e.code());
  } catch (const CLI::Error& e) {
    return report(program, e.what(), ExitCode::bad_input);
  } catch (const std::bad_alloc&) {
    return report(program, "out of memory", ExitCode::failure);
  } catch (const std::exception& e) {
    return report(program, std::string("internal error: ") + e.what(), ExitCode::failure);
  }
}

void write_stdout(const std::string& text) {
  if (std::fwrite(text.data(), 1, text.size(), stdout) != text.size() || std::fflush(stdout) != 0)
    failure(std::string("write error on stdout: ") + std::strerror(errno));
}

}  // namespace tp::cli
