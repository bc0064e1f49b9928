#include "cut_cell_rule.hpp"

#include <sage/solver/gauss.hpp>
#include <sage/solver/mesh_domain.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace sage::solver {

namespace {

using Vec3 = std::array<double, 3>;

Vec3 minus(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

/// n . x + c = 0 with n the outward unit normal: the solid is where n . x + c < 0.
struct Plane {
  Vec3 n;
  double c;
  double at(const Vec3& x) const { return dot(n, x) + c; }
};

Plane triangle_plane(const Vec3& a, const Vec3& b, const Vec3& c) {
  Vec3 n = cross(minus(b, a), minus(c, a));
  const double length = std::sqrt(dot(n, n));
  for (double& x : n) x /= length;
  return {n, -dot(n, a)};
}

/// Whether the triangle meets the box of centre c and half-widths h
/// (separating axes: the box's 3 normals, the triangle's, and the 9 cross
/// products of their edges; Akenine-Moeller 2001).
bool triangle_meets_box(const Vec3& c, const Vec3& h, const Vec3& a0, const Vec3& b0, const Vec3& c0) {
  const Vec3 v[3] = {minus(a0, c), minus(b0, c), minus(c0, c)};
  const Vec3 e[3] = {minus(v[1], v[0]), minus(v[2], v[1]), minus(v[0], v[2])};
  auto separated = [&](const Vec3& axis) {
    const double p0 = dot(axis, v[0]), p1 = dot(axis, v[1]), p2 = dot(axis, v[2]);
    const double r = h[0] * std::abs(axis[0]) + h[1] * std::abs(axis[1]) + h[2] * std::abs(axis[2]);
    return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
  };
  for (int a = 0; a < 3; ++a) {
    Vec3 unit{0, 0, 0};
    unit[a] = 1.0;
    if (separated(unit)) return false;
    for (const Vec3& edge : e)
      if (separated(cross(edge, unit))) return false;
  }
  return !separated(cross(e[0], e[1]));
}

/// The part of the convex polygon where a . x + b <= 0 (Sutherland-Hodgman).
std::vector<Vec3> clip(const std::vector<Vec3>& polygon, const Vec3& a, double b) {
  std::vector<Vec3> out;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p = polygon[i];
    const Vec3& q = polygon[(i + 1) % n];
    const double dp = dot(a, p) + b, dq = dot(a, q) + b;
    if (dp <= 0) out.push_back(p);
    if ((dp < 0 && dq > 0) || (dp > 0 && dq < 0)) {
      const double t = dp / (dp - dq);
      out.push_back({p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1]), p[2] + t * (q[2] - p[2])});
    }
  }
  return out;
}

std::vector<Vec3> clip_to_box(std::vector<Vec3> polygon, const Box<3>& box) {
  for (int axis = 0; axis < 3 && polygon.size() >= 3; ++axis) {
    Vec3 a{0, 0, 0};
    a[axis] = -1.0;
    polygon = clip(polygon, a, box.lo[axis]);  // x_axis >= lo
    a[axis] = 1.0;
    if (polygon.size() >= 3) polygon = clip(polygon, a, -box.hi[axis]);  // x_axis <= hi
  }
  return polygon;
}

double area(const std::vector<Vec3>& polygon) {
  Vec3 sum{0, 0, 0};
  for (std::size_t i = 1; i + 1 < polygon.size(); ++i) {
    const Vec3 c = cross(minus(polygon[i], polygon[0]), minus(polygon[i + 1], polygon[0]));
    for (int a = 0; a < 3; ++a) sum[a] += c[a];
  }
  return 0.5 * std::sqrt(dot(sum, sum));
}

/// Whether every vertex lies on one face of the box (to `tolerance`).
bool on_a_face(const std::vector<Vec3>& polygon, const Box<3>& box, double tolerance) {
  for (int axis = 0; axis < 3; ++axis)
    for (const double face : {box.lo[axis], box.hi[axis]})
      if (std::all_of(polygon.begin(), polygon.end(),
                      [&](const Vec3& p) { return std::abs(p[axis] - face) <= tolerance; }))
        return true;
  return false;
}

