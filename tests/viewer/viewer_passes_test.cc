// The viewer's GPU passes on a headless context: the false-colour displays equal the CPU
// pictures of `hdribr render --debug` (FalseColour, io/false_colour.h), and frustum lines are
// hidden exactly where the scene's depth is nearer.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "gl/context.h"
#include "gl/shader_library.h"
#include "io/false_colour.h"
#include "render/renderer.h"
#include "viewer/false_colour_pass.h"
#include "viewer/frustum_pass.h"

namespace hdribr::viewer {
namespace {

cv::Mat ReadRgba8(const gl::Texture& t) {
  cv::Mat rgba(t.height(), t.width(), CV_8UC4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(t.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE,
                    static_cast<GLsizei>(rgba.total() * rgba.elemSize()), rgba.ptr());
  return rgba;
}

// Pixels whose RGB differs by more than one level, and whether alpha is 255 exactly on `valid`.
int Mismatches(const cv::Mat& rgba, const cv::Mat& expected_bgr, const cv::Mat& valid,
               bool* alpha_ok) {
  cv::Mat bgr;
  cv::cvtColor(rgba, bgr, cv::COLOR_RGBA2BGR);
  cv::Mat diff;
  cv::absdiff(bgr, expected_bgr, diff);
  std::vector<cv::Mat> d, c;
  cv::split(diff, d);
  cv::split(rgba, c);
  *alpha_ok = cv::countNonZero((c[3] > 0) != (valid > 0)) == 0;
  return cv::countNonZero(cv::max(cv::max(d[0], d[1]), d[2]) > 1);
}

TEST(ViewerFalseColourPass, EqualsTheCpuDebugPictures) {
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  FalseColourPass pass(shaders);
  const int w = 40, h = 30, photos = 8;
  render::RenderTarget target = render::RenderTarget::Create(w, h);
  cv::Mat depth(h, w, CV_32FC1), normal(h, w, CV_32FC4), aux(h, w, CV_32FC4);
  cv::RNG rng(3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      depth.at<float>(y, x) = (x + y) % 7 == 0 ? 0.0f : 2.0f + 0.1f * x + 0.037f * y;
      cv::Vec3f n(rng.uniform(-1.f, 1.f), rng.uniform(-1.f, 1.f), rng.uniform(-1.f, -0.1f));
      n /= cv::norm(n);
      normal.at<cv::Vec4f>(y, x) = cv::Vec4f(n[0], n[1], n[2], 0);
      aux.at<cv::Vec4f>(y, x) = cv::Vec4f(static_cast<float>((x * 3 + y) % (photos + 1)), 0, 0, 0);
    }
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTextureSubImage2D(target.depth.depth.id(), 0, 0, 0, w, h, GL_RED, GL_FLOAT, depth.ptr());
  glTextureSubImage2D(target.depth.normal.id(), 0, 0, 0, w, h, GL_RGBA, GL_FLOAT, normal.ptr());
  glTextureSubImage2D(target.aux.id(), 0, 0, 0, w, h, GL_RGBA, GL_FLOAT, aux.ptr());
  gl::Texture display = gl::Texture::Create2D(GL_RGBA8, w, h);
  const cv::Mat valid = depth > 0;

  // Depth: turbo over the valid range, near = red (as `hdribr render --debug depth`).
  pass.Apply(FalseColourMap::kDepth, target, photos, display);
  double lo = 0, hi = 0;
  cv::minMaxLoc(depth, &lo, &hi, nullptr, nullptr, valid);
  bool alpha_ok = false;
  cv::Mat expected = FalseColour(-depth, -hi, -lo, valid);
  EXPECT_LE(Mismatches(ReadRgba8(display), expected, valid, &alpha_ok), w * h / 100);
  EXPECT_TRUE(alpha_ok);

  // Normals: n / 2 + 1/2, RGB = xyz.
  pass.Apply(FalseColourMap::kNormals, target, photos, display);
  cv::Mat n3;
  cv::cvtColor(normal, n3, cv::COLOR_RGBA2BGR);
  n3.convertTo(expected, CV_8UC3, 127.5, 127.5);
  expected.setTo(cv::Scalar(0, 0, 0), valid == 0);
  EXPECT_EQ(Mismatches(ReadRgba8(display), expected, valid, &alpha_ok), 0);
  EXPECT_TRUE(alpha_ok);

  // Count: turbo over [0, photos].
  pass.Apply(FalseColourMap::kCount, target, photos, display);
  std::vector<cv::Mat> a;
  cv::split(aux, a);
  expected = FalseColour(a[0], 0, photos, valid);
  EXPECT_EQ(Mismatches(ReadRgba8(display), expected, valid, &alpha_ok), 0);
  EXPECT_TRUE(alpha_ok);
  // Classes: front orange, background-filled blue, anything else grey (where depth is valid).
  cv::Mat classes(h, w, CV_8UC1);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) classes.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(x % 3);
  }
  gl::Texture class_texture = gl::Texture::Create2D(GL_R8UI, w, h);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(class_texture.id(), 0, 0, 0, w, h, GL_RED_INTEGER, GL_UNSIGNED_BYTE,
                      classes.ptr());
  pass.Apply(FalseColourMap::kClasses, target, photos, display, &class_texture);
  const auto to8 = [](const float* c) {
    return cv::Vec3b(static_cast<std::uint8_t>(std::lround(c[2] * 255)),
                     static_cast<std::uint8_t>(std::lround(c[1] * 255)),
                     static_cast<std::uint8_t>(std::lround(c[0] * 255)));
  };
  expected.create(h, w, CV_8UC3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const int c = classes.at<std::uint8_t>(y, x);
      expected.at<cv::Vec3b>(y, x) = !valid.at<std::uint8_t>(y, x) ? cv::Vec3b(0, 0, 0)
                                     : c == 1                      ? to8(kFrontColour)
                                     : c == 2                      ? to8(kFilledColour)
                                                                   : cv::Vec3b(128, 128, 128);
    }
  }
  EXPECT_EQ(Mismatches(ReadRgba8(display), expected, valid, &alpha_ok), 0);
  EXPECT_TRUE(alpha_ok);

