#pragma once
// PNG pictures, written with VTK's PNG writer, which wants rows bottom-up:
// the writer flips the RgbImage's top-down rows.

#include <sage/output/rgb_image.hpp>

#include <string>

namespace sage::output {

/// Writes `image` to `path` as PNG. Throws OutputError (vtk_writer.hpp)
/// naming the path when it cannot be written.
void write_png(const std::string& path, const RgbImage& image);

}  // namespace sage::output