/// Where the vertical line through (x, y) crosses the triangle, if it does:
/// the height, and whether the outward normal points up there (the solid
/// lies below the crossing).
struct Crossing {
  double z;
  bool leaving;  // going up through it leaves the solid
};

bool vertical_crossing(const Vec3& a, const Vec3& b, const Vec3& c, double x, double y, Crossing& out) {
  auto orient = [&](const Vec3& u, const Vec3& v) { return (v[0] - u[0]) * (y - u[1]) - (v[1] - u[1]) * (x - u[0]); };
  const double d0 = orient(b, c), d1 = orient(c, a), d2 = orient(a, b);
  const double sum = d0 + d1 + d2;
  if (sum == 0.0) return false;  // a vertical triangle: the line does not cross it
  if (!((d0 >= 0 && d1 >= 0 && d2 >= 0) || (d0 <= 0 && d1 <= 0 && d2 <= 0))) return false;
  out.z = (d0 * a[2] + d1 * b[2] + d2 * c[2]) / sum;
  out.leaving = sum > 0;  // counter-clockwise from above: the outward normal points up
  return true;
}

/// Crossings of the line through (x, y) with `triangles` at heights in
/// [lo, hi), sorted, one per point of the surface (a line through a shared
/// edge or vertex meets several triangles there with the same orientation).
std::vector<Crossing> crossings(const TriangleSurface& s, std::span<const std::uint32_t> triangles, double x, double y,
                                double lo, double hi, double merge) {
  std::vector<Crossing> out;
  for (const std::uint32_t t : triangles) {
    const auto& tri = s.triangles[t];
    Crossing c{};
    if (vertical_crossing(s.points[tri[0]], s.points[tri[1]], s.points[tri[2]], x, y, c) && c.z >= lo && c.z < hi)
      out.push_back(c);
  }
  std::sort(out.begin(), out.end(), [](const Crossing& a, const Crossing& b) { return a.z < b.z; });
  std::vector<Crossing> merged;
  for (const Crossing& c : out)
    if (merged.empty() || c.z - merged.back().z > merge || c.leaving != merged.back().leaving) merged.push_back(c);
  return merged;
}

/// The closest distance from p to the triangle (Ericson, Real-Time
/// Collision Detection, 5.1.5).
double distance_to_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = minus(b, a), ac = minus(c, a), ap = minus(p, a);
  auto length = [&](const Vec3& q) { return std::sqrt(dot(minus(p, q), minus(p, q))); };
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return length(a);
  const Vec3 bp = minus(p, b);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return length(b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return length({a[0] + v * ab[0], a[1] + v * ab[1], a[2] + v * ab[2]});
  }
  const Vec3 cp = minus(p, c);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return length(c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return length({a[0] + w * ac[0], a[1] + w * ac[1], a[2] + w * ac[2]});
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return length({b[0] + w * (c[0] - b[0]), b[1] + w * (c[1] - b[1]), b[2] + w * (c[2] - b[2])});
  }
  const double denominator = 1.0 / (va + vb + vc);
  const double v = vb * denominator, w = vc * denominator;
  return length({a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w, a[2] + ab[2] * v + ac[2] * w});
}

/// The vertical lines of the sweeps: each column's centre moved by these
/// fractions of h, so that the line meets no edge of a mesh whose vertices
/// sit on round coordinates.
constexpr double kLineOffsetX = 1.2345678e-4 * 3.14159265358979, kLineOffsetY = 2.3456789e-4 * 2.71828182845905;

}  // namespace

