#pragma once
// A buffered CSV writer for large numeric outputs: numbers are formatted with
// std::to_chars into one buffer that is handed on whole (fwrite to a stream, or a sink:
// a program's stdout or --output file), never an iostream per number.

#include <cstdio>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace tp {

// Where a writer's bytes go; it reports a failed write by throwing tp::Error.
using ByteSink = std::function<void(std::string_view)>;

class CsvWriter {
 public:
  explicit CsvWriter(std::FILE* out, std::size_t buffer_bytes = 1 << 16);
  explicit CsvWriter(ByteSink sink, std::size_t buffer_bytes = 1 << 16);
  ~CsvWriter();  // flushes, errors ignored: they are reported by flush(), so call it first
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;

  void header(const std::vector<std::string>& columns);
  void row(const double* values, std::size_t count);
  void row(const std::vector<double>& values) { row(values.data(), values.size()); }
  // Writes out the buffer; throws tp::Error (failure) on an I/O error.
  void flush();

 private:
  void raw(std::string_view s);
  void put(std::string_view s);
  ByteSink sink_;
  std::vector<char> buf_;
  std::size_t used_ = 0;
};

}  // namespace tp
