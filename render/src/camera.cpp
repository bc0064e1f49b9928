#include <sage/render/camera.hpp>

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace sage::render {

Vec3 normalized(const Vec3& v) {
  const double n = std::sqrt(dot(v, v));
  return n > 0 ? (1 / n) * v : v;
}

Ray Camera::ray(double px, double py, int width, int height) const {
  const Vec3 forward = normalized(target - eye);
  const Vec3 right = normalized(cross(forward, up));
  const Vec3 true_up = cross(right, forward);
  // Pixel centre in [-1, 1] vertically, aspect-scaled horizontally.
  const double aspect = static_cast<double>(width) / height;
  const double sx = ((px + 0.5) / width * 2 - 1) * aspect, sy = 1 - (py + 0.5) / height * 2;
  if (orthographic) {
    const double half = ortho_height / 2;
    return {eye + (sx * half) * right + (sy * half) * true_up, forward};
  }
  const double t = std::tan(fov_degrees * M_PI / 360);
  return {eye, normalized(forward + (sx * t) * right + (sy * t) * true_up)};
}

Camera camera_for_box(const Vec3& lo, const Vec3& hi, double fov_degrees) {
  Camera c;
  c.target = 0.5 * (lo + hi);
  const double radius = 0.5 * std::sqrt(dot(hi - lo, hi - lo));
  // The bounding sphere of the box fits the view; models rarely fill their box.
  const double distance = 0.8 * radius / std::sin(fov_degrees * M_PI / 360);
  c.eye = c.target + distance * normalized({1, -0.8, 0.6});
  c.fov_degrees = fov_degrees;
  return c;
}

namespace {
std::vector<double> numbers(const std::string& text, const std::string& what) {
  std::vector<double> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(v))
      throw std::invalid_argument(what + ": \"" + item + "\" is not a number");
    out.push_back(v);
  }
  return out;
}
}  // namespace

Vec3 parse_vec3(const std::string& text, const std::string& what) {
  const std::vector<double> v = numbers(text, what);
  if (v.size() != 3) throw std::invalid_argument(what + ": expected three numbers a,b,c");
  return {v[0], v[1], v[2]};
}

Camera parse_camera(const std::string& text) {
  Camera c;
  const bool ortho = text.rfind("ortho,", 0) == 0;
  const std::vector<double> v = numbers(ortho ? text.substr(6) : text, "--camera");
  if (ortho ? v.size() != 7 : (v.size() != 6 && v.size() != 7))
    throw std::invalid_argument("--camera: expected ex,ey,ez,tx,ty,tz[,fov] or ortho,ex,ey,ez,tx,ty,tz,height");
  c.eye = {v[0], v[1], v[2]};
  c.target = {v[3], v[4], v[5]};
  if (dot(c.target - c.eye, c.target - c.eye) == 0) throw std::invalid_argument("--camera: eye and target coincide");
  if (std::abs(dot(normalized(c.target - c.eye), c.up)) > 0.999) c.up = {0, 1, 0};  // looking along z
  c.orthographic = ortho;
  if (ortho) c.ortho_height = v[6];
  if (!ortho && v.size() == 7) c.fov_degrees = v[6];
  if (ortho ? !(c.ortho_height > 0) : !(c.fov_degrees > 0 && c.fov_degrees < 180))
    throw std::invalid_argument(ortho ? "--camera: height must be positive" : "--camera: fov must be in (0, 180)");
  return c;
}

}  // namespace sage::render