MeshDomain::MeshDomain(std::shared_ptr<const TriangleSurface> surface, const BackgroundGrid<3>& grid)
    : surface_(std::move(surface)), grid_(grid) {
  if (!surface_ || surface_->triangles.empty()) throw std::invalid_argument("the mesh has no triangles");
  const TriangleSurface& s = *surface_;
  const double h = grid_.h;
  const std::size_t cells = grid_.cell_count();
  auto linear = [&](int i, int j, int k) {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(grid_.cells[0]) *
               (static_cast<std::size_t>(j) + static_cast<std::size_t>(grid_.cells[1]) * static_cast<std::size_t>(k));
  };

  // 1. Binning: (cell, triangle) pairs, gathered per thread, then sorted by cell.
  std::vector<std::pair<std::size_t, std::uint32_t>> pairs;
#pragma omp parallel
  {
    std::vector<std::pair<std::size_t, std::uint32_t>> own;
#pragma omp for schedule(dynamic, 256) nowait
    for (std::size_t t = 0; t < s.triangles.size(); ++t) {
      const auto& tri = s.triangles[t];
      std::array<int, 3> first{}, last{};
      for (int a = 0; a < 3; ++a) {
        double lo = s.points[tri[0]][a], hi = lo;
        for (int v = 1; v < 3; ++v) {
          lo = std::min(lo, s.points[tri[v]][a]);
          hi = std::max(hi, s.points[tri[v]][a]);
        }
        first[a] = std::clamp(static_cast<int>(std::floor((lo - grid_.lo[a]) / h - 1e-9)), 0, grid_.cells[a] - 1);
        last[a] = std::clamp(static_cast<int>(std::floor((hi - grid_.lo[a]) / h + 1e-9)), 0, grid_.cells[a] - 1);
      }
      const Vec3 half{0.5 * h * (1 + 1e-9), 0.5 * h * (1 + 1e-9), 0.5 * h * (1 + 1e-9)};
      for (int k = first[2]; k <= last[2]; ++k)
        for (int j = first[1]; j <= last[1]; ++j)
          for (int i = first[0]; i <= last[0]; ++i) {
            const Vec3 centre{grid_.lo[0] + (i + 0.5) * h, grid_.lo[1] + (j + 0.5) * h, grid_.lo[2] + (k + 0.5) * h};
            if (triangle_meets_box(centre, half, s.points[tri[0]], s.points[tri[1]], s.points[tri[2]]))
              own.emplace_back(linear(i, j, k), static_cast<std::uint32_t>(t));
          }
    }
#pragma omp critical
    pairs.insert(pairs.end(), own.begin(), own.end());
  }
  std::sort(pairs.begin(), pairs.end());
  offset_.assign(cells + 1, 0);
  bins_.resize(pairs.size());
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    ++offset_[pairs[p].first + 1];
    bins_[p] = pairs[p].second;
  }
  for (std::size_t c = 0; c < cells; ++c) offset_[c + 1] += offset_[c];

  // 2. Classification: one upward sweep per column.
  kinds_.assign(cells, CellKind::Outside);
  const double merge = 1e-9 * h, tolerance = 1e-9 * h;
#pragma omp parallel for schedule(dynamic, 16) collapse(2)
  for (int j = 0; j < grid_.cells[1]; ++j)
    for (int i = 0; i < grid_.cells[0]; ++i) {
      const double x = grid_.lo[0] + (i + 0.5 + kLineOffsetX) * h, y = grid_.lo[1] + (j + 0.5 + kLineOffsetY) * h;
      bool status = false;  // below the grid: outside
      for (int k = 0; k < grid_.cells[2]; ++k) {
        const std::size_t c = linear(i, j, k);
        const auto here = triangles(c);
        if (here.empty()) {
          kinds_[c] = status ? CellKind::Inside : CellKind::Outside;
          continue;
        }
        const double lo = grid_.lo[2] + k * h, centre = lo + 0.5 * h;
        const std::vector<Crossing> line = crossings(s, here, x, y, lo, lo + h, merge);
        bool at_centre = status;
        for (const Crossing& cross : line)
          if (cross.z <= centre) at_centre = !cross.leaving;
        if (!line.empty()) status = !line.back().leaving;
        // Cut unless the triangles only touch the cell.
        const Box<3> box{{grid_.lo[0] + i * h, grid_.lo[1] + j * h, lo},
                         {grid_.lo[0] + (i + 1) * h, grid_.lo[1] + (j + 1) * h, lo + h}};
        bool cut = false;
        for (const std::uint32_t t : here) {
          const auto& tri = s.triangles[t];
          const std::vector<Vec3> part = clip_to_box({s.points[tri[0]], s.points[tri[1]], s.points[tri[2]]}, box);
          if (part.size() >= 3 && area(part) > 1e-12 * h * h && !on_a_face(part, box, tolerance)) {
            cut = true;
            break;
          }
        }
        kinds_[c] = cut ? CellKind::Cut : (at_centre ? CellKind::Inside : CellKind::Outside);
      }
    }
}

