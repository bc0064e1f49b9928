#pragma once
// Camera: turns a pixel into a ray. Pixel (0, 0) is the top-left corner;
// rays go through pixel centres. Perspective cameras open a vertical field
// of view from the eye; orthographic ones look along the view direction
// through a window `ortho_height` tall centred on the target.

#include <array>
#include <optional>
#include <string>

namespace sage::render {

using Vec3 = std::array<double, 3>;

struct Ray {
  Vec3 origin;
  Vec3 direction;  // unit length
};

struct Camera {
  Vec3 eye{3, 2.4, 1.8};
  Vec3 target{0, 0, 0};
  Vec3 up{0, 0, 1};
  double fov_degrees = 35;
  bool orthographic = false;
  double ortho_height = 2;

  /// The ray through the centre of pixel (px, py) of a width x height image.
  Ray ray(double px, double py, int width, int height) const;
};

/// A camera that shows the box [lo, hi] whole, from the direction
/// (1, -0.8, 0.6) (z up): the default of `sage render`.
Camera camera_for_box(const Vec3& lo, const Vec3& hi, double fov_degrees = 35);

/// Parses "ex,ey,ez,tx,ty,tz[,fov]" (eye, target, field of view in
/// degrees) or "ortho,ex,ey,ez,tx,ty,tz,height". Throws
/// std::invalid_argument saying what is wrong.
Camera parse_camera(const std::string& text);

/// Parses "a,b,c" into three finite numbers. Throws std::invalid_argument.
Vec3 parse_vec3(const std::string& text, const std::string& what);

inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 normalized(const Vec3& v);
inline Vec3 operator-(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 operator+(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 operator*(double s, const Vec3& a) { return {s * a[0], s * a[1], s * a[2]}; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

}  // namespace sage::render
