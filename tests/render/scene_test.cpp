// Claims: a rendered picture of a known scene covers the expected pixels
// (the silhouette of a sphere, orthographic and perspective, within 0.5%
// of the closed-form area) with both hit methods; normals come out unit
// and facing the camera (shading brightest where the normal faces the
// light); tape pruning along rays changes no hit; 2D colour maps draw the
// zero contour dark and colour inside and outside apart; PNG files
// round-trip through VTK's reader.

#include <sage/expression/primitives.hpp>
#include <sage/output/png_writer.hpp>
#include <sage/render/field_map.hpp>
#include <sage/render/solid.hpp>

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>

#include <gtest/gtest.h>
#include <test_files.hpp>

#include <cmath>
#include <filesystem>
#include <iostream>

namespace sage::render {
namespace {

long long covered(const SolidPicture& pic) {
  long long n = 0;
  for (double d : pic.depth) n += std::isfinite(d);
  return n;
}

TEST(Scene, OrthographicSphereCoverageMatchesTheDiskArea) {
  const double r = 0.55;
  SolidOptions o;
  o.width = o.height = 160;
  o.camera.orthographic = true;
  o.camera.eye = {0, 0, 5};
  o.camera.target = {0, 0, 0};
  o.camera.up = {0, 1, 0};
  o.camera.ortho_height = 1.6;
  const double pixel = o.camera.ortho_height / o.height;
  const double expected = M_PI * r * r / (pixel * pixel);
  for (HitMethod m : {HitMethod::IntervalBisection, HitMethod::SphereTracing}) {
    o.method = m;
    const SolidPicture pic = render_solid(ball({0, 0, 0}, r, 3), {-1, -1, -1}, {1, 1, 1}, o);
    const double error = std::abs(covered(pic) - expected) / expected;
    std::cout << "[ orthographic sphere ] " << covered(pic) << " pixels, closed form " << expected
              << ", relative error " << error << "\n";
    EXPECT_LT(error, 0.005);
  }
}

TEST(Scene, PerspectiveSphereCoverageMatchesTheConeOfView) {
  // A sphere of radius r at distance D fills the cone of half-angle
  // asin(r / D): a disk of radius tan(asin(r / D)) / tan(fov / 2) half-heights.
  const double r = 0.6, D = 4, fov = 30;
  SolidOptions o;
  o.width = 180, o.height = 150;
  o.camera.eye = {0, -D, 0};
  o.camera.target = {0, 0, 0};
  o.camera.fov_degrees = fov;
  const double radius_px = std::tan(std::asin(r / D)) / std::tan(fov * M_PI / 360) * (o.height / 2.0);
  const double expected = M_PI * radius_px * radius_px;
  const SolidPicture pic = render_solid(ball({0, 0, 0}, r, 3), {-1, -1, -1}, {1, 1, 1}, o);
  const double error = std::abs(covered(pic) - expected) / expected;
  std::cout << "[ perspective sphere ] " << covered(pic) << " pixels, closed form " << expected << ", relative error "
            << error << "\n";
  EXPECT_LT(error, 0.005);
  // The hit distances are those of the sphere: D - r straight ahead.
  const std::size_t centre = static_cast<std::size_t>(o.height / 2) * o.width + o.width / 2;
  EXPECT_NEAR(pic.depth[centre], D - r, 1e-3);
}

TEST(Scene, ShadingIsBrightestWhereTheNormalFacesTheLight) {
  SolidOptions o;
  o.width = o.height = 64;
  o.camera.orthographic = true;
  o.camera.eye = {0, 0, 5};
  o.camera.up = {0, 1, 0};
  o.light_direction = {0, 0, 1};  // from the camera
  const SolidPicture pic = render_solid(ball({0, 0, 0}, 0.8, 3), {-1, -1, -1}, {1, 1, 1}, o);
  const int centre = pic.image.pixel(32, 32)[1], edge = pic.image.pixel(32, 8)[1];  // n.l = 0.4 there
  EXPECT_GT(centre, edge + 50);
  // Shadows: a ball over a floor darkens the floor below it.
  const Expr scene = max(ball({0, 0, 0.5}, 0.4, 3), halfspace({0, 0, -0.5}, {0, 0, 1}, 3));
  o.shadows = true;
  o.camera.eye = {0, -0.01, 5};
  o.light_direction = {1, 0, 1};  // the shadow falls around (-1, 0) on the floor z = -0.5
  const SolidPicture oblique = render_solid(scene, {-1, -1, -1}, {1, 1, 1}, o);
  EXPECT_LT(oblique.image.pixel(8, 32)[0] + 40, oblique.image.pixel(8, 5)[0]) << "floor in shadow vs lit floor";
}

TEST(Scene, PrunedTapesGiveTheSameHitsBitForBit) {
  // A union of 24 balls: a tape worth specializing to ray segments.
  Expr scene = ball({-1.1, -1.1, 0}, 0.3, 3);
  for (int i = 1; i < 24; ++i)
    scene = max(scene, ball({-1.1 + 0.45 * (i % 6), -1.1 + 0.7 * (i / 6), 0.2 * std::sin(i)}, 0.3, 3));
  SolidOptions o;
  o.width = 48, o.height = 36;
  o.camera = camera_for_box({-1.5, -1.5, -0.6}, {1.5, 1.5, 0.6});
  const SolidPicture pruned = render_solid(scene, {-1.5, -1.5, -0.6}, {1.5, 1.5, 0.6}, o);
  o.prune_tapes = false;
  const SolidPicture whole = render_solid(scene, {-1.5, -1.5, -0.6}, {1.5, 1.5, 0.6}, o);
  EXPECT_GT(pruned.stats.hits, 200);
  EXPECT_EQ(pruned.stats.hits, whole.stats.hits);
  for (std::size_t i = 0; i < pruned.depth.size(); ++i) ASSERT_EQ(pruned.depth[i], whole.depth[i]) << "pixel " << i;
}

TEST(Scene, MapDrawsTheZeroContourDarkAndSidesApart) {
  MapOptions o;
  o.width = o.height = 64;
  const output::RgbImage map = render_map(ball({0, 0, 0}, 0.5, 2), {-1, -1, 0}, {1, 1, 0}, o);
  const auto* inside = map.pixel(32, 32);
  const auto* outside = map.pixel(2, 2);
  EXPECT_GT(inside[0], inside[2]);    // red inside
  EXPECT_GT(outside[2], outside[0]);  // blue outside
  // The contour crosses row 32 at x = +-0.5, i.e. pixels 16 and 48.
  const auto* contour = map.pixel(47, 32);
  const auto* contour2 = map.pixel(48, 32);
  EXPECT_LT(std::min(contour[0] + contour[1] + contour[2], contour2[0] + contour2[1] + contour2[2]), 120);
}

TEST(Scene, PngFilesRoundTripThroughVtk) {
  output::RgbImage image(7, 5);
  image.pixel(1, 0)[0] = 255;  // top row, red
  image.pixel(6, 4)[2] = 200;  // bottom-right, blue
  const auto path = sage::test::scratch_dir() / "roundtrip.png";
  output::write_png(path.string(), image);
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(path.string().c_str());
  reader->Update();
  vtkImageData* data = reader->GetOutput();
  int dims[3];
  data->GetDimensions(dims);
  EXPECT_EQ(dims[0], 7);
  EXPECT_EQ(dims[1], 5);
  // VTK images start at the bottom row.
  EXPECT_EQ(static_cast<int>(data->GetScalarComponentAsDouble(1, 4, 0, 0)), 255);
  EXPECT_EQ(static_cast<int>(data->GetScalarComponentAsDouble(6, 0, 0, 2)), 200);
  std::filesystem::remove(path);
  EXPECT_THROW(output::write_png("/nonexistent-dir/x.png", image), std::runtime_error);
}

}  // namespace
}  // namespace sage::render
