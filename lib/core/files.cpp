#include "core/files.hpp"

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error.hpp"

namespace tp {
namespace {

// The temporaries a signal removes: strdup'ed paths, published atomically.
constexpr int kSlots = 64;
std::atomic<char*> g_temporaries[kSlots];

int publish(const std::string& path) {
  char* copy = strdup(path.c_str());
  if (!copy) return -1;
  for (int i = 0; i < kSlots; ++i) {
    char* expected = nullptr;
    if (g_temporaries[i].compare_exchange_strong(expected, copy)) return i;
  }
  std::free(copy);
  return -1;
}

void withdraw(int slot) {
  if (slot < 0) return;
  std::free(g_temporaries[slot].exchange(nullptr));
}

std::string reason() {
  return std::strerror(errno);
}

// Writes all of [data, data + n) to fd, retrying after a signal; false with errno set on
// an error (a write that makes no progress is ENOSPC).
bool write_all(int fd, const char* data, std::size_t n) {
  while (n > 0) {
    const ssize_t k = ::write(fd, data, n);
    if (k < 0 && errno == EINTR) continue;
    if (k < 0) return false;
    if (k == 0) {
      errno = ENOSPC;
      return false;
    }
    data += k;
    n -= static_cast<std::size_t>(k);
  }
  return true;
}

// The file a path names, symbolic links followed (the link stays a link); the path itself
// when it does not exist yet.
std::string resolved(const std::string& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return path;
  char* real = ::realpath(path.c_str(), nullptr);
  if (!real) return path;  // a dangling link: created through it by open()
  std::string r(real);
  std::free(real);
  return r;
}

}  // namespace

AtomicFile::AtomicFile(const std::string& path, const std::string& what)
    : path_(path), what_(what) {
  if (path.empty()) bad_input(what + ": empty file name");
  const std::string target = resolved(path);
  struct stat st {};
  if (::stat(target.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    if (S_ISDIR(st.st_mode)) bad_input(what + ": '" + path + "' is a directory");
    // A terminal, pipe or device: written in place, never replaced.
    fd_ = ::open(target.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd_ < 0) bad_input(what + ": cannot open '" + path + "': " + reason());
    in_place_ = true;
    return;
  }
  const auto slash = target.rfind('/');
  const std::string dir = slash == std::string::npos ? "" : target.substr(0, slash + 1);
  const std::string base = slash == std::string::npos ? target : target.substr(slash + 1);
  std::string temp = dir + "." + base + ".XXXXXX";
  fd_ = ::mkostemp(temp.data(), O_CLOEXEC);
  if (fd_ < 0) bad_input(what + ": cannot write '" + path + "': " + reason());
  temp_ = temp;
  slot_ = publish(temp_);
  // mkstemp makes it 0600; a new file gets what open(2) would give it, an existing one
  // keeps its mode.
  mode_t mode = 0;
  if (::stat(target.c_str(), &st) == 0) {
    mode = st.st_mode & 07777;
  } else {
    const mode_t mask = ::umask(0);
    ::umask(mask);
    mode = 0666 & ~mask;
  }
  (void)::fchmod(fd_, mode);
  path_ = target;
}

AtomicFile::~AtomicFile() {
  discard();
}

void AtomicFile::discard() noexcept {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  if (!temp_.empty()) ::unlink(temp_.c_str());
  withdraw(slot_);
  slot_ = -1;
  temp_.clear();
}

void AtomicFile::write(std::string_view text) {
  if (fd_ < 0) failure(what_ + ": '" + path_ + "' is already closed");
  if (!write_all(fd_, text.data(), text.size())) {
    const std::string why = reason();
    discard();
    failure(what_ + ": cannot write '" + path_ + "': " + why);
  }
}

void AtomicFile::commit() {
  if (fd_ < 0) failure(what_ + ": '" + path_ + "' is already closed");
  const bool synced = in_place_ || ::fsync(fd_) == 0;
  const int close_rc = ::close(fd_);
  fd_ = -1;
  if (!synced || close_rc != 0) {
    const std::string why = reason();
    discard();
    failure(what_ + ": cannot write '" + path_ + "': " + why);
  }
  if (in_place_) return;
  if (::rename(temp_.c_str(), path_.c_str()) != 0) {
    const std::string why = reason();
    discard();
    failure(what_ + ": cannot write '" + path_ + "': " + why);
  }
  withdraw(slot_);
  slot_ = -1;
  temp_.clear();
}

void write_file_atomically(const std::string& path, const std::string& text,
                           const std::string& what) {
  AtomicFile f(path, what);
  f.write(text);
  f.commit();
}

LineFile::LineFile(const std::string& path, const std::string& what) : path_(path), what_(what) {
  if (path.empty()) bad_input(what + ": empty file name");
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd_ < 0) bad_input(what + ": cannot open '" + path + "': " + reason());
}

LineFile::~LineFile() {
  if (fd_ >= 0) ::close(fd_);
}

void LineFile::line(const std::string& text) {
  if (fd_ < 0) failure(what_ + ": '" + path_ + "' is already closed");
  std::string whole;
  whole.reserve(text.size() + 1);
  whole += text;
  whole += '\n';
  // Where the line starts (a regular file's end; -1 for a pipe or a device): a write that
  // fails part-way (a size limit, a disk filling up) is cut back to it, so that the file
  // never ends in a cut line.
  const off_t start = ::lseek(fd_, 0, SEEK_CUR);
  if (!write_all(fd_, whole.data(), whole.size())) {
    const std::string why = reason();
    if (start >= 0 && ::ftruncate(fd_, start) == 0) (void)::lseek(fd_, start, SEEK_SET);
    failure(what_ + ": cannot write '" + path_ + "': " + why);
  }
}

void LineFile::write(const char* data, std::size_t n) {
  if (fd_ < 0) failure(what_ + ": '" + path_ + "' is already closed");
  if (!write_all(fd_, data, n)) failure(what_ + ": cannot write '" + path_ + "': " + reason());
}

void LineFile::close() {
  if (fd_ < 0) return;
  const int rc = ::close(fd_);
  fd_ = -1;
  if (rc != 0) failure(what_ + ": cannot write '" + path_ + "': " + reason());
}

void check_writable(const std::string& path, const std::string& what) {
  if (path.empty()) bad_input(what + ": empty file name");
  const std::string target = resolved(path);
  struct stat st {};
  if (::stat(target.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) bad_input(what + ": '" + path + "' is a directory");
    if (::access(target.c_str(), W_OK) != 0)
      bad_input(what + ": cannot open '" + path + "': " + reason());
    return;
  }
  const auto slash = target.rfind('/');
  const std::string dir = slash == std::string::npos ? "." : target.substr(0, slash + 1);
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    bad_input(what + ": cannot open '" + path + "': " + reason());
}

void remove_temporaries() noexcept {
  for (auto& slot : g_temporaries) {
    const char* p = slot.load();
    if (p) ::unlink(p);
  }
}

}  // namespace tp
