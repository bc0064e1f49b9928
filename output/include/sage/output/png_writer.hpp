#pragma once
// PNG pictures, written with VTK's PNG writer. An RgbImage holds 8-bit RGB
// pixels row by row from the TOP row down (as pictures are read); the
// writer flips them into VTK's bottom-up image order.

#include <cstdint>
#include <string>
#include <vector>

namespace sage::output {

struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  // 3 * width * height, top row first

  RgbImage() = default;
  RgbImage(int w, int h) : width(w), height(h), rgb(3 * static_cast<std::size_t>(w) * h, 0) {}
  std::uint8_t* pixel(int x, int y) { return &rgb[3 * (static_cast<std::size_t>(y) * width + x)]; }
  const std::uint8_t* pixel(int x, int y) const { return &rgb[3 * (static_cast<std::size_t>(y) * width + x)]; }
};

/// Writes `image` to `path` as PNG. Throws OutputError (vtk_writer.hpp)
/// naming the path when it cannot be written.
void write_png(const std::string& path, const RgbImage& image);

}  // namespace sage::output
