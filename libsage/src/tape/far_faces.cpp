#include <sage/tape/far_faces.hpp>

#include "../scalars/vector_clones.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>

namespace sage {

namespace {

using V3 = std::array<double, 3>;

// Where three planes g . p + o = 0 meet (Cramer's rule); false if they
// hardly do (a degenerate face: no box, never a far cluster).
bool meet(const std::array<V3, 3>& g, const std::array<double, 3>& o, V3& p) {
  auto det = [](const V3& a, const V3& b, const V3& c) {
    return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
  };
  const double d = det(g[0], g[1], g[2]);
  auto norm = [](const V3& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); };
  if (!(std::fabs(d) > 1e-9 * norm(g[0]) * norm(g[1]) * norm(g[2]))) return false;
  const V3 rhs{-o[0], -o[1], -o[2]};
  for (int a = 0; a < 3; ++a) {
    std::array<V3, 3> m = g;
    for (int r = 0; r < 3; ++r) m[r][a] = rhs[r];
    p[a] = det(m[0], m[1], m[2]) / d;
  }
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

double diagonal(const Box3& b) {
  double s = 0;
  for (int a = 0; a < 3; ++a) s += (b.hi[a] - b.lo[a]) * (b.hi[a] - b.lo[a]);
  return std::sqrt(s);
}

double distance(const Box3& a, const Box3& b) {
  double s = 0;
  for (int k = 0; k < 3; ++k) {
    const double gap = std::max({a.lo[k] - b.hi[k], b.lo[k] - a.hi[k], 0.0});
    s += gap * gap;
  }
  return std::sqrt(s);
}

constexpr std::size_t kLanes = FarFaces::kMaxLanes;

// A cluster value's lanes: value, then the three partials.
struct Slot {
  alignas(64) float c[4][kLanes];
};

// The intermediate values of a face at every lane (face_lanes).
struct FaceStages {
  alignas(64) float h[kLanes], s1[kLanes], s2[kLanes], s3[kLanes];
  alignas(64) float r1[kLanes], u[kLanes], r2[kLanes], t[kLanes], root[kLanes], m[kLanes];
};

// The face at every lane: w = sqrt(h^2 + (R p + t q)^2), R = sqrt(t^2 +
// (c h)^4), t = (s1 AND s2) AND s3 by R0 (signs E1, E2: -1 conjunction),
// and its partials by the chain rule through the planes (whose gradients
// are constant). g: the planes' gradients, o: their values at the centre
// (q = 0), constants: FloatFace's.
//
// Why in stages, a loop each: the value is a chain of four square roots,
// and in one loop the vector units waited on it (the processor holds too
// few operations in flight to overlap several lanes' chains); each stage's
// loop has a short chain and independent lanes. The signs are template
// arguments (R0's +-r are additions), and the four reciprocals come from
// two divisions.
template <bool Gradient, int E1, int E2>
SAGE_VECTOR_CLONES void face_lanes(const std::array<std::array<float, 3>, 4>& g, const std::array<float, 4>& o,
                                   const std::array<float, 5>& constants, const float* __restrict qx,
                                   const float* __restrict qy, const float* __restrict qz, std::size_t count,
                                   FaceStages& __restrict f, Slot& __restrict out) {
  const float g00 = g[0][0], g01 = g[0][1], g02 = g[0][2], o0 = o[0];
  const float g10 = g[1][0], g11 = g[1][1], g12 = g[1][2], o1 = o[1];
  const float g20 = g[2][0], g21 = g[2][1], g22 = g[2][2], o2 = o[2];
  const float g30 = g[3][0], g31 = g[3][1], g32 = g[3][2], o3 = o[3];
  const float c = constants[2], p = constants[3], q = constants[4];
  for (std::size_t l = 0; l < count; ++l) {  // the planes, and R0's root of the first two sides
    const float x = qx[l], y = qy[l], z = qz[l];
    const float s1 = g10 * x + g11 * y + g12 * z + o1, s2 = g20 * x + g21 * y + g22 * z + o2;
    f.h[l] = g00 * x + g01 * y + g02 * z + o0;
    f.s1[l] = s1;
    f.s2[l] = s2;
    f.s3[l] = g30 * x + g31 * y + g32 * z + o3;
    f.r1[l] = std::sqrt(s1 * s1 + s2 * s2);
  }
  for (std::size_t l = 0; l < count; ++l) {  // u = s1 AND/OR s2, and R0's root of u and s3
    const float u = E1 > 0 ? (f.s1[l] + f.s2[l]) + f.r1[l] : (f.s1[l] + f.s2[l]) - f.r1[l];
    f.u[l] = u;
    f.r2[l] = std::sqrt(u * u + f.s3[l] * f.s3[l]);
  }
  for (std::size_t l = 0; l < count; ++l) {  // t = u AND/OR s3, and R
    const float t = E2 > 0 ? (f.u[l] + f.s3[l]) + f.r2[l] : (f.u[l] + f.s3[l]) - f.r2[l];
    const float hc = f.h[l] * c, hc2 = hc * hc;
    f.t[l] = t;
    f.root[l] = std::sqrt(t * t + hc2 * hc2);
  }
  for (std::size_t l = 0; l < count; ++l) {  // the value
    const float m = f.root[l] * p + f.t[l] * q, h = f.h[l];
    f.m[l] = m;
    out.c[0][l] = std::sqrt(h * h + m * m);
  }
  if constexpr (!Gradient) return;
  const float dr_factor = 2.0f * p * c;  // dm/dh = p dR/dh = 2 p c (c h)^3 / R
  constexpr float e1 = E1, e2 = E2;
  for (std::size_t l = 0; l < count; ++l) {
    const float h = f.h[l], u = f.u[l], t = f.t[l], m = f.m[l], w = out.c[0][l];
    const float root = f.root[l], r1 = f.r1[l], r2 = f.r2[l];
    // A product out of the normal range (or not finite) makes the lane's
    // reciprocals infinite: its partials are then not finite, and the
    // doubles redo the cluster.
    const float outer = root * w, inner = r1 * r2;
    const bool normal = std::min(outer, inner) >= std::numeric_limits<float>::min() &&
                        std::max(outer, inner) <= std::numeric_limits<float>::max();
    const float infinity = std::numeric_limits<float>::infinity();
    const float inverse_outer = normal ? 1.0f / outer : infinity, inverse_inner = normal ? 1.0f / inner : infinity;
    const float inverse_root = inverse_outer * w, inverse_w = inverse_outer * root;
    const float inverse_r1 = inverse_inner * r2, inverse_r2 = inverse_inner * r1;
    const float hc = h * c;
    const float dm_dh = dr_factor * (hc * hc * hc) * inverse_root;
    const float dm_dt = (p * t) * inverse_root + q;
    const float m_w = m * inverse_w;
    const float dw_dh = m_w * dm_dh + h * inverse_w;
    const float dw_dt = m_w * dm_dt;
    // dw/du = dw/dt (1 + e2 u / r2), dw/ds3 = dw/dt (1 + e2 s3 / r2), and
    // so on down to s1 and s2.
    const float by_r2 = dw_dt * (e2 * inverse_r2);
    const float dw_du = u * by_r2 + dw_dt, a3 = f.s3[l] * by_r2 + dw_dt;
    const float by_r1 = dw_du * (e1 * inverse_r1);
    const float a1 = f.s1[l] * by_r1 + dw_du, a2 = f.s2[l] * by_r1 + dw_du;
    out.c[1][l] = dw_dh * g00 + a1 * g10 + a2 * g20 + a3 * g30;
    out.c[2][l] = dw_dh * g01 + a1 * g11 + a2 * g21 + a3 * g31;
    out.c[3][l] = dw_dh * g02 + a1 * g12 + a2 * g22 + a3 * g32;
  }
}

// face_lanes with the face's signs as template arguments.
template <bool Gradient>
void face_lanes(const std::array<std::array<float, 3>, 4>& g, const std::array<float, 4>& o,
                const std::array<float, 5>& constants, const float* qx, const float* qy, const float* qz,
                std::size_t count, FaceStages& stages, Slot& out) {
  const bool or1 = constants[0] > 0, or2 = constants[1] > 0;
  if (or1 && or2)
    face_lanes<Gradient, 1, 1>(g, o, constants, qx, qy, qz, count, stages, out);
  else if (or1)
    face_lanes<Gradient, 1, -1>(g, o, constants, qx, qy, qz, count, stages, out);
  else if (or2)
    face_lanes<Gradient, -1, 1>(g, o, constants, qx, qy, qz, count, stages, out);
  else
    face_lanes<Gradient, -1, -1>(g, o, constants, qx, qy, qz, count, stages, out);
}

// a = a AND b (sign -1) or a OR b (+1) by R0, lane by lane, of values
// >= 0 (faces and clusters). The conjunction x + y - r (r = sqrt(x^2 +
// y^2)) as 2 x y / (x + y + r): the same number without the cancellation
// that costs x + y - r relative accuracy where x >> y (single precision's
// 6e-8 times x / y; the field then missed 1e-9 of the diagonal on a 3,290
// triangle STL part).
template <bool Gradient, int Sign>
SAGE_VECTOR_CLONES void glue_lanes(Slot& a, const Slot& b, std::size_t count) {
  constexpr float sign = Sign;
  for (std::size_t l = 0; l < count; ++l) {
    const float x = a.c[0][l], y = b.c[0][l];
    const float r = std::sqrt(x * x + y * y), sum = x + y + r;
    if constexpr (Gradient) {
      const float inverse = 1.0f / (r * sum);  // 1 / r and 1 / sum in one division
      a.c[0][l] = Sign < 0 ? 2.0f * x * y * (r * inverse) : sum;
      const float by_r = sign * (sum * inverse);
      const float dx = x * by_r + 1.0f, dy = y * by_r + 1.0f;
      for (int k = 1; k <= 3; ++k) a.c[k][l] = dx * a.c[k][l] + dy * b.c[k][l];
    } else {
      a.c[0][l] = Sign < 0 ? 2.0f * x * y / sum : sum;
    }
  }
}

template <bool Gradient>
void glue_lanes(Slot& a, const Slot& b, float sign, std::size_t count) {
  if (sign < 0)
    glue_lanes<Gradient, -1>(a, b, count);
  else
    glue_lanes<Gradient, 1>(a, b, count);
}

// Whether a float is finite, from its bits (one integer test per lane).
inline bool finite_bits(float x) {
  std::uint32_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  return (bits & 0x7f800000u) != 0x7f800000u;
}

// Whether every lane's value (and partials) is finite.
template <bool Gradient>
SAGE_VECTOR_CLONES bool all_finite(const Slot& s, std::size_t count) {
  unsigned bad = 0;
  for (int k = 0; k < (Gradient ? 4 : 1); ++k)
    for (std::size_t l = 0; l < count; ++l) bad |= finite_bits(s.c[k][l]) ? 0u : 1u;
  return bad == 0;
}

}  // namespace

bool far_faces_pay(const Tape& tape) {
  if (tape.dimension() != 3) return false;
  std::vector<char> is_constant(tape.register_count(), 0);
  std::vector<double> constant_value(tape.register_count(), 0.0);
  for (const auto& [r, c] : tape.constants()) {
    is_constant[r] = 1;
    constant_value[r] = c;
  }
  // Small meshes gain little (joint's 446 faces: sampling 1.4 times faster,
  // against 3 times from 3,000 faces up), and their fields are large
  // against their diagonals (fewer conjunctions shrink them), where single
  // precision's roundings come closest to the limit (joint at 64^3: 9.9e-10
  // of the diagonal at 10,000 points, mesh_deviation_bench).
  constexpr std::size_t kEnough = 1024;
  std::size_t faces = 0;
  const std::size_t n = tape.code().size();
  for (std::size_t i = 0; i < n && faces < kEnough; ++i)
    if (const auto run = find_trimmed_face(tape, i, is_constant, constant_value)) {
      ++faces;
      i += run->length - 1;
    }
  return faces >= kEnough;
}

void FarFaces::build(const std::vector<Step>& steps, const std::vector<std::uint32_t>& results) {
  faces_.clear();
  program_.clear();
  clusters_.clear();
  std::vector<std::size_t> op_of_step(steps.size(), static_cast<std::size_t>(-1));  // index into program_
  largest_at_.assign(steps.size(), -1);

  // Candidate clusters, bottom up: a face, or an R0 of two candidates whose
  // steps come just before it, one after the other.
  struct Candidate {
    std::size_t first, last;
    std::uint32_t out;
    Box3 box;
    bool has_box;
    int parent = -1;
    bool valid = true;
  };
  std::vector<Candidate> nodes;
  std::vector<int> node_at_root(steps.size(), -1);
  std::vector<int> node_of_register;
  std::vector<std::ptrdiff_t> writer;  // by register: the step that last wrote it
  auto grow = [](std::vector<int>& v, std::uint32_t r, int fill) {
    if (v.size() <= r) v.resize(static_cast<std::size_t>(r) + 1, fill);
  };
  auto write = [&](std::uint32_t r, std::size_t step, int node) {
    grow(node_of_register, r, -1);
    node_of_register[r] = node;
    if (writer.size() <= r) writer.resize(static_cast<std::size_t>(r) + 1, -1);
    writer[r] = static_cast<std::ptrdiff_t>(step);
  };
  auto node_in = [&](std::uint32_t r) { return r < node_of_register.size() ? node_of_register[r] : -1; };

  // Reads of a register written inside a candidate, from outside it, make
  // the candidate (and every one around it that does not hold the reader)
  // unusable: its internal results would be missing.
  auto read = [&](std::uint32_t r, std::size_t at) {
    if (r >= writer.size() || writer[r] < 0) return;
    int n = node_at_root[static_cast<std::size_t>(writer[r])];
    if (n < 0) return;
    for (int p = nodes[static_cast<std::size_t>(n)].parent; p >= 0; p = nodes[static_cast<std::size_t>(p)].parent) {
      Candidate& up = nodes[static_cast<std::size_t>(p)];
      if (up.first <= at && at <= up.last) break;
      up.valid = false;
    }
  };

  for (std::size_t i = 0; i < steps.size(); ++i) {
    const Step& s = steps[i];
    if (s.kind == Step::Kind::Face) {
      const TrimmedFace& t = *s.face;
      FloatFace f;
      for (int k = 0; k < 4; ++k) {
        for (int a = 0; a < 3; ++a) {
          f.gradient[k][a] = t.planes[k].partials[a];
          f.single[k][a] = static_cast<float>(f.gradient[k][a]);
        }
        f.offset[k] = t.planes[k].form.has_offset ? t.planes[k].form.d : 0.0;
      }
      f.constants = {static_cast<float>(t.first_sign), static_cast<float>(t.second_sign),
                     static_cast<float>(t.trim.has_scale ? t.trim.scale : 1.0), static_cast<float>(t.trim.root_weight),
                     static_cast<float>(t.trim.t_weight)};
      Candidate node{i, i, s.out, {}, true};
      for (int corner = 0; corner < 3 && node.has_box; ++corner) {
        // Vertex opposite side plane `corner`: h = 0 and the other two sides.
        std::array<V3, 3> g{};
        std::array<double, 3> o{};
        int row = 0;
        for (int k = 0; k < 4; ++k)
          if (k != corner + 1) {
            g[row] = f.gradient[k];
            o[row++] = f.offset[k];
          }
        V3 v{};
        node.has_box = meet(g, o, v);
        for (int a = 0; a < 3; ++a) {
          node.box.lo[a] = corner == 0 ? v[a] : std::min(node.box.lo[a], v[a]);
          node.box.hi[a] = corner == 0 ? v[a] : std::max(node.box.hi[a], v[a]);
        }
      }
      op_of_step[i] = program_.size();
      program_.push_back({static_cast<std::int32_t>(faces_.size()), 0.0f});
      faces_.push_back(f);
      node_at_root[i] = static_cast<int>(nodes.size());
      nodes.push_back(node);
      write(s.out, i, node_at_root[i]);
      continue;
    }
    for (int k = 0; k < s.read_count; ++k) read(s.reads[static_cast<std::size_t>(k)], i);
    int made = -1;
    if (s.kind == Step::Kind::Glue) {
      const int a = node_in(s.reads[0]), b = node_in(s.reads[1]);
      if (a >= 0 && b >= 0 && a != b) {
        const Candidate &na = nodes[static_cast<std::size_t>(a)], &nb = nodes[static_cast<std::size_t>(b)];
        const Candidate& left = na.first < nb.first ? na : nb;
        const Candidate& right = na.first < nb.first ? nb : na;
        if (left.last + 1 == right.first && right.last + 1 == i && left.parent < 0 && right.parent < 0) {
          Candidate node{left.first, i, s.out, {}, left.has_box && right.has_box};
          for (int k = 0; k < 3; ++k) {
            node.box.lo[k] = std::min(left.box.lo[k], right.box.lo[k]);
            node.box.hi[k] = std::max(left.box.hi[k], right.box.hi[k]);
          }
          made = static_cast<int>(nodes.size());
          nodes[static_cast<std::size_t>(a)].parent = made;
          nodes[static_cast<std::size_t>(b)].parent = made;
          nodes.push_back(node);
          node_at_root[i] = made;
          op_of_step[i] = program_.size();
          program_.push_back({-1, static_cast<float>(s.sign)});
        }
      }
    }
    write(s.out, i, made);
  }
  for (std::uint32_t r : results) read(r, steps.size());

  for (const Candidate& n : nodes) {
    if (!n.valid || !n.has_box) continue;
    Cluster c;
    c.first = n.first;
    c.last = n.last;
    c.out = n.out;
    c.box = n.box;
    c.size = diagonal(n.box);
    c.ops = op_of_step[n.first];
    c.op_count = op_of_step[n.last] - c.ops + 1;
    clusters_.push_back(c);
  }
  // Chains from the largest cluster at a first step down to the smallest.
  std::vector<int> order(clusters_.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int i, int j) {
    const Cluster &a = clusters_[static_cast<std::size_t>(i)], &b = clusters_[static_cast<std::size_t>(j)];
    return a.first != b.first ? a.first < b.first : a.last > b.last;
  });
  for (std::size_t k = 0; k < order.size(); ++k) {
    Cluster& c = clusters_[static_cast<std::size_t>(order[k])];
    if (k == 0 || clusters_[static_cast<std::size_t>(order[k - 1])].first != c.first) largest_at_[c.first] = order[k];
    if (k + 1 < order.size() && clusters_[static_cast<std::size_t>(order[k + 1])].first == c.first)
      c.smaller = order[k + 1];
  }
}