std::span<const std::uint32_t> MeshDomain::triangles(std::size_t cell) const {
  return {bins_.data() + offset_[cell], offset_[cell + 1] - offset_[cell]};
}

bool MeshDomain::inside_on_line(double x, double y, double z) const {
  const double h = grid_.h;
  const std::array<double, 3> p{x, y, z};
  auto c = grid_.cell_of(p.data());
  for (; c[2] < grid_.cells[2]; ++c[2]) {
    std::size_t linear = 0;
    for (int a = 2; a >= 0; --a)
      linear = linear * static_cast<std::size_t>(grid_.cells[a]) + static_cast<std::size_t>(c[a]);
    const auto here = triangles(linear);
    // No triangle between z and this cell: the line has the cell's status.
    if (here.empty()) return kinds_[linear] == CellKind::Inside;
    const double lo = grid_.lo[2] + c[2] * h;
    // The top cell keeps crossings on its top face: a solid whose top lies
    // on the grid's would otherwise look open above.
    const double hi = c[2] + 1 == grid_.cells[2] ? HUGE_VAL : lo + h;
    for (const Crossing& cross : crossings(*surface_, here, x, y, std::max(lo, z), hi, 1e-9 * h))
      if (cross.z > z) return cross.leaving;
  }
  return false;  // above the grid: outside
}

bool MeshDomain::inside(const std::array<double, 3>& p) const {
  // Off the lattice and off the mesh's round coordinates, like the sweeps.
  return inside_on_line(p[0] + kLineOffsetX * 1e-3 * grid_.h, p[1] + kLineOffsetY * 1e-3 * grid_.h, p[2]);
}

double MeshDomain::signed_distance(const std::array<double, 3>& p, double band) const {
  const double h = grid_.h;
  const int reach = static_cast<int>(std::ceil(band / h));
  const auto c = grid_.cell_of(p.data());
  double nearest = band;
  for (int k = std::max(0, c[2] - reach); k <= std::min(grid_.cells[2] - 1, c[2] + reach); ++k)
    for (int j = std::max(0, c[1] - reach); j <= std::min(grid_.cells[1] - 1, c[1] + reach); ++j)
      for (int i = std::max(0, c[0] - reach); i <= std::min(grid_.cells[0] - 1, c[0] + reach); ++i) {
        const std::size_t linear =
            static_cast<std::size_t>(i) +
            static_cast<std::size_t>(grid_.cells[0]) *
                (static_cast<std::size_t>(j) + static_cast<std::size_t>(grid_.cells[1]) * static_cast<std::size_t>(k));
        for (const std::uint32_t t : triangles(linear)) {
          const auto& tri = surface_->triangles[t];
          nearest = std::min(nearest, distance_to_triangle(p, surface_->points[tri[0]], surface_->points[tri[1]],
                                                           surface_->points[tri[2]]));
        }
      }
  return inside(p) ? nearest : -nearest;
}

// ---------------------------------------------------------------------------
// Cut cells: the clipped triangles as a Boolean formula of their planes.

