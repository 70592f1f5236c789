#pragma once
/// @file A SEQUENCE OF with a SIZE upper bound, stored inline (no heap on the codec's hot path).

#include <array>
#include <cstddef>
#include <initializer_list>
#include <stdexcept>

namespace tb::its::messages {

template <typename T, std::size_t N>
class BoundedVector {
 public:
  static constexpr std::size_t kCapacity = N;

  BoundedVector() = default;
  BoundedVector(std::initializer_list<T> init) {
    if (init.size() > N)
      throw std::length_error("BoundedVector: initializer longer than capacity");
    for (const T& v : init)
      items_[size_++] = v;
  }

  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  bool full() const { return size_ == N; }
  static constexpr std::size_t capacity() { return N; }

  /// Returns false (and changes nothing) when full.
  bool push_back(const T& v) {
    if (size_ == N)
      return false;
    items_[size_++] = v;
    return true;
  }
  /// Appends a default element and returns it; call only when !full().
  T& emplace_back() {
    items_[size_] = T{};
    return items_[size_++];
  }
  /// Appends the next slot as it is, without resetting it: it holds a default element or what
  /// an earlier use left there. For decoders that assign every member of the element anyway and
  /// whose elements are too large to build a fresh one (T{}) on the stack; call only when
  /// !full().
  T& append_for_overwrite() { return items_[size_++]; }
  void clear() { size_ = 0; }
  /// Shrinks to @p n (n <= size()).
  void resize_down(std::size_t n) {
    if (n < size_)
      size_ = n;
  }

  T& operator[](std::size_t i) { return items_[i]; }
  const T& operator[](std::size_t i) const { return items_[i]; }
  T* begin() { return items_.data(); }
  T* end() { return items_.data() + size_; }
  const T* begin() const { return items_.data(); }
  const T* end() const { return items_.data() + size_; }

  friend bool operator==(const BoundedVector& a, const BoundedVector& b) {
    if (a.size_ != b.size_)
      return false;
    for (std::size_t i = 0; i < a.size_; ++i)
      if (!(a.items_[i] == b.items_[i]))
        return false;
    return true;
  }

 private:
  std::array<T, N> items_{};
  std::size_t size_ = 0;
};

}  // namespace tb::its::messages
