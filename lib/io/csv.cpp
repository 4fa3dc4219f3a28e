#include "io/csv.hpp"

#include <cerrno>
#include <cstring>

#include "core/error.hpp"
#include "io/number.hpp"

namespace tp {

CsvWriter::CsvWriter(std::FILE* out, std::size_t buffer_bytes)
    : out_(out), buf_(buffer_bytes < 4096 ? 4096 : buffer_bytes) {}

CsvWriter::~CsvWriter() {
  if (used_ > 0) std::fwrite(buf_.data(), 1, used_, out_);
}

void CsvWriter::raw(std::string_view s) {
  if (used_ + s.size() > buf_.size()) flush();
  if (s.size() > buf_.size()) {
    if (std::fwrite(s.data(), 1, s.size(), out_) != s.size()) failure("write error");
    return;
  }
  std::memcpy(buf_.data() + used_, s.data(), s.size());
  used_ += s.size();
}

void CsvWriter::header(const std::vector<std::string>& columns) {
  std::string line;
  for (std::size_t i = 0; i < columns.size(); ++i) line += (i ? "," : "") + columns[i];
  line += '\n';
  raw(line);
}

void CsvWriter::row(const double* values, std::size_t count) {
  const std::size_t worst = count * 33 + 1;
  if (used_ + worst > buf_.size()) flush();
  if (worst > buf_.size()) buf_.resize(worst);
  char* p = buf_.data() + used_;
  for (std::size_t i = 0; i < count; ++i) {
    if (i) *p++ = ',';
    p += format_number(p, values[i]);
  }
  *p++ = '\n';
  used_ = static_cast<std::size_t>(p - buf_.data());
}

void CsvWriter::flush() {
  if (used_ > 0 && std::fwrite(buf_.data(), 1, used_, out_) != used_) {
    used_ = 0;
    failure(std::string("write error: ") + std::strerror(errno));
  }
  used_ = 0;
  if (std::fflush(out_) != 0) failure(std::string("write error: ") + std::strerror(errno));
}

}  // namespace tp
