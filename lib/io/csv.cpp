#include "io/csv.hpp"

#include <cerrno>
#include <cstring>

#include "core/error.hpp"
#include "core/number.hpp"

namespace tp {

CsvWriter::CsvWriter(std::FILE* out, std::size_t buffer_bytes)
    : CsvWriter(
          [out](std::string_view s) {
            if (std::fwrite(s.data(), 1, s.size(), out) != s.size() || std::fflush(out) != 0)
              failure(std::string("write error: ") + std::strerror(errno));
          },
          buffer_bytes) {}

CsvWriter::CsvWriter(ByteSink sink, std::size_t buffer_bytes)
    : sink_(std::move(sink)), buf_(buffer_bytes < 4096 ? 4096 : buffer_bytes) {}

CsvWriter::~CsvWriter() {
  try {
    if (used_ > 0) sink_(std::string_view(buf_.data(), used_));
  } catch (...) {  // reported by flush(), when it is called
  }
}

void CsvWriter::put(std::string_view s) {
  if (!s.empty()) sink_(s);
}

void CsvWriter::raw(std::string_view s) {
  if (used_ + s.size() > buf_.size()) flush();
  if (s.size() > buf_.size()) {
    put(s);
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
  const std::size_t n = used_;
  used_ = 0;  // not written again by the destructor when the sink fails
  put(std::string_view(buf_.data(), n));
}

}  // namespace tp
