#include "synth/scene_layouts.h"

#include <cmath>
#include <numbers>

#include "core/error.h"
#include "synth/camera_response.h"

namespace hdribr::synth {
namespace {

using Eigen::Vector3d;

Shape Rect(const Vector3d& c, const Vector3d& u, const Vector3d& v, double hu, double hv, int mat) {
  Shape s;
  s.kind = ShapeKind::kRectangle;
  s.centre = c;
  s.axis_u = u;
  s.axis_v = v;
  s.half_size = Vector3d(hu, hv, 0);
  s.material = mat;
  return s;
}

Shape Sphere(const Vector3d& c, double r, int mat) {
  Shape s;
  s.kind = ShapeKind::kSphere;
  s.centre = c;
  s.radius = r;
  s.material = mat;
  return s;
}

Shape Box(const Vector3d& c, const Vector3d& half, double yaw, int mat) {
  Shape s;
  s.kind = ShapeKind::kBox;
  s.centre = c;
  s.half_size = half;
  s.yaw = yaw;
  s.material = mat;
  return s;
}

// Vertical capped cylinder standing on base (x, y, z0).
Shape Cylinder(const Vector3d& base, double r, double height, int mat) {
  Shape s;
  s.kind = ShapeKind::kCylinder;
  s.centre = base;
  s.radius = r;
  s.half_size = Vector3d(r, r, 0.5 * height);
  s.material = mat;
  return s;
}

Material Mat(TextureKind kind, const Vector3d& a, const Vector3d& b, double scale, double grain,
             const Vector3d& stripe_axis = Vector3d::UnitZ()) {
  Material m;
  m.texture.kind = kind;
  m.texture.colour_a = a;
  m.texture.colour_b = b;
  m.texture.scale = scale;
  m.texture.grain = grain;
  m.texture.stripe_axis = stripe_axis.normalized();
  return m;
}

// Lights, ground, back wall and the emissive panel shared by every scene. Material ids 0..2.
// Lights, ground, back wall and the emissive panel shared by every scene. Material ids 0..2.
void AddCommon(SynthScene& s) {
  s.sun_direction = Vector3d(0.45, -0.55, 0.75).normalized();
  s.sun_irradiance = Vector3d(3.0, 2.85, 2.6);
  s.ambient = Vector3d(0.10, 0.12, 0.16);
  s.look_at = Vector3d(0.0, 0.1, 0.25);
  s.size = 1.0;
  s.materials.push_back(
      Mat(TextureKind::kChecker, {0.55, 0.50, 0.45}, {0.10, 0.10, 0.12}, 8.0, 0.35));
  s.materials.push_back(Mat(TextureKind::kNoise, {0.70, 0.65, 0.50}, {0.20, 0.26, 0.38}, 7.0, 0.2));
  Material emitter = Mat(TextureKind::kSolid, {0.05, 0.05, 0.05}, {0.05, 0.05, 0.05}, 1.0, 0.0);
  emitter.emission = Vector3d(30.0, 26.0, 20.0);
  s.materials.push_back(emitter);
  s.shapes.push_back(Rect({0, 0, 0}, Vector3d::UnitX(), Vector3d::UnitY(), 1.6, 1.6, 0));
  s.shapes.push_back(Rect({0, 0.9, 0.7}, Vector3d::UnitX(), Vector3d::UnitZ(), 1.6, 0.7, 1));
  s.shapes.push_back(Box({-0.55, 0.88, 0.95}, {0.07, 0.015, 0.07}, 0.0, 2));
  s.point_lights.push_back({{-0.55, 0.84, 0.95}, Vector3d(0.08, 0.07, 0.055)});
}

SynthScene DefaultScene() {
  SynthScene s;
  s.name = "default";
  AddCommon(s);
  const int pedestal = static_cast<int>(s.materials.size());
  s.materials.push_back(
      Mat(TextureKind::kStripes, {0.80, 0.80, 0.78}, {0.30, 0.10, 0.08}, 14.0, 0.2));
  Material glossy = Mat(TextureKind::kNoise, {0.60, 0.08, 0.05}, {0.25, 0.02, 0.03}, 10.0, 0.1);
  glossy.specular = 0.6;
  glossy.shininess = 300;
  const int gloss = static_cast<int>(s.materials.size());
  s.materials.push_back(glossy);
  const int box = static_cast<int>(s.materials.size());
  s.materials.push_back(
      Mat(TextureKind::kChecker, {0.10, 0.35, 0.60}, {0.85, 0.85, 0.80}, 22.0, 0.2));
  const int cyl = static_cast<int>(s.materials.size());
  s.materials.push_back(Mat(TextureKind::kStripes, {0.90, 0.75, 0.10}, {0.05, 0.05, 0.05}, 24.0,
                            0.15, Vector3d(0.2, 0.1, 1.0)));
  const int small = static_cast<int>(s.materials.size());
  s.materials.push_back(
      Mat(TextureKind::kNoise, {0.15, 0.55, 0.20}, {0.85, 0.90, 0.60}, 25.0, 0.0));

  s.shapes.push_back(Box({0.1, 0.15, 0.15}, {0.18, 0.18, 0.15}, 0.2, pedestal));
  s.shapes.push_back(Sphere({0.1, 0.15, 0.47}, 0.17, gloss));
  s.shapes.push_back(Box({-0.32, -0.15, 0.2}, {0.11, 0.11, 0.2}, 0.6, box));
  s.shapes.push_back(Cylinder({0.42, -0.22, 0.0}, 0.07, 0.55, cyl));
  s.shapes.push_back(Sphere({-0.05, -0.42, 0.09}, 0.09, small));
  return s;
}

SynthScene ThinScene() {
  SynthScene s;
  s.name = "thin";
  AddCommon(s);
  const int rods = static_cast<int>(s.materials.size());
  s.materials.push_back(Mat(TextureKind::kStripes, {0.9, 0.9, 0.85}, {0.1, 0.1, 0.3}, 30.0, 0.1));
  const int cavity = static_cast<int>(s.materials.size());
  s.materials.push_back(
      Mat(TextureKind::kChecker, {0.75, 0.55, 0.30}, {0.15, 0.10, 0.08}, 25.0, 0.3));
  Material glossy = Mat(TextureKind::kNoise, {0.05, 0.15, 0.55}, {0.02, 0.05, 0.20}, 12.0, 0.1);
  glossy.specular = 0.6;
  glossy.shininess = 300;
  const int gloss = static_cast<int>(s.materials.size());
  s.materials.push_back(glossy);
  const int plate = static_cast<int>(s.materials.size());
  s.materials.push_back(Mat(TextureKind::kNoise, {0.9, 0.8, 0.2}, {0.3, 0.1, 0.05}, 30.0, 0.0));

  // A row of thin rods (radii 6 to 12 thousandths of the scene size) in front of the wall.
  for (int i = 0; i < 9; ++i) {
    const double x = -0.55 + 0.13 * i;
    s.shapes.push_back(Cylinder({x, 0.35 + 0.03 * (i % 3), 0.0}, 0.006 + 0.00075 * i, 0.65, rods));
  }
  // An open cubicle facing the cameras (-y): a concavity with walls 1 hundredth thick.
  const Vector3d c(-0.3, -0.1, 0.0);
  const double w = 0.17, t = 0.005;
  s.shapes.push_back(Box(c + Vector3d(0, w, w), {w, t, w}, 0, cavity));              // back
  s.shapes.push_back(Box(c + Vector3d(-w, 0, w), {t, w, w}, 0, cavity));             // left
  s.shapes.push_back(Box(c + Vector3d(w, 0, w), {t, w, w}, 0, cavity));              // right
  s.shapes.push_back(Box(c + Vector3d(0, 0, 2 * w), {w + t, w + t, t}, 0, cavity));  // roof
  // A thin plate on a thin stem, and the glossy sphere.
  s.shapes.push_back(Cylinder({0.25, -0.25, 0.0}, 0.01, 0.2, rods));
  s.shapes.push_back(Box({0.25, -0.25, 0.32}, {0.16, 0.004, 0.12}, -0.3, plate));
  s.shapes.push_back(Sphere({0.3, 0.22, 0.15}, 0.15, gloss));
  return s;
}

// The common room opened up: no back wall, panel or lamp; a wide ground and a far wall `far_y`
// units away.
void MakeOpenGround(SynthScene& s, double far_y, int far_material) {
  s.shapes.erase(s.shapes.begin() + 1, s.shapes.end());
  s.point_lights.clear();
  s.shapes.front().half_size = Vector3d(4.0, 6.0, 0);
  s.shapes.push_back(
      Rect({0, far_y, 0.8}, Vector3d::UnitX(), Vector3d::UnitZ(), 4.0, 0.8, far_material));
}

int AddMaterial(SynthScene& s, const Material& m) {
  s.materials.push_back(m);
  return static_cast<int>(s.materials.size()) - 1;
}

Material Glossy(const Material& base, double specular, double shininess) {
  Material m = base;
  m.specular = specular;
  m.shininess = shininess;
  return m;
}

// A gateway of two pillars and a lintel: an opening of width 2 * half_gap, `height` high.
void AddArch(SynthScene& s, const Vector3d& base, double half_gap, double height, double thick,
             double yaw, int mat) {
  const Vector3d side(std::cos(yaw), std::sin(yaw), 0);
  for (const double sign : {-1.0, 1.0}) {
    s.shapes.push_back(Box(base + sign * (half_gap + thick) * side + Vector3d(0, 0, 0.5 * height),
                           {thick, thick, 0.5 * height}, yaw, mat));
  }
  s.shapes.push_back(
      Box(base + Vector3d(0, 0, height + thick), {half_gap + 2 * thick, thick, thick}, yaw, mat));
}

// A ring of `count` cubes in the vertical plane through `centre` facing -y: a hole to see
// through.
void AddRing(SynthScene& s, const Vector3d& centre, double radius, double cube, int count,
             int mat) {
  for (int i = 0; i < count; ++i) {
    const double a = 2 * std::numbers::pi * i / count;
    s.shapes.push_back(Box(centre + radius * Vector3d(std::cos(a), 0, std::sin(a)),
                           Vector3d::Constant(cube), 0.0, mat));
  }
}

// Holes through objects: a gateway, a ring of cubes and a narrow gap between two blocks, with
// a sphere seen through the gateway.
SynthScene ArchesScene() {
  SynthScene s;
  s.name = "arches";
  AddCommon(s);
  const int stone =
      AddMaterial(s, Mat(TextureKind::kNoise, {0.75, 0.70, 0.62}, {0.35, 0.30, 0.25}, 12.0, 0.25));
  const int brick = AddMaterial(s, Mat(TextureKind::kStripes, {0.62, 0.25, 0.15},
                                       {0.85, 0.80, 0.70}, 20.0, 0.2, Vector3d(0, 0.2, 1)));
  const int ring = AddMaterial(
      s, Mat(TextureKind::kChecker, {0.15, 0.30, 0.65}, {0.90, 0.90, 0.85}, 30.0, 0.15));
  const int ball = AddMaterial(
      s,
      Glossy(Mat(TextureKind::kNoise, {0.10, 0.55, 0.20}, {0.05, 0.20, 0.10}, 9.0, 0.1), 0.4, 150));
  AddArch(s, {0.0, 0.1, 0.0}, 0.19, 0.6, 0.06, 0.1, stone);
  s.shapes.push_back(Sphere({0.02, 0.55, 0.16}, 0.16, ball));
  AddRing(s, {0.58, -0.1, 0.32}, 0.17, 0.035, 12, ring);
  s.shapes.push_back(Box({-0.62, -0.05, 0.25}, {0.1, 0.1, 0.25}, 0.3, brick));
  s.shapes.push_back(Box({-0.38, -0.13, 0.2}, {0.1, 0.1, 0.2}, 0.3, brick));
  return s;
}

// Thin structures: a railing of posts and rails, a tall pole and a bare tree's branches.
SynthScene RailingScene() {
  SynthScene s;
  s.name = "railing";
  AddCommon(s);
  const int metal = AddMaterial(
      s, Glossy(Mat(TextureKind::kStripes, {0.85, 0.85, 0.80}, {0.20, 0.20, 0.25}, 40.0, 0.1), 0.3,
                200));
  const int bark = AddMaterial(s, Mat(TextureKind::kStripes, {0.35, 0.22, 0.12}, {0.60, 0.45, 0.30},
                                      35.0, 0.3, Vector3d(1, 0.3, 0.2)));
  const int crate =
      AddMaterial(s, Mat(TextureKind::kChecker, {0.80, 0.60, 0.20}, {0.30, 0.15, 0.05}, 18.0, 0.2));
  for (int i = 0; i < 13; ++i) {
    s.shapes.push_back(Cylinder({-0.6 + 0.1 * i, -0.2, 0.0}, 0.008, 0.42, metal));
  }
  for (const double z : {0.22, 0.42}) {
    s.shapes.push_back(Box({0.0, -0.2, z}, {0.62, 0.007, 0.007}, 0.0, metal));
  }
  s.shapes.push_back(Box({0.1, 0.3, 0.18}, {0.2, 0.15, 0.18}, 0.4, crate));
  s.shapes.push_back(Cylinder({0.55, 0.4, 0.0}, 0.014, 1.25, metal));
  // The tree: a trunk and horizontal branches at several heights and headings.
  s.shapes.push_back(Cylinder({-0.4, 0.45, 0.0}, 0.03, 0.95, bark));
  for (int i = 0; i < 6; ++i) {
    const double yaw = 0.9 * i + 0.3;
    const double len = 0.12 + 0.03 * (i % 3);
    const Vector3d dir(std::cos(yaw), std::sin(yaw), 0);
    s.shapes.push_back(Box(Vector3d(-0.4, 0.45, 0.5 + 0.08 * i) + len * dir,
                           {len, 0.006 + 0.002 * (i % 2), 0.006}, yaw, bark));
  }
  return s;
}

// Concave corners and textureless surfaces: a side wall meeting the back wall, an L of thick
// walls opening towards the cameras, steps, and a plain white block in the corner.
SynthScene CornerScene() {
  SynthScene s;
  s.name = "corner";
  AddCommon(s);
  const int plaster =
      AddMaterial(s, Mat(TextureKind::kNoise, {0.82, 0.80, 0.76}, {0.70, 0.68, 0.64}, 3.0, 0.03));
  const int white =
      AddMaterial(s, Mat(TextureKind::kSolid, {0.9, 0.9, 0.88}, {0.9, 0.9, 0.88}, 1.0, 0.01));
  const int tiles =
      AddMaterial(s, Mat(TextureKind::kChecker, {0.55, 0.20, 0.10}, {0.85, 0.75, 0.55}, 16.0, 0.2));
  s.shapes.push_back(
      Rect({-0.75, 0.35, 0.5}, Vector3d::UnitY(), Vector3d::UnitZ(), 0.55, 0.5, plaster));
  s.shapes.push_back(Box({-0.6, 0.75, 0.15}, {0.12, 0.12, 0.15}, 0.0, white));
  // The L: its inside corner faces the cameras.
  s.shapes.push_back(Box({0.25, 0.35, 0.22}, {0.28, 0.03, 0.22}, 0.0, tiles));
  s.shapes.push_back(Box({-0.0, 0.1, 0.22}, {0.03, 0.22, 0.22}, 0.0, tiles));
  const int vase = AddMaterial(
      s,
      Glossy(Mat(TextureKind::kNoise, {0.1, 0.3, 0.25}, {0.05, 0.12, 0.1}, 8.0, 0.05), 0.6, 300));
  s.shapes.push_back(Sphere({0.4, 0.12, 0.1}, 0.1, vase));
  // Steps.
  for (int i = 0; i < 3; ++i) {
    s.shapes.push_back(Box({0.45, -0.25 + 0.08 * i, 0.03 + 0.06 * i}, {0.18, 0.04, 0.03 + 0.06 * i},
                           0.0, plaster));
  }
  return s;
}

// A facade walked along (CameraPath::kFacade): pilasters, a balcony with a railing, and two
// columns close to the cameras that cross every view.
SynthScene FacadeScene() {
  SynthScene s;
  s.name = "facade";
  AddCommon(s);
  s.path = CameraPath::kFacade;
  s.look_at = Vector3d(0.0, 0.6, 0.5);
  const int stone =
      AddMaterial(s, Mat(TextureKind::kNoise, {0.80, 0.74, 0.60}, {0.45, 0.40, 0.32}, 10.0, 0.2));
  const int frame = AddMaterial(  // glossy paint
      s,
      Glossy(Mat(TextureKind::kStripes, {0.2, 0.25, 0.3}, {0.85, 0.85, 0.8}, 25.0, 0.1), 0.4, 200));
  const int column = AddMaterial(s, Mat(TextureKind::kStripes, {0.75, 0.72, 0.68},
                                        {0.40, 0.38, 0.35}, 30.0, 0.15, Vector3d(1, 1, 0)));
  for (int i = 0; i < 5; ++i) {
    s.shapes.push_back(Box({-1.0 + 0.5 * i, 0.85, 0.65}, {0.05, 0.05, 0.65}, 0.0, stone));
  }
  for (int i = 0; i < 4; ++i) {  // window frames standing out of the wall
    const Vector3d c(-0.75 + 0.5 * i, 0.88, 0.9);
    s.shapes.push_back(Box(c + Vector3d(0, 0, 0.15), {0.13, 0.02, 0.015}, 0.0, frame));
    s.shapes.push_back(Box(c - Vector3d(0, 0, 0.15), {0.13, 0.02, 0.015}, 0.0, frame));
  }
  s.shapes.push_back(Box({0.25, 0.72, 0.55}, {0.3, 0.16, 0.02}, 0.0, stone));  // balcony
  for (int i = 0; i < 9; ++i) {
    s.shapes.push_back(Cylinder({0.0 + 0.0625 * i, 0.57, 0.57}, 0.006, 0.2, frame));
  }
  s.shapes.push_back(Cylinder({-0.35, -0.45, 0.0}, 0.05, 1.3, column));
  s.shapes.push_back(Cylinder({0.45, -0.45, 0.0}, 0.05, 1.3, column));
  s.shapes.push_back(Box({0.05, -0.2, 0.1}, {0.25, 0.08, 0.1}, 0.0, stone));  // a bench
  return s;
}

// Glossy and textureless surfaces, and textures of very low and very high frequency.
SynthScene GlossyScene() {
  SynthScene s;
  s.name = "glossy";
  AddCommon(s);
  const int red = AddMaterial(
      s, Glossy(Mat(TextureKind::kSolid, {0.55, 0.06, 0.05}, {0.55, 0.06, 0.05}, 1.0, 0.02), 0.8,
                500));
  const int chrome = AddMaterial(
      s, Glossy(Mat(TextureKind::kNoise, {0.25, 0.25, 0.28}, {0.15, 0.15, 0.18}, 6.0, 0.05), 0.9,
                800));
  const int lacquer = AddMaterial(
      s,
      Glossy(Mat(TextureKind::kChecker, {0.05, 0.2, 0.45}, {0.8, 0.8, 0.75}, 12.0, 0.1), 0.5, 250));
  const int plain =
      AddMaterial(s, Mat(TextureKind::kSolid, {0.85, 0.85, 0.83}, {0.85, 0.85, 0.83}, 1.0, 0.01));
  const int fine = AddMaterial(s, Mat(TextureKind::kStripes, {0.9, 0.85, 0.3}, {0.1, 0.1, 0.1},
                                      70.0, 0.05, Vector3d(1, 0, 0.3)));
  const int coarse =
      AddMaterial(s, Mat(TextureKind::kNoise, {0.6, 0.4, 0.7}, {0.2, 0.5, 0.3}, 1.5, 0.05));
  s.shapes.push_back(Sphere({-0.35, 0.0, 0.18}, 0.18, red));
  s.shapes.push_back(Sphere({0.1, 0.35, 0.22}, 0.22, chrome));
  s.shapes.push_back(Box({0.45, -0.1, 0.15}, {0.12, 0.12, 0.15}, 0.5, lacquer));
  s.shapes.push_back(Cylinder({-0.1, -0.35, 0.0}, 0.08, 0.35, plain));
  s.shapes.push_back(Box({-0.55, 0.45, 0.25}, {0.12, 0.1, 0.25}, -0.3, fine));
  s.shapes.push_back(Box({0.55, 0.5, 0.3}, {0.15, 0.12, 0.3}, 0.2, coarse));
  return s;
}

// Open ground and background: no back wall, a far wall, sky above; objects on a wide ground.
SynthScene OpenScene() {
  SynthScene s;
  s.name = "open";
  AddCommon(s);
  const int distant =
      AddMaterial(s, Mat(TextureKind::kNoise, {0.55, 0.60, 0.55}, {0.25, 0.30, 0.25}, 1.5, 0.2));
  MakeOpenGround(s, 5.5, distant);
  const int wood = AddMaterial(s, Mat(TextureKind::kStripes, {0.65, 0.45, 0.25}, {0.40, 0.25, 0.12},
                                      22.0, 0.2, Vector3d(0, 1, 0.1)));
  const int slate = AddMaterial(  // polished
      s, Glossy(Mat(TextureKind::kChecker, {0.25, 0.28, 0.32}, {0.6, 0.62, 0.66}, 14.0, 0.2), 0.5,
                300));
  s.shapes.push_back(Box({0.0, 0.2, 0.2}, {0.2, 0.15, 0.2}, 0.4, wood));
  s.shapes.push_back(Sphere({-0.45, -0.1, 0.14}, 0.14, slate));
  s.shapes.push_back(Cylinder({0.5, 0.3, 0.0}, 0.06, 0.5, wood));
  s.shapes.push_back(Box({-0.2, 0.8, 0.3}, {0.1, 0.1, 0.3}, 0.1, slate));
  return s;
}

// A seeded layout: the common room (or an open ground) with 5 to 9 objects of random kind,
// size, texture and gloss, among them gateways, rings and bundles of rods.
SynthScene RandomScene(std::uint64_t seed) {
  SynthScene s;
  s.name = "random";
  AddCommon(s);
  SplitMix64 rng(seed * 0x9E3779B97F4A7C15ull + 0x5851F42D4C957F2Dull);
  if (rng.Uniform() < 0.3) {  // open ground with a far wall
    MakeOpenGround(s, 5.0, 1);
  }
  const auto colour = [&] {
    return Vector3d(rng.Uniform(0.05, 0.9), rng.Uniform(0.05, 0.9), rng.Uniform(0.05, 0.9));
  };
  const int objects = 5 + static_cast<int>(rng.Uniform() * 5);
  std::vector<Eigen::Vector3d> placed;  // x, y, footprint radius
  for (int i = 0; i < objects; ++i) {
    Material m = Mat(static_cast<TextureKind>(static_cast<int>(rng.Uniform() * 4)), colour(),
                     colour(), std::exp(rng.Uniform(std::log(2.0), std::log(50.0))),
                     rng.Uniform(0.0, 0.3), Vector3d(rng.Uniform(-1, 1), rng.Uniform(-1, 1), 1));
    // At least one glossy object: a highlight that moves with the viewpoint.
    if (rng.Uniform() < 0.3 || i == 0) m = Glossy(m, rng.Uniform(0.3, 0.8), rng.Uniform(100, 600));
    const int mat = AddMaterial(s, m);
    const int kind = static_cast<int>(rng.Uniform() * 7);
    const double r = kind >= 5 ? 0.22 : rng.Uniform(0.06, 0.2);
    Vector3d at(0, 0, 0);
    for (int attempt = 0; attempt < 50; ++attempt) {
      at = Vector3d(rng.Uniform(-0.7, 0.7), rng.Uniform(-0.45, 0.65), 0);
      bool clear = true;
      for (const Vector3d& p : placed) {
        clear = clear && (p.head<2>() - at.head<2>()).norm() > p.z() + r;
      }
      if (clear) break;
    }
    placed.emplace_back(at.x(), at.y(), r);
    const double yaw = rng.Uniform(0, std::numbers::pi);
    switch (kind) {
      case 0:
        s.shapes.push_back(Sphere(at + Vector3d(0, 0, r), r, mat));
        break;
      case 1:
      case 2: {
        const Vector3d half(r, rng.Uniform(0.3, 1.0) * r, rng.Uniform(0.5, 2.0) * r);
        s.shapes.push_back(Box(at + Vector3d(0, 0, half.z()), half, yaw, mat));
        break;
      }
      case 3:
        s.shapes.push_back(Cylinder(at, rng.Uniform(0.3, 1.0) * r, rng.Uniform(2, 5) * r, mat));
        break;
      case 4:  // a bundle of rods
        for (int k = 0; k < 4; ++k) {
          s.shapes.push_back(Cylinder(at + Vector3d(rng.Uniform(-r, r), rng.Uniform(-r, r), 0),
                                      rng.Uniform(0.005, 0.015), rng.Uniform(0.3, 0.8), mat));
        }
        break;
      case 5:
        AddArch(s, at, rng.Uniform(0.1, 0.16), rng.Uniform(0.3, 0.55), 0.04, yaw, mat);
        break;
      default:
        AddRing(s, at + Vector3d(0, 0, 0.2), 0.14, 0.03, 10, mat);
        break;
    }
  }
  return s;
}

}  // namespace

std::vector<std::string> SceneNames() {
  return {"default", "thin", "arches", "railing", "corner", "facade", "glossy", "open", "random"};
}

SynthScene MakeScene(const std::string& name, std::uint64_t seed) {
  if (name == "default") return DefaultScene();
  if (name == "thin") return ThinScene();
  if (name == "arches") return ArchesScene();
  if (name == "railing") return RailingScene();
  if (name == "corner") return CornerScene();
  if (name == "facade") return FacadeScene();
  if (name == "glossy") return GlossyScene();
  if (name == "open") return OpenScene();
  if (name == "random") return RandomScene(seed);
  std::string known;
  for (const std::string& n : SceneNames()) known += (known.empty() ? "" : ", ") + n;
  throw UsageError("unknown synthetic scene '" + name + "' (known: " + known + ")");
}

}  // namespace hdribr::synth
