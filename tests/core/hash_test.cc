// FNV-1a 64: the published test vectors, and what the typed helpers feed it.
#include "core/hash.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

namespace hdribr {
namespace {

std::uint64_t HashOf(const std::string& bytes) {
  return Fnv1a64().AddBytes(bytes.data(), bytes.size()).value();
}

TEST(Fnv1a64Test, PublishedVectors) {
  EXPECT_EQ(HashOf(""), 0xcbf29ce484222325ULL);
  EXPECT_EQ(HashOf("a"), 0xaf63dc4c8601ec8cULL);
  EXPECT_EQ(HashOf("foobar"), 0x85944171f73967e8ULL);
}

TEST(Fnv1a64Test, IncrementalEqualsWhole) {
  Fnv1a64 h;
  h.AddBytes("foo", 3).AddBytes("bar", 3);
  EXPECT_EQ(h.value(), HashOf("foobar"));
}

TEST(Fnv1a64Test, NumbersAndStrings) {
  const std::uint32_t one = 1;
  EXPECT_EQ(Fnv1a64().Add(one).value(), HashOf(std::string("\x01\x00\x00\x00", 4)));
  EXPECT_NE(Fnv1a64().Add(1.0f).value(), Fnv1a64().Add(1.0).value());
  EXPECT_NE(Fnv1a64().Add(0.0f).value(), Fnv1a64().Add(-0.0f).value());
  // Lengths are hashed: the split of a text between strings matters.
  EXPECT_NE(Fnv1a64().AddString("ab").AddString("c").value(),
            Fnv1a64().AddString("a").AddString("bc").value());
  EXPECT_EQ(Fnv1a64().AddString("abc").value(), Fnv1a64().AddString("abc").value());
}

}  // namespace
}  // namespace hdribr
