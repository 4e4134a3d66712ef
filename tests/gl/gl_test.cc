// GL layer: headless context, RAII wrappers, shader embedding, includes, defines and errors.
#include <gtest/gtest.h>

#include <cstdlib>
#include <type_traits>

#include "gl/context.h"
#include "gl/debug.h"
#include "gl/objects.h"
#include "gl/shader_library.h"

namespace hdribr::gl {
namespace {

using Sources = std::map<std::string, std::string>;

static_assert(!std::is_copy_constructible_v<Texture>);
static_assert(!std::is_copy_assignable_v<Program>);
static_assert(std::is_nothrow_move_constructible_v<Buffer>);
static_assert(std::is_nothrow_move_assignable_v<Framebuffer>);

class GlTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { context_ = new HeadlessContext(); }
  static void TearDownTestSuite() {
    delete context_;
    context_ = nullptr;
  }
  void TearDown() override { EXPECT_EQ(DrainGlErrors(), ""); }
  static HeadlessContext* context_;
};
HeadlessContext* GlTest::context_ = nullptr;

TEST_F(GlTest, HeadlessContextIsGl45Core) {
  EXPECT_GE(epoxy_gl_version(), 45);
  EXPECT_FALSE(context_->Renderer().empty());
  EXPECT_FALSE(context_->platform().empty());
  GLint origin = 0;
  glGetIntegerv(GL_CLIP_ORIGIN, &origin);
  EXPECT_EQ(origin, GL_UPPER_LEFT);
}

TEST_F(GlTest, WrappersMoveAndRelease) {
  Texture a = Texture::Create2D(GL_R32F, 8, 4);
  const GLuint id = a.id();
  EXPECT_NE(id, 0u);
  EXPECT_TRUE(glIsTexture(id));
  Texture b = std::move(a);
  EXPECT_TRUE(a.empty());  // NOLINT(bugprone-use-after-move): moved-from state is specified
  EXPECT_EQ(b.id(), id);
  EXPECT_EQ(b.width(), 8);
  b.Reset();
  EXPECT_FALSE(glIsTexture(id));

  Texture arr = Texture::Create2DArray(GL_R32F, 4, 4, 3);
  EXPECT_EQ(arr.layers(), 3);
  Buffer buf(16, nullptr, GL_DYNAMIC_STORAGE_BIT);
  EXPECT_EQ(buf.size(), 16u);
  Framebuffer fb = Framebuffer::Create();
  fb.AttachColor(0, Texture::Create2D(GL_RGBA8, 4, 4));  // texture deleted right after: fine
  VertexArray vao = VertexArray::Create();
  EXPECT_NE(vao.id(), 0u);
}

TEST_F(GlTest, TimestampsAreOrderedAndBracketTheTimerQuery) {
  TimestampQuery before = TimestampQuery::Create(), after = TimestampQuery::Create();
  TimerQuery elapsed = TimerQuery::Create();
  Texture t = Texture::Create2D(GL_R32F, 256, 256);
  const float one = 1.0f;
  before.Stamp();
  elapsed.Begin();
  for (int i = 0; i < 8; ++i) glClearTexImage(t.id(), 0, GL_RED, GL_FLOAT, &one);
  elapsed.End();
  after.Stamp();
  const GLuint64 start = before.ResultNs(), end = after.ResultNs();
  EXPECT_TRUE(before.Available());
  EXPECT_TRUE(after.Available());
  EXPECT_GT(start, 0u);
  ASSERT_LE(start, end);
  // The timer's interval lies between the two stamps (1 us allowed for clock granularity).
  EXPECT_LE(elapsed.ElapsedMs(), static_cast<double>(end - start) * 1e-6 + 1e-3);
}

TEST_F(GlTest, EmbeddedShadersAreThere) {
  const auto& shaders = EmbeddedShaders();
  EXPECT_EQ(shaders.count("splat.vert"), 1u);
  EXPECT_EQ(shaders.count("camera.glsl"), 1u);
  ShaderLibrary lib;
  const std::string src = lib.Preprocess("splat.vert", {{"FOO", "3"}});
  EXPECT_EQ(src.rfind("#version 450 core", 0), 0u);
  EXPECT_NE(src.find("#define FOO 3"), std::string::npos);
  EXPECT_NE(src.find("InsideEllipse"), std::string::npos);  // from the included chunk
  EXPECT_EQ(src.find("#include"), std::string::npos);
}

TEST_F(GlTest, IncludesAndDefinesCompile) {
  ShaderLibrary lib({{"a.comp",
                      "#version 450 core\nlayout(local_size_x = 1) in;\n#include \"b.glsl\"\n"
                      "layout(binding = 0, r32f) uniform image2D img;\n"
                      "void main() { imageStore(img, ivec2(0), vec4(Value() + VALUE)); }\n"},
                     {"b.glsl", "float Value() { return 2.0; }\n"}});
  Program p = lib.Build({"a.comp"}, {{"VALUE", "5.0"}});
  Texture t = Texture::Create2D(GL_R32F, 1, 1);
  p.Use();
  glBindImageTexture(0, t.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  glDispatchCompute(1, 1, 1);
  glMemoryBarrier(GL_ALL_BARRIER_BITS);
  float v = 0;
  glGetTextureImage(t.id(), 0, GL_RED, GL_FLOAT, 4, &v);
  EXPECT_EQ(v, 7.0f);
}

TEST_F(GlTest, CompileErrorNamesFileAndLine) {
  ShaderLibrary lib(
      {{"main.frag",
        "#version 450 core\n#include \"chunk.glsl\"\nout vec4 c;\n"
        "void main() { c = vec4(Good()); }\n"},
       {"chunk.glsl", "float Good() { return 1.0; }\n\nfloat Bad() { return x; }\n"}});
  try {
    lib.Build({"main.frag"}, {{"SOMETHING", "1"}});
    FAIL() << "expected a ShaderError";
  } catch (const ShaderError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("chunk.glsl:3"), std::string::npos) << what;
  }
  ShaderLibrary lib2(
      Sources{{"x.vert", "#version 450 core\nvoid main() {\n  gl_Position = y;\n}\n"}});
  try {
    lib2.Build({"x.vert"}, {{"A", "1"}, {"B", "2"}});
    FAIL() << "expected a ShaderError";
  } catch (const ShaderError& e) {
    EXPECT_NE(std::string(e.what()).find("x.vert:3"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ShaderLibrary(Sources{{"m.frag", "#version 450 core\n#include \"none.glsl\"\n"}})
                   .Preprocess("m.frag"),
               ShaderError);
}

TEST_F(GlTest, EveryEmbeddedShaderCompiles) {
  ShaderLibrary lib;
  EXPECT_NO_THROW(lib.Build({"splat.vert", "splat.frag"}));
  EXPECT_NO_THROW(lib.Build({"project.vert", "project.frag"}, {{"CLASSIFY", "1"}}));
  EXPECT_NO_THROW(lib.Build({"pull.comp"}));
  EXPECT_NO_THROW(lib.Build({"push.comp"}));
  EXPECT_NO_THROW(lib.Build({"resolve.comp"}));
}

TEST(GlWindowTest, WindowContextWhenADisplayExists) {
  if (std::getenv("DISPLAY") == nullptr && std::getenv("WAYLAND_DISPLAY") == nullptr) {
    GTEST_SKIP() << "no DISPLAY: run under xvfb-run to test the GLFW window context";
  }
  WindowContext window(64, 48, "hdribr test", /*visible=*/false);
  EXPECT_GE(epoxy_gl_version(), 45);
  GLint origin = 0;
  glGetIntegerv(GL_CLIP_ORIGIN, &origin);
  EXPECT_EQ(origin, GL_UPPER_LEFT);
  EXPECT_EQ(DrainGlErrors(), "");
}

}  // namespace
}  // namespace hdribr::gl