  // The pictures do differ from each other (the test is not vacuous).
  cv::Mat depth_rgba;
  pass.Apply(FalseColourMap::kDepth, target, photos, display);
  depth_rgba = ReadRgba8(display);
  EXPECT_GT(Mismatches(depth_rgba, expected, valid, &alpha_ok), w * h / 4);
}

// One photo 3 units in front of the view camera, looking the same way; its frustum (depth 1)
// spans camera z 3 ... 4 of the view.
Scene OnePhotoScene(const Camera& camera) {
  Scene scene;
  scene.cameras[camera.id] = camera;
  Photo p;
  p.id = 1;
  p.name = "p.jpg";
  p.camera_id = camera.id;
  p.cam_from_world.translation = Eigen::Vector3d(0, 0, -3);
  scene.photos.push_back(p);
  return scene;
}

TEST(ViewerFrustumPass, LinesHiddenWhereTheSceneIsNearer) {
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  const Camera camera = Camera::Pinhole(1, 64, 48, 50, 50, 32, 24);
  const Scene scene = OnePhotoScene(camera);
  const FrustumLines lines = MakeFrustumLines(scene, 1.0);
  ASSERT_EQ(lines.points.size(), 16u);  // 8 segments
  EXPECT_TRUE(lines.points[0].isApprox(Eigen::Vector3f(0, 0, 3)));
  FrustumPass pass(shaders);
  pass.SetLines(lines);
  EXPECT_EQ(pass.segments(), 8u);

  gl::Texture depth = gl::Texture::Create2D(GL_R32F, 64, 48);
  gl::Texture colour = gl::Texture::Create2D(GL_RGBA8, 64, 48);
  gl::Framebuffer fb = gl::Framebuffer::Create();
  fb.AttachColor(0, colour);
  fb.SetDrawBuffers(1);
  fb.CheckComplete();
  // Pixels drawn with the scene at camera z `scene_z` everywhere (0 = no scene).
  auto drawn = [&](float scene_z, int highlight, cv::Mat* out = nullptr) {
    glClearTexImage(depth.id(), 0, GL_RED, GL_FLOAT, &scene_z);
    glClearTexImage(colour.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    pass.Draw(camera, Rigid3d(), depth, fb, highlight);
    const cv::Mat rgba = ReadRgba8(colour);
    if (out) *out = rgba;
    std::vector<cv::Mat> c;
    cv::split(rgba, c);
    return cv::countNonZero(c[3]);
  };
  cv::Mat none_rgba;
  const int none = drawn(0.0f, -1, &none_rgba);
  EXPECT_GT(none, 40);                 // apex-to-corner lines and the far rectangle
  EXPECT_EQ(drawn(10.0f, -1), none);   // scene behind every line
  EXPECT_EQ(drawn(2.5f, -1), 0);       // scene in front of every line: all hidden
  const int partly = drawn(3.5f, -1);  // the far rectangle and the far half hidden
  EXPECT_GT(partly, 5);
  EXPECT_LT(partly, none);
  // Colours: every drawn pixel has the normal colour, or the highlight colour for photo 0.
  auto count_colour = [](const cv::Mat& rgba, const cv::Vec4b& c) {
    cv::Mat eq;
    cv::inRange(rgba, c, c, eq);
    return cv::countNonZero(eq);
  };
  EXPECT_EQ(count_colour(none_rgba, cv::Vec4b(79, 199, 255, 255)), none);
  cv::Mat hl;
  drawn(0.0f, 0, &hl);
  EXPECT_EQ(count_colour(hl, cv::Vec4b(255, 199, 0, 255)), none);
  // A candidate photo gets the candidate colour (the highlight still wins); out-of-range
  // indices are ignored; no candidates, the normal colour again.
  const cv::Vec4b candidate(89, 255, 89, 255);
  pass.SetCandidates({0, 7, -1});
  cv::Mat cand;
  drawn(0.0f, -1, &cand);
  EXPECT_EQ(count_colour(cand, candidate), none);
  drawn(0.0f, 0, &hl);
  EXPECT_EQ(count_colour(hl, cv::Vec4b(255, 199, 0, 255)), none);
  pass.SetCandidates({});
  drawn(0.0f, -1, &cand);
  EXPECT_EQ(count_colour(cand, cv::Vec4b(79, 199, 255, 255)), none);
  // A view 10 units behind (every vertex at camera z 13 ... 14): drawn, smaller; a view past
  // the frustum (every vertex behind the camera): nothing.
  Rigid3d away;
  away.translation = Eigen::Vector3d(0, 0, 10);
  glClearTexImage(colour.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  const float zero = 0.0f;
  glClearTexImage(depth.id(), 0, GL_RED, GL_FLOAT, &zero);
  pass.Draw(camera, away, depth, fb);  // every vertex at camera z > 10: drawn, small
  std::vector<cv::Mat> c;
  cv::split(ReadRgba8(colour), c);
  EXPECT_GT(cv::countNonZero(c[3]), 0);
  away.translation = Eigen::Vector3d(0, 0, -10);  // everything behind the camera
  glClearTexImage(colour.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  pass.Draw(camera, away, depth, fb);
  cv::split(ReadRgba8(colour), c);
  EXPECT_EQ(cv::countNonZero(c[3]), 0);
}

}  // namespace
}  // namespace hdribr::viewer
