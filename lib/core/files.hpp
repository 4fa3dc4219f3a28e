#pragma once
// Files the programs write, either complete or absent (docs/programs.md, "Files"):
//
//  - a document (a profile, a bank, a curve table, --output) is written whole or not at
//    all: AtomicFile writes a temporary beside it, checks every write, the sync and the
//    close, and renames it over the name only when everything was written;
//  - a record or a log written as it goes (stimctl --record, calibrate --log) is written
//    a whole line at a time by one write(2), each checked, so a full disk is an error and a
//    killed program leaves whole lines behind, never a line cut at a buffer's edge; only
//    the line being written when SIGKILL lands may be cut (Linux ends the write at a
//    page's edge), and only the last.
//
// A place that is not a regular file (a terminal, a pipe, /dev/null, /dev/full) is written
// in place, every write checked; it is never replaced.

#include <cstddef>
#include <string>
#include <string_view>

namespace tp {

class AtomicFile {
 public:
  // Creates the temporary at once, so that an unwritable place is refused (bad input
  // naming `what`, the option or key that gave the path) before any work is done.
  AtomicFile(const std::string& path, const std::string& what);
  // Not committed: the temporary is removed and the file is left as it was.
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  // Appends; a failed write is a runtime failure naming the file and the reason.
  void write(std::string_view text);
  // Syncs, closes and renames the temporary over the file (each step checked).
  void commit();
  const std::string& path() const { return path_; }

 private:
  void discard() noexcept;
  std::string path_, what_, temp_;
  int fd_ = -1;
  int slot_ = -1;  // in the table of temporaries a signal removes
  bool in_place_ = false;
};

// The whole text to `path` through an AtomicFile.
void write_file_atomically(const std::string& path, const std::string& text,
                           const std::string& what);

class LineFile {
 public:
  // Creates or truncates the file (bad input naming `what` when it cannot).
  LineFile(const std::string& path, const std::string& what);
  ~LineFile();
  LineFile(const LineFile&) = delete;
  LineFile& operator=(const LineFile&) = delete;

  // One line (the newline is added), written whole by one write(2); a failed or short
  // write is a runtime failure naming the file and the reason, and a regular file is cut
  // back to the line's start (no cut line left).
  void line(const std::string& text);
  // Bytes that already end in a newline, written whole by one write(2), as line() does.
  void write(const char* data, std::size_t n);
  // Closes, checked; the destructor closes unchecked when close() was not called.
  void close();
  const std::string& path() const { return path_; }

 private:
  std::string path_, what_;
  int fd_ = -1;
};

// Refuses (bad input naming `what`) a path that a LineFile or AtomicFile could not create:
// a directory, or a place whose directory is missing or not writable.  Nothing is created,
// so a run refused later leaves no file and a previous one as it was.
void check_writable(const std::string& path, const std::string& what);

// Removes every AtomicFile temporary still open; async-signal-safe (unlink only), for a
// handler of a signal that ends the program.  The programs' entry point (cli::run) installs
// such handlers for SIGHUP, SIGINT, SIGQUIT, SIGTERM and SIGPIPE; a program that turns
// signals into a flag (stimctl, calibrate) unwinds instead, and the destructors remove them.
void remove_temporaries() noexcept;

}  // namespace tp
