#include "core/hash.h"

namespace hdribr {

Fnv1a64& Fnv1a64::AddBytes(const void* data, size_t size) {
  const auto* p = static_cast<const unsigned char*>(data);
  std::uint64_t h = state_;
  for (size_t i = 0; i < size; ++i) {
    h ^= p[i];
    h *= kPrime;
  }
  state_ = h;
  return *this;
}

Fnv1a64& Fnv1a64::AddString(std::string_view text) {
  Add<std::uint64_t>(text.size());
  return AddBytes(text.data(), text.size());
}

}  // namespace hdribr
