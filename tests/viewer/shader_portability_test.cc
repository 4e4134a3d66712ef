// Every shader program the passes build, as the driver receives it (includes expanded,
// defines injected), also passes glslangValidator, the Khronos reference compiler, with its
// stages linked: CI compiles them with Mesa alone, and other drivers differ in what they let
// through, so the spec's own checker guards the GPU machines' runs.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "gl/context.h"
#include "gl/shader_library.h"
#include "render/blend_pass.h"
#include "render/depth_pass.h"
#include "render/fill_pass.h"
#include "render/point_color_pass.h"
#include "render/pull_push.h"
#include "render/tonemap_pass.h"
#include "test_util.h"
#include "viewer/false_colour_pass.h"
#include "viewer/frustum_pass.h"

namespace hdribr {
namespace {

TEST(ShaderPortability, EveryProgramPassesTheReferenceCompiler) {
  if (std::system("command -v glslangValidator > /dev/null 2>&1") != 0) {
    GTEST_SKIP() << "glslangValidator (Debian package glslang-tools) is absent: skipping";
  }
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  {
    // Every pass that builds programs; their constructors build all of their variants.
    render::DepthPass depth(shaders);
    render::PullPushPass occluding_pull_push(shaders, /*occlude=*/true);
    render::BlendPass blend(shaders);
    render::FillPass fill(shaders);
    render::TonemapPass tonemap(shaders);
    render::PointColorPass point_color(shaders);
    viewer::FalseColourPass false_colour(shaders);
    viewer::FrustumPass frustum(shaders);
  }
  const auto dir = test::TempDir("shader_portability");
  std::set<std::string> covered;
  int index = 0;
  // What the passes built, then every blend program an option can reach.
  std::vector<gl::ShaderLibrary::Variant> variants = shaders.built();
  for (const auto& [file, modes] : render::BlendPass::ReachablePrograms()) {
    variants.push_back({{file}, modes, 0});
  }
  for (const auto& variant : variants) {
    std::string files, label;
    for (const std::string& name : variant.names) {
      covered.insert(name);
      // glslangValidator takes the stage from the extension.
      const auto path = dir / (std::to_string(index) + "_" + name);
      std::ofstream(path) << shaders.Preprocess(name, variant.defines);
      files += " " + path.string();
      label += name + " ";
    }
    for (const auto& [key, value] : variant.defines) label += key + "=" + value + " ";
    ++index;
    const auto r = test::RunCommand("glslangValidator -l" + files);
    EXPECT_EQ(r.exit_code, 0) << label << "\n" << r.output;
  }
  EXPECT_GE(index, 20);
  // A new stage file must come with its pass above.
  for (const auto& [name, text] : gl::EmbeddedShaders()) {
    const std::string ext = name.substr(name.find_last_of('.') + 1);
    if (ext == "vert" || ext == "frag" || ext == "comp") {
      EXPECT_TRUE(covered.count(name)) << name << " is built by no pass of this test";
    }
  }
}

}  // namespace
}  // namespace hdribr
