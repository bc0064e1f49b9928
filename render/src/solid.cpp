#include <sage/render/solid.hpp>

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace sage::render {

namespace {

const Vec3 kPalette[] = {{0.85, 0.55, 0.35}, {0.35, 0.6, 0.85}, {0.5, 0.78, 0.4},   {0.85, 0.4, 0.5},
                         {0.75, 0.7, 0.35},  {0.6, 0.45, 0.8},  {0.35, 0.75, 0.72}, {0.9, 0.65, 0.6}};
const Vec3 kSolidColour{0.8, 0.72, 0.6};

std::uint8_t to_byte(double v) { return static_cast<std::uint8_t>(std::clamp(v, 0.0, 1.0) * 255.0 + 0.5); }

Vec3 background(double py, int height) {
  const double s = py / height;
  return {0.93 - 0.25 * s, 0.94 - 0.22 * s, 0.96 - 0.15 * s};
}

/// Per-thread state: evaluators are not thread-safe.
struct Shader {
  Shader(const FieldTapes& tapes, const Tape* materials, double leaf, bool prune)
      : caster(tapes, leaf, prune), normal_eval(tapes.field) {
    if (materials) material_eval.emplace(*materials);
  }
  RayCaster caster;
  Evaluator<Tuple<3, 1>> normal_eval;
  std::optional<Evaluator<double>> material_eval;
  long long rays = 0;
};

}  // namespace

SolidPicture render_solid(const Expr& field, const Vec3& box_min, const Vec3& box_max, const SolidOptions& o) {
  if (o.width <= 0 || o.height <= 0) throw std::invalid_argument("image size must be positive");
  for (int i = 0; i < 3; ++i)
    if (!(box_max[i] > box_min[i])) throw std::invalid_argument("the render box is empty");
  const auto start = std::chrono::steady_clock::now();
  const FieldTapes tapes(field);
  std::optional<Tape> material_tape;
  if (!o.materials.empty()) material_tape.emplace(o.materials, 3);
  const Vec3 diagonal = box_max - box_min;
  const double size = std::sqrt(dot(diagonal, diagonal)), leaf = o.relative_leaf_width * size;
  const Vec3 light = normalized(o.light_direction);

  SolidPicture pic;
  pic.image = output::RgbImage(o.width, o.height);
  pic.depth.assign(static_cast<std::size_t>(o.width) * o.height, std::numeric_limits<double>::infinity());
  long long hits = 0, rays = 0, interval_evals = 0, point_evals = 0;

#pragma omp parallel reduction(+ : hits, rays, interval_evals, point_evals)
  {
    Shader sh(tapes, material_tape ? &*material_tape : nullptr, leaf, o.prune_tapes);
#pragma omp for schedule(dynamic, 2)
    for (int py = 0; py < o.height; ++py) {
      for (int px = 0; px < o.width; ++px) {
        const Ray ray = o.camera.ray(px, py, o.width, o.height);
        Vec3 colour = background(py, o.height);
        ++rays;
        const auto span = clip_to_box(ray, box_min, box_max);
        const auto t = span ? sh.caster.first_hit(ray, span->first, span->second, o.method) : std::nullopt;
        if (t) {
          ++hits;
          const Vec3 p = ray.origin + *t * ray.direction;
          pic.depth[static_cast<std::size_t>(py) * o.width + px] = *t;
          const auto g = sh.normal_eval.at(p).gradient();
          Vec3 n = normalized({-g[0], -g[1], -g[2]});
          if (dot(n, n) == 0 || dot(n, ray.direction) > 0) n = -1.0 * ray.direction;  // cut faces, singular points
          Vec3 base = kSolidColour;
          if (sh.material_eval) {
            sh.material_eval->evaluate(p.data());
            std::size_t best = 0;
            for (std::size_t i = 1; i < o.materials.size(); ++i)
              if (std::abs(sh.material_eval->result(i)) < std::abs(sh.material_eval->result(best))) best = i;
            base = kPalette[best % std::size(kPalette)];
          }
          bool lit = dot(n, light) > 0;
          if (lit && o.shadows) {
            ++rays;
            const Ray to_light{p + (4 * leaf) * n, light};
            const auto shadow_span = clip_to_box(to_light, box_min, box_max);
            lit = !(shadow_span && sh.caster.first_hit(to_light, shadow_span->first, shadow_span->second, o.method));
          }
          const double diffuse = lit ? std::max(0.0, dot(n, light)) : 0.0;
          const Vec3 half = normalized(light - ray.direction);
          const double specular = lit ? std::pow(std::max(0.0, dot(n, half)), 48) : 0.0;
          for (int c = 0; c < 3; ++c) colour[c] = base[c] * (0.18 + 0.75 * diffuse) + 0.35 * specular;
        }
        std::uint8_t* out = pic.image.pixel(px, py);
        for (int c = 0; c < 3; ++c) out[c] = to_byte(colour[c]);
      }
    }
    interval_evals += sh.caster.stats().interval_evaluations;
    point_evals += sh.caster.stats().point_evaluations;
  }
  pic.stats = {rays, hits, interval_evals, point_evals,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()};
  return pic;
}

}  // namespace sage::render
