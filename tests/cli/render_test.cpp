// `sage render` end to end: the PNG it writes has the requested size and
// shows the model where it is. A 3D ball seen by an orthographic camera
// covers the closed-form disk area (within 0.5%); a 2D disk's bold zero
// contour lies on the circle, so the area between the contour's centre
// lines matches the closed form (within 0.5%). Every gallery model loads
// and renders. Bad input gives a clear message and exit code 1 (bad input)
// or 2 (bad command line). --shadows darken the ground where a ball hides
// the light, and --materials colour each named primitive its own colour.

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>

#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace sage_cli_test;

struct Picture {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;  // top row first, like the renderer
  const unsigned char* pixel(int x, int y) const { return &rgb[3 * (static_cast<std::size_t>(y) * width + x)]; }
};

Picture read_png(const std::string& path) {
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkImageData* data = reader->GetOutput();
  int dims[3];
  data->GetDimensions(dims);
  Picture p;
  p.width = dims[0], p.height = dims[1];
  if (data->GetNumberOfScalarComponents() < 3) return {};
  p.rgb.resize(3 * static_cast<std::size_t>(p.width) * p.height);
  for (int y = 0; y < p.height; ++y)
    for (int x = 0; x < p.width; ++x)
      for (int c = 0; c < 3; ++c)  // VTK images start at the bottom row
        p.rgb[3 * (static_cast<std::size_t>(y) * p.width + x) + c] =
            static_cast<unsigned char>(data->GetScalarComponentAsDouble(x, p.height - 1 - y, 0, c));
  return p;
}

/// Pixels of the solid: its colour is warm (red > blue), the background's
/// cool (blue > red) everywhere.
long long solid_pixels(const Picture& p) {
  long long n = 0;
  for (int y = 0; y < p.height; ++y)
    for (int x = 0; x < p.width; ++x) n += p.pixel(x, y)[0] > p.pixel(x, y)[2];
  return n;
}

/// How much of a map pixel the bold zero contour covers. The map colours a
/// pixel (1 - z) ((1 - w) white + w end), end red inside and blue outside
/// (render/src/field_map.cpp): solve for a = (1 - z)(1 - w), b = (1 - z) w
/// by least squares with either end and keep the better fit; z = 1 - a - b.
/// (Brightness alone is biased: the inside reddens faster than the outside
/// blues, which moved the measured contour inwards by a quarter pixel.)
double contour_darkness(const unsigned char* c) {
  const double white[3] = {0.97, 0.96, 0.94}, red[3] = {0.75, 0.18, 0.15}, blue[3] = {0.2, 0.35, 0.72};
  double best = 1e300, z = 0;
  for (const double* end : {red, blue}) {
    double ww = 0, we = 0, ee = 0, wc = 0, ec = 0;
    for (int k = 0; k < 3; ++k) {
      const double v = c[k] / 255.0;
      ww += white[k] * white[k], we += white[k] * end[k], ee += end[k] * end[k];
      wc += white[k] * v, ec += end[k] * v;
    }
    const double det = ww * ee - we * we, a = (wc * ee - ec * we) / det, b = (ec * ww - wc * we) / det;
    double residual = 0;
    for (int k = 0; k < 3; ++k) residual += std::pow(c[k] / 255.0 - a * white[k] - b * end[k], 2);
    if (b >= -0.02 && residual < best) best = residual, z = 1 - a - b;
  }
  return std::clamp(z, 0.0, 1.0);
}

void expect_failure(const std::string& args, int code, std::initializer_list<std::string> pieces) {
  const Result r = run(args);
  EXPECT_EQ(r.exit_code, code) << args << "\n" << r.output;
  for (const auto& piece : pieces)
    EXPECT_NE(r.output.find(piece), std::string::npos) << "'" << piece << "' not in: " << r.output;
}

TEST(CliRender, BallCoversTheDiskArea) {
  const double r = 0.55;
  const std::string m = write_file("render_ball.json", R"({"dimension": 3,
      "bounds": {"min": [-1, -1, -1], "max": [1, 1, 1]},
      "field": {"primitive": "ball", "center": [0, 0, 0], "radius": 0.55}})");
  const std::string out = scratch("render_ball.png").string();
  for (const std::string hit : {"interval", "sphere"}) {
    fs::remove(out);
    // Looking along +y, 1.6 units tall over 160 pixels.
    const Result res =
        run("render " + m + " -o " + out + " --size 200x160 --camera ortho,0,-5,0,0,0,0,1.6 --hit " + hit);
    ASSERT_EQ(res.exit_code, 0) << res.output;
    EXPECT_NE(res.output.find("200x160"), std::string::npos) << res.output;
    const Picture p = read_png(out);
    ASSERT_EQ(p.width, 200);
    ASSERT_EQ(p.height, 160);
    const double pixel = 1.6 / 160, expected = M_PI * r * r / (pixel * pixel);
    const double error = std::abs(solid_pixels(p) - expected) / expected;
    std::cout << "[ render ball, " << hit << " ] " << solid_pixels(p) << " pixels, closed form " << expected
              << ", relative error " << error << "\n";
    EXPECT_LT(error, 0.005);
  }
}