namespace {

/// A convex piece of the surface in a box, on the box's plane `plane`.
struct Polygon {
  std::vector<Vec3> vertices;
  std::uint32_t plane;
};

/// The planes of a box as pieces: n . x + c <= 0 inside, so the piece is
/// -(n . x + c), >= 0 in the solid.
class PlanePieces final : public PieceSource<3> {
 public:
  std::vector<Plane> planes;
  std::size_t count() const override { return planes.size(); }
  double value(std::uint32_t i, const std::array<double, 3>& p) override { return -planes[i].at(p); }
  double gradient(std::uint32_t i, const std::array<double, 3>& p, std::array<double, 3>& g) override {
    for (int a = 0; a < 3; ++a) g[a] = -planes[i].n[a];
    return -planes[i].at(p);
  }
  std::array<Interval, 4> enclosure(std::uint32_t i, const std::array<Interval, 3>& box) override {
    const Plane& q = planes[i];
    const Interval v =
        Interval(q.n[0]) * box[0] + Interval(q.n[1]) * box[1] + Interval(q.n[2]) * box[2] + Interval(q.c);
    return {-v, Interval(-q.n[0]), Interval(-q.n[1]), Interval(-q.n[2])};
  }
  bool planar(std::uint32_t) const override { return true; }
};

/// A cell's triangles go to the rule with its breaks when they lie on at
/// most this many planes and two of those meet at a sharp angle (an edge
/// or corner of a part: the integrand along the base jumps or bends hard
/// there). Otherwise (the facets of a curved surface, whose bends are
/// slight, or many planes around a vertex, where the breaks would carry
/// every pair's crossing line: 4,700 points per cell with 4 planes on a
/// gear's flanks) the volume comes from exact lines over an unbroken
/// base, and the surface from the polygons.
constexpr std::size_t kMaxRulePlanes = 4;
/// Normals at more than 30 degrees: a sharp meeting.
constexpr double kSharpCosine = 0.8660254037844387;

/// Gauss points on the triangle (a, b, c), q^2 of them: the square's
/// tensor rule collapsed onto it (x = a + s (b - a) + s t (c - b), Jacobian
/// 2 area s), exact for polynomials of degree 2q - 2.
template <class Visit>
void triangle_rule(const Vec3& a, const Vec3& b, const Vec3& c, int q, Visit&& visit) {
  const GaussRule& rule = gauss_legendre(q);
  const double twice_area = std::sqrt(dot(cross(minus(b, a), minus(c, a)), cross(minus(b, a), minus(c, a))));
  for (std::size_t i = 0; i < rule.nodes.size(); ++i)
    for (std::size_t j = 0; j < rule.nodes.size(); ++j) {
      const double s = rule.nodes[i], t = rule.nodes[j];
      Vec3 x{};
      for (int k = 0; k < 3; ++k) x[k] = a[k] + s * (b[k] - a[k]) + s * t * (c[k] - b[k]);
      visit(x, twice_area * s * rule.weights[i] * rule.weights[j]);
    }
}

}  // namespace

class MeshCellQuadrature::Impl {
 public:
  Impl(const MeshDomain& domain, QuadratureOptions options) : domain_(domain), options_(options), rule_(options) {}

