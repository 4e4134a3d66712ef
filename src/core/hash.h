// A stable 64-bit hash of bytes (FNV-1a), for cache keys and file checksums; not cryptographic.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <type_traits>

namespace hdribr {

// 64-bit FNV-1a (Fowler, Noll, Vo): the same bytes give the same value on every run and build.
class Fnv1a64 {
 public:
  static constexpr std::uint64_t kOffsetBasis = 0xcbf29ce484222325ULL;
  static constexpr std::uint64_t kPrime = 0x100000001b3ULL;

  // Hashes `size` bytes at `data`.
  Fnv1a64& AddBytes(const void* data, size_t size);
  // Hashes the bytes of a number as stored in memory.
  template <typename T>
  Fnv1a64& Add(T value) {
    static_assert(std::is_arithmetic_v<T>, "numbers only: use AddBytes or AddString");
    return AddBytes(&value, sizeof(value));
  }
  // Hashes the length, then the characters (so that "ab" + "c" differs from "a" + "bc").
  Fnv1a64& AddString(std::string_view text);

  std::uint64_t value() const { return state_; }

 private:
  std::uint64_t state_ = kOffsetBasis;
};

}  // namespace hdribr
