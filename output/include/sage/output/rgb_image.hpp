#pragma once
// An 8-bit RGB picture held row by row from the TOP row down (as pictures
// are read). Made by render/, written by png_writer.hpp.

#include <cstddef>
#include <cstdint>
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

}  // namespace sage::output
