#pragma once
// How samples were made, in words, for every writer's metadata (VTK field
// data, GeoTIFF metadata items), so that the files say the same.

#include <sage/sampling/field_samples.hpp>

#include <string>

namespace sage::output {

inline std::string evaluation_text(const FieldSamples& s) {
  if (s.far_field_tolerance > 0)
    return "far-field approximation: patches within far_field_tolerance of the exact field";
  if (s.far_faces)
    return "far mesh faces in single precision: deviation from exact evaluation measured as far_faces_deviation";
  return "exact";
}

}  // namespace sage::output