TEST(CliRender, DiskMapHasItsZeroContourOnTheCircle) {
  const double r = 0.5;
  const std::string m = write_file("render_disk.json", R"({"dimension": 2,
      "bounds": {"min": [-1, -1], "max": [1, 1]},
      "field": {"primitive": "disk", "center": [0, 0], "radius": 0.5}})");
  const std::string out = scratch("render_disk.png").string();
  fs::remove(out);
  const Result res = run("render " + m + " -o " + out + " --size 240x180 -q");
  ASSERT_EQ(res.exit_code, 0) << res.output;
  const Picture p = read_png(out);
  ASSERT_EQ(p.width, 240);
  ASSERT_EQ(p.height, 180);
  const double pixel = 2.0 / 180;  // square pixels: the box fits the height
  const auto* centre = p.pixel(120, 90);
  const auto* corner = p.pixel(3, 3);
  EXPECT_GT(centre[0], centre[2] + 30) << "red inside";
  EXPECT_GT(corner[2], corner[0] + 30) << "blue outside";
  // Each row meets the bold contour twice; the darkness-weighted centre of
  // each crossing locates the circle to a fraction of a pixel. Rows with
  // |y| < 0.8 r, where the contour crosses the row steeply.
  double measured = 0, exact = 0;
  for (int row = 0; row < p.height; ++row) {
    const double y = (90 - row - 0.5) * pixel;
    if (std::abs(y) >= 0.8 * r) continue;
    const double half_chord = std::sqrt(r * r - y * y) / pixel;  // pixels from the centre column line (x = 120)
    double ends[2];
    for (int side = 0; side < 2; ++side) {
      const double guess = 120 + (side ? half_chord : -half_chord);
      double weight = 0, moment = 0;
      for (int x = static_cast<int>(guess) - 5; x <= static_cast<int>(guess) + 5; ++x) {
        const double darkness = contour_darkness(p.pixel(x, row));
        weight += darkness;
        moment += darkness * (x + 0.5);
      }
      ASSERT_GT(weight, 1.0) << "no contour near pixel " << guess << " of row " << row;
      ends[side] = moment / weight;
    }
    measured += (ends[1] - ends[0]) * pixel * pixel;
    exact += 2 * half_chord * pixel * pixel;
  }
  const double error = std::abs(measured - exact) / exact;
  std::cout << "[ render disk map ] area between the contour lines " << measured << ", closed form " << exact
            << ", relative error " << error << "\n";
  EXPECT_LT(error, 0.005);
}

TEST(CliRender, EveryGalleryModelRenders) {
  // Small pictures: each model loads, renders, and its solid fills a
  // plausible part of the frame (the default camera shows the whole box).
  const fs::path gallery = fs::path(SAGE_SOURCE_DIR) / "examples" / "gallery";
  int models = 0;
  for (const auto& entry : fs::directory_iterator(gallery)) {
    if (entry.path().extension() != ".json") continue;
    ++models;
    const std::string out = scratch("gallery_" + entry.path().stem().string() + ".png").string();
    fs::remove(out);
    const Result res = run("render " + entry.path().string() + " -o " + out + " --size 64x48 -q");
    ASSERT_EQ(res.exit_code, 0) << entry.path() << "\n" << res.output;
    const Picture p = read_png(out);
    ASSERT_EQ(p.width, 64);
    ASSERT_EQ(p.height, 48);
    const double fraction = static_cast<double>(solid_pixels(p)) / (64 * 48);
    std::cout << "[ gallery ] " << entry.path().filename().string() << ": " << fraction << " of the frame\n";
    EXPECT_GT(fraction, 0.04) << entry.path();
    EXPECT_LT(fraction, 0.9) << entry.path();
  }
  EXPECT_GE(models, 12);
}

/// A ball above a slab (the ground), both named, seen from straight above
/// by an orthographic camera: a pixel (px, py) of the 80x80 picture shows
/// the point x = ((px + 0.5) / 40 - 1) 1.2, y = (1 - (py + 0.5) / 40) 1.2.
std::string ball_over_ground() {
  return write_file("ball_over_ground.json", R"({"dimension": 3,
      "bounds": {"min": [-1, -1, -1], "max": [1, 1, 1]},
      "field": {"op": "union", "args": [
        {"name": "ground", "primitive": "box", "min": [-0.9, -0.9, -0.6], "max": [0.9, 0.9, -0.4]},
        {"name": "ball", "primitive": "ball", "center": [-0.4, 0, 0.3], "radius": 0.25}]}})");
}
const std::string kFromAbove = " --size 80x80 --camera ortho,0,0,5,0,0,0,2.4";

double brightness(const unsigned char* c) { return c[0] + c[1] + c[2]; }