  void append(std::size_t cell, const Box<3>& box, std::vector<VolumePoint<3>>& volume,
              std::vector<SurfacePoint<3>>* surface) {
    const CellKind kind = domain_.kinds()[cell];
    const auto triangles = domain_.triangles(cell);
    if (triangles.empty()) {
      pieces_.planes.clear();
      if (kind == CellKind::Inside)
        rule_.append(pieces_, box, {CellKind::Inside, BooleanFormula::constant(true)}, volume, surface);
      return;
    }
    h_ = box.hi[0] - box.lo[0];
    // The clipped triangles, with coplanar ones on one plane.
    std::vector<Plane> planes;
    std::vector<Polygon> polygons;
    const TriangleSurface& s = domain_.surface();
    for (const std::uint32_t t : triangles) {
      const auto& tri = s.triangles[t];
      std::vector<Vec3> part = clip_to_box({s.points[tri[0]], s.points[tri[1]], s.points[tri[2]]}, box);
      if (part.size() < 3 || !(area(part) > 1e-12 * h_ * h_)) continue;
      const Plane plane = triangle_plane(s.points[tri[0]], s.points[tri[1]], s.points[tri[2]]);
      std::uint32_t id = 0;
      for (; id < planes.size(); ++id)
        if (dot(planes[id].n, plane.n) > 1.0 - 1e-10 && std::all_of(part.begin(), part.end(), [&](const Vec3& v) {
              return std::abs(planes[id].at(v)) <= 1e-8 * h_;
            }))
          break;
      if (id == planes.size()) planes.push_back(plane);
      polygons.push_back({std::move(part), id});
    }
    integrate(box, planes, polygons, volume, surface);
  }

  const QuadratureCounts& counts() const {
    merged_ = rule_.counts();
    merged_.unbroken_boxes += own_.unbroken_boxes;
    return merged_;
  }

 private:
  void integrate(const Box<3>& box, const std::vector<Plane>& planes, const std::vector<Polygon>& polygons,
                 std::vector<VolumePoint<3>>& volume, std::vector<SurfacePoint<3>>* surface) {
    std::vector<std::uint32_t> used;
    for (const Polygon& p : polygons) used.push_back(p.plane);
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    // The box's planes as pieces 0..m-1.
    pieces_.planes.clear();
    std::vector<std::uint32_t> local(planes.size(), 0);
    for (const std::uint32_t id : used) {
      local[id] = static_cast<std::uint32_t>(pieces_.planes.size());
      pieces_.planes.push_back(planes[id]);
    }
    std::vector<Polygon> renumbered = polygons;
    for (Polygon& p : renumbered) p.plane = local[p.plane];
    if (used.size() > kMaxRulePlanes || (used.size() > 1 && !sharp(pieces_.planes)))
      return unbroken(box, renumbered, volume, surface);
    std::array<Interval, 3> x{};
    for (int a = 0; a < 3; ++a) x[a] = Interval(box.lo[a], box.hi[a]);
    const BooleanFormula formula =
        renumbered.empty() ? BooleanFormula::constant(domain_.inside(centre(box))) : partition(renumbered);
    auto enclosure = [&](std::uint32_t p) { return pieces_.enclosure(p, x)[0]; };
    const BooleanFormula restricted =
        formula.restricted([&](std::size_t p) { return sign_of(enclosure(static_cast<std::uint32_t>(p))); });
    rule_.append(pieces_, box, classified_cell(restricted, enclosure), volume, surface);
  }

  /// Whether two of the planes meet at an edge of the solid (a feature
  /// the rule must resolve), not at the slight bend between the facets of
  /// a curved surface.
  static bool sharp(const std::vector<Plane>& planes) {
    for (std::size_t i = 0; i < planes.size(); ++i)
      for (std::size_t j = i + 1; j < planes.size(); ++j)
        if (dot(planes[i].n, planes[j].n) < kSharpCosine) return true;
    return false;
  }

  /// A box with too many planes for the rule's breaks (around a vertex
  /// where many triangles meet, or a mesh much finer than the grid): the
  /// volume from lines along the axis most normals point along, with exact
  /// roots but over a base without breaks, and the polygons' own surface
  /// rules. Counted in QuadratureCounts::unbroken_boxes.
  void unbroken(const Box<3>& box, const std::vector<Polygon>& polygons, std::vector<VolumePoint<3>>& volume,
                std::vector<SurfacePoint<3>>* surface) {
    ++own_.unbroken_boxes;
    const BooleanFormula formula = partition(polygons);
    rule_.append(pieces_, box, {CellKind::Cut, formula}, volume, nullptr, false);
    if (!surface) return;
    const double tolerance = 1e-9 * h_;
    for (const Polygon& polygon : polygons) {
      const Vec3& n = pieces_.planes[polygon.plane].n;
      // A polygon in a face of the box belongs to the box on the solid's side.
      bool foreign = false;
      for (int a = 0; a < 3; ++a)
        for (const double face : {box.lo[a], box.hi[a]})
          if (std::all_of(polygon.vertices.begin(), polygon.vertices.end(),
                          [&](const Vec3& v) { return std::abs(v[a] - face) <= tolerance; }))
            foreign = foreign || (face == box.lo[a] ? n[a] > 0 : n[a] < 0);
      if (foreign) continue;
      for (std::size_t v = 1; v + 1 < polygon.vertices.size(); ++v)
        triangle_rule(polygon.vertices[0], polygon.vertices[v], polygon.vertices[v + 1], options_.points,
                      [&](const Vec3& x, double w) {
                        surface->push_back({x, w, n});
                      });
    }
  }

