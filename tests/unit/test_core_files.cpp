// Files written whole or not at all, and records written a whole line at a time
// (core/files.hpp).
#include <catch2/catch.hpp>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "core/error.hpp"
#include "core/files.hpp"

using namespace tp;
namespace fs = std::filesystem;

namespace {

struct TempDir {
  fs::path dir;
  TempDir() {
    char tmpl[] = "/tmp/tp-files-XXXXXX";
    REQUIRE(mkdtemp(tmpl) != nullptr);
    dir = tmpl;
  }
  ~TempDir() { fs::remove_all(dir); }
  std::size_t entries() const {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), {}));
  }
};

std::string slurp(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

void put(const fs::path& p, const std::string& text) {
  std::ofstream(p) << text;
}

std::string message_of(const std::function<void()>& f, ExitCode expected) {
  try {
    f();
  } catch (const Error& e) {
    CHECK(e.code() == expected);
    return e.what();
  }
  FAIL("no error");
  return "";
}

}  // namespace

TEST_CASE("an atomic file appears whole at commit, and not before", "[io][files]") {
  TempDir t;
  const fs::path p = t.dir / "profile.json";
  put(p, "old\n");
  {
    AtomicFile f(p.string(), "--output");
    f.write("new ");
    f.write("text\n");
    CHECK(slurp(p) == "old\n");  // the old file until the commit
    CHECK(t.entries() == 2);     // beside it, the temporary
    f.commit();
  }
  CHECK(slurp(p) == "new text\n");
  CHECK(t.entries() == 1);
}

TEST_CASE("an atomic file not committed leaves the old file and no temporary", "[io][files]") {
  TempDir t;
  const fs::path p = t.dir / "r.csv";
  put(p, "old\n");
  try {
    AtomicFile f(p.string(), "--recruitment");
    f.write("half");
    throw Error(ExitCode::failure, "interrupted");
  } catch (const Error&) {
  }
  CHECK(slurp(p) == "old\n");
  CHECK(t.entries() == 1);
  // Nor is a new file created.
  { AtomicFile f((t.dir / "new.csv").string(), "--recruitment"); }
  CHECK(!fs::exists(t.dir / "new.csv"));
  CHECK(t.entries() == 1);
}

TEST_CASE("an atomic file keeps an existing file's mode, and follows a link", "[io][files]") {
  TempDir t;
  const fs::path p = t.dir / "doc.json";
  put(p, "old\n");
  fs::permissions(p, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  fs::create_symlink(p, t.dir / "link.json");
  write_file_atomically((t.dir / "link.json").string(), "new\n", "--output");
  CHECK(fs::is_symlink(t.dir / "link.json"));
  CHECK(slurp(p) == "new\n");
  CHECK((fs::status(p).permissions() & fs::perms::all) ==
        (fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read));
}

TEST_CASE("a full device or an unwritable place is an error naming the file", "[io][files]") {
  // /dev/full: written in place (never replaced), and the write fails.
  const std::string full =
      message_of([] { write_file_atomically("/dev/full", std::string(100000, 'x'), "--output"); },
                 ExitCode::failure);
  CHECK(full == "--output: cannot write '/dev/full': No space left on device");
  CHECK(message_of(
            [] {
              LineFile f("/dev/full", "--record");
              f.line(std::string(10, 'x'));
            },
            ExitCode::failure) == "--record: cannot write '/dev/full': No space left on device");
  // Refused before any work: a missing directory, a directory.
  CHECK(message_of([] { AtomicFile f("/nonexistent-dir/x.json", "--output"); },
                   ExitCode::bad_input) ==
        "--output: cannot write '/nonexistent-dir/x.json': No such file or directory");
  CHECK(message_of([] { AtomicFile f("/tmp", "--output"); }, ExitCode::bad_input) ==
        "--output: '/tmp' is a directory");
  CHECK(
      message_of([] { LineFile f("/nonexistent-dir/x.jsonl", "--record"); }, ExitCode::bad_input) ==
      "--record: cannot open '/nonexistent-dir/x.jsonl': No such file or directory");
}

TEST_CASE("a line file writes whole lines, so a killed writer cuts at most the last", "[io][files]") {
  TempDir t;
  const fs::path p = t.dir / "r.jsonl";
  // A child writes lines of 301 bytes (never a divisor of a buffer's 4096) until killed.
  // Each line is one write(2), so every line but the last is whole whatever a buffer's
  // size; the last may be cut, because Linux ends a write to a regular file at a page's
  // edge when SIGKILL arrives inside it (no program can prevent that).
  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    LineFile f(p.string(), "--record");
    for (;;) f.line(std::string(300, 'x'));
  }
  while (!fs::exists(p) || fs::file_size(p) < 100000) usleep(1000);
  kill(child, SIGKILL);
  int status = 0;
  waitpid(child, &status, 0);
  const std::string text = slurp(p);
  const std::size_t end = text.rfind('\n');
  REQUIRE(end != std::string::npos);
  const std::string whole = text.substr(0, end + 1), cut = text.substr(end + 1);
  CHECK(whole.size() >= 100000 - 301);
  CHECK(whole.size() % 301 == 0);
  CHECK(whole == [&] {
    std::string lines;
    for (std::size_t k = 0; k < whole.size() / 301; ++k) lines += std::string(300, 'x') + '\n';
    return lines;
  }());
  CHECK(cut.size() < 301);
  CHECK(cut == std::string(cut.size(), 'x'));
}

TEST_CASE("a line file that cannot be written whole leaves no cut line", "[io][files]") {
  TempDir t;
  const fs::path p = t.dir / "log.csv";
  // A child under a 1000-byte file size limit (SIGXFSZ ignored: write(2) fails with EFBIG)
  // writes lines of 301 bytes: the fourth is cut at byte 1000, then refused.
  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    std::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{1000, 1000};
    setrlimit(RLIMIT_FSIZE, &limit);
    try {
      LineFile f(p.string(), "--log");
      for (int k = 0; k < 10; ++k) f.line(std::string(300, 'x'));
    } catch (const Error& e) {
      _exit(std::string(e.what()) == "--log: cannot write '" + p.string() + "': File too large"
                ? 3
                : 4);
    }
    _exit(5);
  }
  int status = 0;
  waitpid(child, &status, 0);
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 3);
  const std::string text = slurp(p);
  CHECK(text.size() == 3 * 301u);
  CHECK(text.back() == '\n');
}

TEST_CASE("a signal removes the temporaries of files not yet complete", "[io][files]") {
  TempDir t;
  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    AtomicFile f((t.dir / "bank.json").string(), "--output");
    f.write("partial");
    remove_temporaries();  // as the programs' signal handler does
    std::_Exit(0);         // no destructor runs
  }
  int status = 0;
  waitpid(child, &status, 0);
  CHECK(t.entries() == 0);
}
