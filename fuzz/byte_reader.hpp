// Reads the fuzz input as a stream of little-endian integers; past the end it
// yields zeros, so every input decodes to something.
#pragma once

#include <cstddef>
#include <cstdint>

namespace ceilnav::fuzz {

class ByteReader {
 public:
  ByteReader(const uint8_t* data, size_t size) : data_(data), size_(size) {}

  bool empty() const { return pos_ >= size_; }
  size_t remaining() const { return pos_ < size_ ? size_ - pos_ : 0; }
  uint8_t u8() { return pos_ < size_ ? data_[pos_++] : uint8_t{0}; }
  uint16_t u16() {
    const uint16_t lo = u8();
    return static_cast<uint16_t>(lo | (u8() << 8));
  }
  int8_t s8() { return static_cast<int8_t>(u8()); }
  bool bit() { return (u8() & 1u) != 0; }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
};

}  // namespace ceilnav::fuzz