  static Vec3 centre(const Box<3>& box) {
    return {0.5 * (box.lo[0] + box.hi[0]), 0.5 * (box.lo[1] + box.hi[1]), 0.5 * (box.lo[2] + box.hi[2])};
  }

  /// The solid in the box as a formula of the polygons' planes: a binary
  /// space partition by the first polygon's plane, front leaves outside
  /// and back leaves inside (every polygon lies in the box, so the region
  /// just behind the splitting polygon is the solid and just in front is
  /// not; each side without polygons is that way throughout, being convex).
  BooleanFormula partition(const std::vector<Polygon>& polygons) {
    const std::uint32_t split = polygons.front().plane;
    const Plane& plane = pieces_.planes[split];
    const double tolerance = 1e-9 * h_;
    std::vector<Polygon> front, back;
    for (const Polygon& p : polygons) {
      if (p.plane == split) continue;
      bool any_front = false, any_back = false;
      for (const Vec3& v : p.vertices) {
        const double d = plane.at(v);
        any_front = any_front || d > tolerance;
        any_back = any_back || d < -tolerance;
      }
      if (!any_front && !any_back) continue;  // in the plane
      if (!any_back) {
        front.push_back(p);
      } else if (!any_front) {
        back.push_back(p);
      } else {
        const Vec3 minus_n{-plane.n[0], -plane.n[1], -plane.n[2]};
        std::vector<Vec3> f = clip(p.vertices, minus_n, -plane.c), b = clip(p.vertices, plane.n, plane.c);
        if (f.size() >= 3) front.push_back({std::move(f), p.plane});
        if (b.size() >= 3) back.push_back({std::move(b), p.plane});
      }
    }
    const BooleanFormula behind = BooleanFormula::piece(split);
    const BooleanFormula in_back = back.empty() ? BooleanFormula::constant(true) : partition(back);
    const BooleanFormula in_front = front.empty() ? BooleanFormula::constant(false) : partition(front);
    return BooleanFormula::disjunction(BooleanFormula::conjunction(behind, in_back),
                                       BooleanFormula::conjunction(BooleanFormula::negation(behind), in_front));
  }

  const MeshDomain& domain_;
  QuadratureOptions options_;
  CutCellRule<3> rule_;
  PlanePieces pieces_;
  double h_ = 1.0;
  QuadratureCounts own_;
  mutable QuadratureCounts merged_;
};

MeshCellQuadrature::MeshCellQuadrature(const MeshDomain& domain, QuadratureOptions options)
    : impl_(std::make_unique<Impl>(domain, options)) {}

MeshCellQuadrature::~MeshCellQuadrature() = default;

MeshCellQuadrature::MeshCellQuadrature(MeshCellQuadrature&&) noexcept = default;

void MeshCellQuadrature::append_rule(std::size_t cell, const Box<3>& box, std::vector<VolumePoint<3>>& volume,
                                     std::vector<SurfacePoint<3>>* surface) {
  impl_->append(cell, box, volume, surface);
}

const QuadratureCounts& MeshCellQuadrature::counts() const { return impl_->counts(); }

}  // namespace sage::solver
