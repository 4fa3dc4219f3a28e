#pragma once
// A byte buffer of fixed capacity, for the device core: no allocation, so the firmware
// build has no heap.  (Debian packages no embedded container library: its etl-dev is
// synfig's "Extended Class and Template Library", not the Embedded Template Library.)
// Appending beyond the capacity is refused and remembered (overflowed()), never written.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

namespace tp::device {

template <std::size_t N>
class FixedBytes {
 public:
  FixedBytes() = default;

  std::size_t size() const { return size_; }
  static constexpr std::size_t capacity() { return N; }
  bool empty() const { return size_ == 0; }
  bool overflowed() const { return overflowed_; }
  const std::uint8_t* data() const { return bytes_.data(); }
  const std::uint8_t* begin() const { return bytes_.data(); }
  const std::uint8_t* end() const { return bytes_.data() + size_; }
  std::uint8_t operator[](std::size_t i) const { return bytes_[i]; }

  void clear() {
    size_ = 0;
    overflowed_ = false;
  }
  void push_back(std::uint8_t b) {
    if (size_ == N) {
      overflowed_ = true;
      return;
    }
    bytes_[size_++] = b;
  }
  void append(const std::uint8_t* p, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) push_back(p[i]);
  }
  void assign(const std::uint8_t* first, const std::uint8_t* last) {
    clear();
    append(first, static_cast<std::size_t>(last - first));
  }

  // Equal contents, against any contiguous byte container (a std::vector in host tests).
  template <class C>
  bool same_as(const C& other) const {
    return other.size() == size_ && std::equal(begin(), end(), other.data());
  }
  friend bool operator==(const FixedBytes& a, const FixedBytes& b) { return a.same_as(b); }

 private:
  std::array<std::uint8_t, N> bytes_{};
  std::size_t size_ = 0;
  bool overflowed_ = false;
};

}  // namespace tp::device
