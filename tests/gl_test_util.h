// A GoogleTest suite base for GL tests: one headless OpenGL 4.5 context and shader library
// shared by the suite's tests, and no GL error left after each test.
#pragma once

#include <gtest/gtest.h>

#include <memory>

#include "gl/context.h"
#include "gl/debug.h"
#include "gl/shader_library.h"

namespace hdribr::test {

// Derive a suite from it; a suite with its own SetUpTestSuite calls this one's first.
class GlSuite : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    context_ = std::make_unique<gl::HeadlessContext>();
    shaders_ = std::make_unique<gl::ShaderLibrary>();
  }
  static void TearDownTestSuite() {
    shaders_.reset();
    context_.reset();
  }
  void TearDown() override { EXPECT_EQ(gl::DrainGlErrors(), ""); }

  static inline std::unique_ptr<gl::HeadlessContext> context_;
  static inline std::unique_ptr<gl::ShaderLibrary> shaders_;
};

}  // namespace hdribr::test
