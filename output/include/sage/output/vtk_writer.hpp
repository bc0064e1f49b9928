#pragma once
// Writing sampled fields as VTK XML files that ParaView opens, with VTK's
// own writers (binary, appended, LZ4-compressed).
//
//  .vtu  vtkUnstructuredGrid: the grid's points with quad (2D) or hexahedron
//        (3D) cells, for any pipeline that wants cells.
//  .vti  vtkImageData: the same samples as a regular image (smaller).
//
// Point arrays: omega, grad_omega (3 components; z = 0 in 2D), grad_norm,
// and d<k>_omega for each higher order k in the samples, with one named
// component per partial ("xx", "xy", ...).

#include <sage/expression/triangle_surface.hpp>
#include <sage/sampling/field_samples.hpp>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace sage::output {

class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Writes the samples to `path`; the extension (.vtu or .vti) picks the
/// format. Throws OutputError naming the path when it cannot be written.
void write_field(const std::string& path, const FieldSamples& samples);

/// True if `path` ends with one of the extensions write_field supports.
bool is_supported_field_path(const std::string& path);

/// Writes the triangles as a .vtp (vtkPolyData) with integer cell arrays,
/// one value per triangle: a CAD model's faces by number, to pick them in
/// ParaView. Throws OutputError naming the path.
void write_surface(const std::string& path, const TriangleSurface& surface,
                   const std::vector<std::pair<std::string, std::vector<int>>>& cell_arrays);

}  // namespace sage::output