int FarFaces::far_cluster_at(std::size_t step, const Box3& box) const {
  if (step >= largest_at_.size() || largest_at_[step] < 0) return -1;  // most steps: no square root
  const double box_size = diagonal(box);
  for (int c = largest_at_[step]; c >= 0; c = clusters_[static_cast<std::size_t>(c)].smaller) {
    const Cluster& cluster = clusters_[static_cast<std::size_t>(c)];
    if (distance(cluster.box, box) >= std::max(cluster.size, box_size)) return c;
  }
  return -1;
}

bool FarFaces::evaluate(int cluster, const std::array<double, 3>& centre, const double* x, const double* y,
                        const double* z, std::size_t count, double* value,
                        const std::array<double*, 3>* gradient) const {
  if (count > kMaxLanes) return false;
  const Cluster& c = clusters_[static_cast<std::size_t>(cluster)];
  thread_local std::vector<Slot> stack;
  thread_local FaceStages stages;
  alignas(64) float qx[kLanes], qy[kLanes], qz[kLanes];
  for (std::size_t l = 0; l < count; ++l) {
    qx[l] = static_cast<float>(x[l] - centre[0]);
    qy[l] = static_cast<float>(y[l] - centre[1]);
    qz[l] = static_cast<float>(z[l] - centre[2]);
  }
  std::size_t top = 0;
  for (std::size_t k = c.ops; k < c.ops + c.op_count; ++k) {
    const Op& op = program_[k];
    if (op.face >= 0) {
      const FloatFace& f = faces_[static_cast<std::size_t>(op.face)];
      // The planes' values at the centre, in doubles (the lanes' offsets
      // from it are small: their rounding stays small against the distance).
      std::array<float, 4> at_centre{};
      for (std::size_t j = 0; j < 4; ++j)
        at_centre[j] = static_cast<float>(f.offset[j] + f.gradient[j][0] * centre[0] + f.gradient[j][1] * centre[1] +
                                          f.gradient[j][2] * centre[2]);
      if (stack.size() <= top) stack.resize(top + 1);
      if (gradient)
        face_lanes<true>(f.single, at_centre, f.constants, qx, qy, qz, count, stages, stack[top]);
      else
        face_lanes<false>(f.single, at_centre, f.constants, qx, qy, qz, count, stages, stack[top]);
      ++top;
    } else {
      if (gradient)
        glue_lanes<true>(stack[top - 2], stack[top - 1], op.sign, count);
      else
        glue_lanes<false>(stack[top - 2], stack[top - 1], op.sign, count);
      --top;
    }
  }
  const Slot& result = stack[0];
  if (!(gradient ? all_finite<true>(result, count) : all_finite<false>(result, count))) return false;
  for (std::size_t l = 0; l < count; ++l) value[l] = result.c[0][l];
  if (gradient)
    for (int k = 0; k < 3; ++k)
      for (std::size_t l = 0; l < count; ++l) (*gradient)[static_cast<std::size_t>(k)][l] = result.c[1 + k][l];
  return true;
}

}  // namespace sage
