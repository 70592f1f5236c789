#pragma once
/// @file Bounds-checked byte cursors for binary wire formats, in either byte order.
///
/// ByteReader never reads past its span: a read beyond the end sets a sticky failure flag and
/// yields zero, so a decoder can read a whole header and check ok() once.

#include <bit>
#include <cstdint>
#include <cstring>
#include <span>
#include <type_traits>

namespace tb {

enum class Endian { kLittle, kBig };

class ByteReader {
 public:
  explicit ByteReader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}

  template <typename T, Endian E>
  T get() {
    static_assert(std::is_arithmetic_v<T>);
    if (pos_ + sizeof(T) > bytes_.size()) {
      failed_ = true;
      pos_ = bytes_.size();
      return T{};
    }
    std::uint8_t raw[sizeof(T)];
    std::memcpy(raw, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    if constexpr (sizeof(T) > 1) {
      if ((E == Endian::kLittle) != (std::endian::native == std::endian::little)) {
        for (std::size_t i = 0; i < sizeof(T) / 2; ++i)
          std::swap(raw[i], raw[sizeof(T) - 1 - i]);
      }
    }
    T value;
    std::memcpy(&value, raw, sizeof(T));
    return value;
  }
  template <typename T>
  T le() {
    return get<T, Endian::kLittle>();
  }
  template <typename T>
  T be() {
    return get<T, Endian::kBig>();
  }

  /// Copies @p out.size() bytes, or fails without copying.
  bool read(std::span<std::uint8_t> out) {
    if (pos_ + out.size() > bytes_.size()) {
      failed_ = true;
      pos_ = bytes_.size();
      return false;
    }
    if (!out.empty())
      std::memcpy(out.data(), bytes_.data() + pos_, out.size());
    pos_ += out.size();
    return true;
  }
  void skip(std::size_t n) {
    if (pos_ + n > bytes_.size()) {
      failed_ = true;
      pos_ = bytes_.size();
    } else {
      pos_ += n;
    }
  }

  bool ok() const { return !failed_; }
  std::size_t position() const { return pos_; }
  std::size_t remaining() const { return bytes_.size() - pos_; }
  std::span<const std::uint8_t> rest() const { return bytes_.subspan(pos_); }

 private:
  std::span<const std::uint8_t> bytes_;
  std::size_t pos_ = 0;
  bool failed_ = false;
};

/// Writes into a caller-provided span; like ByteReader, overflow sets a sticky failure flag.
class ByteWriter {
 public:
  explicit ByteWriter(std::span<std::uint8_t> out) : out_(out) {}

  template <typename T, Endian E>
  void put(T value) {
    static_assert(std::is_arithmetic_v<T>);
    if (pos_ + sizeof(T) > out_.size()) {
      failed_ = true;
      return;
    }
    std::uint8_t raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    if constexpr (sizeof(T) > 1) {
      if ((E == Endian::kLittle) != (std::endian::native == std::endian::little)) {
        for (std::size_t i = 0; i < sizeof(T) / 2; ++i)
          std::swap(raw[i], raw[sizeof(T) - 1 - i]);
      }
    }
    std::memcpy(out_.data() + pos_, raw, sizeof(T));
    pos_ += sizeof(T);
  }
  template <typename T>
  void le(T v) {
    put<T, Endian::kLittle>(v);
  }
  template <typename T>
  void be(T v) {
    put<T, Endian::kBig>(v);
  }

  void write(std::span<const std::uint8_t> bytes) {
    if (pos_ + bytes.size() > out_.size()) {
      failed_ = true;
      return;
    }
    if (!bytes.empty())
      std::memcpy(out_.data() + pos_, bytes.data(), bytes.size());
    pos_ += bytes.size();
  }

  bool ok() const { return !failed_; }
  std::size_t position() const { return pos_; }

 private:
  std::span<std::uint8_t> out_;
  std::size_t pos_ = 0;
  bool failed_ = false;
};

}  // namespace tb