// --shadows: with the light from (-1, 0, 1), the ball at x = -0.4 casts its
// shadow on the ground's top (z = -0.4) around x = -0.4 + 0.7 = 0.3, y = 0
// (an ellipse of half-axes 0.35 and 0.25). That point is lit without
// shadows (the ground faces the light at 45 degrees) and takes the ambient
// light alone with them; the ground beside it (y = 0.6) keeps its light.
// The summary counts the shadow rays.
TEST(CliRender, ShadowsDarkenTheGroundUnderTheBall) {
  const std::string m = ball_over_ground();
  const std::string plain = scratch("shadows_off.png").string(), shadowed = scratch("shadows_on.png").string();
  const Result a = run("render " + m + " -o " + plain + kFromAbove + " --light -1,0,1");
  const Result b = run("render " + m + " -o " + shadowed + kFromAbove + " --light -1,0,1 --shadows");
  ASSERT_EQ(a.exit_code, 0) << a.output;
  ASSERT_EQ(b.exit_code, 0) << b.output;
  EXPECT_NE(a.output.find(" 6400 rays"), std::string::npos) << a.output;  // one per pixel
  EXPECT_GT(number_after(b.output, "80x80, "), 6400) << b.output;         // and one per lit hit
  const Picture p = read_png(plain), q = read_png(shadowed);
  ASSERT_EQ(p.width, 80);
  ASSERT_EQ(q.width, 80);
  // x = 0.285, y = 0.015: in the shadow; the ambient light is 0.18 / (0.18 + 0.75 cos 45) of the lit colour.
  const unsigned char *lit = p.pixel(49, 39), *dark = q.pixel(49, 39);
  EXPECT_GT(brightness(lit), 300) << "the ground is lit";
  EXPECT_NEAR(brightness(dark) / brightness(lit), 0.18 / (0.18 + 0.75 * M_SQRT1_2), 0.03);
  // x = 0.285, y = 0.615: beside the shadow, the same with and without.
  EXPECT_NEAR(brightness(q.pixel(49, 19)), brightness(p.pixel(49, 19)), 3);
  // The ball's top (x = -0.39, y = 0.015) sees the light either way.
  EXPECT_NEAR(brightness(q.pixel(27, 39)), brightness(p.pixel(27, 39)), 3);
}

// --materials colours each named primitive of the model from a palette:
// the ground (the first) orange, the ball (the second) blue. Without it
// both have the one solid colour, warm.
TEST(CliRender, MaterialsColourEachNamedPrimitive) {
  const std::string m = ball_over_ground();
  const std::string plain = scratch("materials_off.png").string(), coloured = scratch("materials_on.png").string();
  ASSERT_EQ(run("render " + m + " -o " + plain + kFromAbove + " -q").exit_code, 0);
  const Result r = run("render " + m + " -o " + coloured + kFromAbove + " --materials -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Picture p = read_png(plain), q = read_png(coloured);
  ASSERT_EQ(p.width, 80);
  ASSERT_EQ(q.width, 80);
  auto red = [](const unsigned char* c) { return static_cast<int>(c[0]); };
  auto blue = [](const unsigned char* c) { return static_cast<int>(c[2]); };
  const unsigned char *ball = q.pixel(27, 39), *ground = q.pixel(60, 60);
  EXPECT_GT(blue(ball), red(ball) + 40) << "the ball is blue";
  EXPECT_GT(red(ground), blue(ground) + 40) << "the ground is orange";
  for (const auto& [x, y] : {std::pair{27, 39}, std::pair{60, 60}})
    EXPECT_GT(red(p.pixel(x, y)), blue(p.pixel(x, y))) << "one warm colour without --materials";
}

TEST(CliRender, BadInput) {
  const std::string m = write_file("render_ball2.json", R"({"dimension": 3,
      "bounds": {"min": [-1, -1, -1], "max": [1, 1, 1]},
      "field": {"primitive": "ball", "center": [0, 0, 0], "radius": 0.5}})");
  const std::string out = " -o " + scratch("bad.png").string();
  expect_failure("render " + m + out + " --size 80by60", 2, {"--size", "80by60"});
  expect_failure("render " + m + out + " --size 0x60", 2, {"--size"});
  expect_failure("render " + m + out + " --size 20000x60", 2, {"--size"});
  expect_failure("render " + m + out + " --camera 1,2", 2, {"--camera", "expected"});
  expect_failure("render " + m + out + " --camera 1,2,x,0,0,0", 2, {"--camera", "\"x\""});
  expect_failure("render " + m + out + " --camera ortho,0,0,5,0,0,0,-1", 2, {"--camera", "height"});
  expect_failure("render " + m + out + " --light 0,0", 2, {"--light"});
  expect_failure("render " + m + out + " --hit march", 2, {"--hit", "march"});
  expect_failure("render " + m + " -o " + scratch("bad.jpg").string(), 2, {"bad.jpg", ".png"});
  expect_failure("render " + m + " -o /nonexistent-folder/x.png", 1, {"/nonexistent-folder/x.png"});
  expect_failure("render /nonexistent/m.json" + out, 1, {"/nonexistent/m.json"});
  const std::string broken = write_file("render_broken.json", "{\"dimension\": 3,\n \"field\": {\"ball\": 1}}");
  expect_failure("render " + broken + out, 1, {"render_broken.json", "/field"});
  expect_failure("render " + m, 2, {"output"});
}

}  // namespace
