// Fused mesh faces (trimmed_face.hpp). Compiled without errno and trapping
// math, as tuple_op_lanes.cpp, and for AVX2 and AVX-512 too
// (vector_clones.hpp: no fused multiply-adds, so the same bits). The
// arithmetic of every piece is lane_steps.hpp's.

#include <sage/tape/trimmed_face.hpp>

#include <sage/scalars/rfunction.hpp>

#include "../scalars/lane_steps.hpp"
#include "../scalars/vector_clones.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

namespace sage {

namespace {

constexpr std::size_t kNone = static_cast<std::size_t>(-1);
using Kind = FacePlane::Kind;

// A plane's value from its arguments' values, for a kind known at compile
// time: tuples through the instructions' tuple arithmetic (a product by a
// constant is 0.0 + a0 p, a negation a * -1.0), doubles through
// scalar.hpp's.
template <Kind K, bool Tuples>
[[gnu::always_inline]] inline double plane_value(const LinearForm& f, double a0, double b0, double c0) {
  if constexpr (K == Kind::ThreeTerms) return lane::linear_form_value<Tuples>(f, a0, b0, c0);
  double value = a0;
  if constexpr (K == Kind::Negated) value = a0 * -1.0;
  if constexpr (K == Kind::Scaled) value = Tuples ? 0.0 + a0 * f.p : a0 * f.p;
  if constexpr (K == Kind::TwoTerms) value = a0 * f.p + b0 * f.q;
  return f.has_offset ? value + f.d : value;
}

// f(std::integral_constant<Kind, plane.kind>{}): the kind chosen once.
template <class F>
[[gnu::always_inline]] inline decltype(auto) visit_kind(Kind kind, F&& f) {
  switch (kind) {
    case Kind::Variable: return f(std::integral_constant<Kind, Kind::Variable>{});
    case Kind::Negated: return f(std::integral_constant<Kind, Kind::Negated>{});
    case Kind::Scaled: return f(std::integral_constant<Kind, Kind::Scaled>{});
    case Kind::TwoTerms: return f(std::integral_constant<Kind, Kind::TwoTerms>{});
    case Kind::ThreeTerms: break;
  }
  return f(std::integral_constant<Kind, Kind::ThreeTerms>{});
}

// A partial of the plane, from its arguments' values (a0 and c0) and
// partials j.
double plane_partial(const FacePlane& plane, double a0, double c0, double aj, double bj, double cj) {
  const LinearForm& f = plane.form;
  double partial = aj;
  switch (plane.kind) {
    case Kind::Variable: break;
    case Kind::Negated: partial = aj * -1.0; break;
    case Kind::Scaled: partial = (0.0 + a0 * 0.0) + aj * f.p; break;
    case Kind::TwoTerms: partial = aj * f.p + bj * f.q; break;
    case Kind::ThreeTerms: return lane::linear_form_partial(f, c0, aj, bj, cj);
  }
  return f.has_offset ? partial + 0.0 : partial;
}

// The plane computed by the instructions from `first`, if they are one:
// a linear form, or an Axpby, Scale or Negation of variables, or a
// variable, then maybe an Offset. Its arguments must be the variables
// (registers no instruction writes, read as inputs). `length` is how many
// instructions it takes.
struct PlaneRun {
  FacePlane plane;
  std::size_t length = 0;
};
std::optional<PlaneRun> find_plane(const Tape& tape, std::size_t first, const std::vector<char>& is_constant,
                                   const std::vector<double>& constant_value) {
  const std::vector<Instruction>& code = tape.code();
  const auto& producers = tape.producers();
  const auto& readers = tape.readers();
  auto variable = [&](std::uint32_t r, std::uint32_t producer) {
    return producer == Tape::kInput && r < static_cast<std::uint32_t>(tape.dimension()) && !is_constant[r];
  };
  PlaneRun run;
  FacePlane& plane = run.plane;
  if (auto form = find_linear_form(tape, first, is_constant, constant_value)) {
    const std::size_t product = first + 1;
    const std::uint32_t c_producer = producers[product][code[product].a == form->c ? 0 : 1];
    if (!variable(form->a, producers[first][0]) || !variable(form->b, producers[first][1]) ||
        !variable(form->c, c_producer))
      return std::nullopt;
    plane.kind = Kind::ThreeTerms;
    plane.form = form->form;
    plane.variables = {static_cast<int>(form->a), static_cast<int>(form->b), static_cast<int>(form->c)};
    run.length = form->length;
  } else {
    const Instruction& ins = code[first];
    if (!variable(ins.a, producers[first][0])) return std::nullopt;
    plane.variables = {static_cast<int>(ins.a), static_cast<int>(ins.a), static_cast<int>(ins.a)};
    run.length = 1;
    switch (ins.op) {
      case Op::Offset:  // a + d: nothing more
        plane.kind = Kind::Variable;
        plane.form.has_offset = true;
        plane.form.d = ins.p0;
        break;
      case Op::Neg: plane.kind = Kind::Negated; break;
      case Op::Scale:
        plane.kind = Kind::Scaled;
        plane.form.p = ins.p0;
        break;
      case Op::Axpby:
        if (!variable(ins.b, producers[first][1])) return std::nullopt;
        plane.kind = Kind::TwoTerms;
        plane.variables[1] = static_cast<int>(ins.b);
        plane.form.p = ins.p0;
        plane.form.q = ins.p1;
        break;
      default: return std::nullopt;
    }
    const std::size_t next = first + 1;
    if (ins.op != Op::Offset && next < code.size() && code[next].op == Op::Offset && producers[next][0] == first &&
        readers[first] == 1) {
      plane.form.has_offset = true;
      plane.form.d = code[next].p0;
      ++run.length;
    }
  }
  return run;
}

// The variable `r` itself as a plane (a face in the plane x = 0, say).
FacePlane variable_plane(std::uint32_t r) {
  FacePlane plane;
  plane.kind = Kind::Variable;
  plane.variables = {static_cast<int>(r), static_cast<int>(r), static_cast<int>(r)};
  return plane;
}

}  // namespace

std::optional<TrimmedFaceRun> find_trimmed_face(const Tape& tape, std::size_t first,
                                                const std::vector<char>& is_constant,
                                                const std::vector<double>& constant_value) {
  if (tape.dimension() != 3) return std::nullopt;
  const std::vector<Instruction>& code = tape.code();
  const auto& producers = tape.producers();
  const auto& readers = tape.readers();
  const std::size_t n = code.size();

  // The pieces, in the order the tape has them, up to the trimming.
  struct Found {
    FacePlane plane;
    std::size_t last;  // the instruction computing it
  };
  std::array<Found, 4> planes{};
  int plane_count = 0, r0_count = 0;
  std::size_t square = kNone;
  std::array<std::size_t, 2> r0{kNone, kNone};
  std::optional<SmoothTrimRun> trim;
  std::size_t trim_first = kNone;
  // A square or an R0 of the run reads only what the run computes (or the
  // variables): an R0 gluing earlier faces is no start, and is not parsed
  // on into the face after it.
  auto reads_inside = [&](std::size_t i) {
    for (std::uint32_t p : producers[i])
      if (p != Tape::kInput && p < first) return false;
    return true;
  };
  for (std::size_t i = first; i < n;) {
    if ((trim = find_smooth_trim(tape, i))) {
      trim_first = i;
      break;
    }
    const Instruction& ins = code[i];
    if (ins.op == Op::Square && square == kNone && reads_inside(i)) {
      square = i++;
    } else if ((ins.op == Op::RAnd || ins.op == Op::ROr) && r0_count < 2 &&
               static_cast<RKind>(static_cast<int>(ins.p0)) == RKind::R0 && reads_inside(i)) {
      r0[static_cast<std::size_t>(r0_count++)] = i++;
    } else if (auto plane = plane_count < 4 ? find_plane(tape, i, is_constant, constant_value) : std::nullopt) {
      planes[static_cast<std::size_t>(plane_count++)] = {plane->plane, i + plane->length - 1};
      i += plane->length;
    } else {
      return std::nullopt;
    }
  }
  if (!trim || square == kNone || r0_count != 2) return std::nullopt;

  // The data flow: S = h^2, U = R0(s, s'), T = R0(U, s'') (either order),
  // W = trim(T, h, S), each intermediate read by the run alone. A plane
  // is one of the pieces, or a variable read as it is.
  std::array<FacePlane, 4> chosen{};
  std::array<int, 4> piece{-1, -1, -1, -1};
  auto plane_of = [&](std::size_t slot, std::size_t reader, int argument) {
    const std::uint32_t producer = producers[reader][static_cast<std::size_t>(argument)];
    const std::uint32_t r = argument == 0 ? code[reader].a : code[reader].b;
    if (producer == Tape::kInput) {
      if (r >= static_cast<std::uint32_t>(tape.dimension()) || is_constant[r]) return false;
      chosen[slot] = variable_plane(r);
      return true;
    }
    for (int k = 0; k < plane_count; ++k)
      if (planes[static_cast<std::size_t>(k)].last == producer) {
        chosen[slot] = planes[static_cast<std::size_t>(k)].plane;
        piece[slot] = k;
        return true;
      }
    return false;
  };
  const bool trimming_first = producers[r0[1]][0] == r0[0];
  if (!trimming_first && producers[r0[1]][1] != r0[0]) return std::nullopt;
  if (!plane_of(0, square, 0) || !plane_of(1, r0[0], 0) || !plane_of(2, r0[0], 1) ||
      !plane_of(3, r0[1], trimming_first ? 1 : 0))
    return std::nullopt;
  // Every piece used once (h by its square and the trimming), none left over.
  std::array<int, 4> uses{};
  for (int k : piece)
    if (k >= 0) ++uses[static_cast<std::size_t>(k)];
  for (int k = 0; k < plane_count; ++k) {
    const auto reads = static_cast<std::uint32_t>(k == piece[0] ? 2 : 1);
    if (uses[static_cast<std::size_t>(k)] != 1 || readers[planes[static_cast<std::size_t>(k)].last] != reads)
      return std::nullopt;
  }
  const std::size_t reads_h = trim_first + 1;               // its Scale or fourth power
  const std::size_t total = trim_first + trim->length - 2;  // S + the mix squared
  if (producers[trim_first][0] != r0[1] || producers[reads_h][0] != producers[square][0] ||
      code[reads_h].a != code[square].a || (producers[total][0] != square && producers[total][1] != square))
    return std::nullopt;
  if (readers[square] != 1 || readers[r0[0]] != 1 || readers[r0[1]] != 2) return std::nullopt;

  TrimmedFaceRun run;
  TrimmedFace& face = run.face;
  face.planes = chosen;
  // The seeds' partials (1 for the variable itself, else 0) through each
  // plane's arithmetic, at a finite point (where 0.0 + a0 0.0 is 0.0).
  for (FacePlane& plane : face.planes)
    for (int j = 0; j < 3; ++j) {
      auto seed = [&](std::size_t argument) { return plane.variables[argument] == j ? 1.0 : 0.0; };
      plane.partials[static_cast<std::size_t>(j)] = plane_partial(plane, 0.0, 0.0, seed(0), seed(1), seed(2));
    }
  face.first_sign = code[r0[0]].op == Op::RAnd ? -1.0 : 1.0;
  face.second_sign = code[r0[1]].op == Op::RAnd ? -1.0 : 1.0;
  face.trimming_first = trimming_first;
  face.trim = trim->trim;
  run.out = trim->out;
  run.length = trim_first + trim->length - first;
  return run;
}

namespace {

constexpr std::size_t kChunk = 64;
using Lanes3 = ConstFirstOrderLanes<3>;

// The face through the operators, for the lanes where one of them takes
// another branch, or a coordinate is not finite: the planes' partials from
// the seeded variables, as their instructions compute them.
Tuple<3, 1> face_operators(const TrimmedFace& face, const std::array<Tuple<3, 1>, 3>& variables) {
  std::array<Tuple<3, 1>, 4> plane;
  for (std::size_t k = 0; k < 4; ++k) {
    const FacePlane& p = face.planes[k];
    const Tuple<3, 1>& a = variables[static_cast<std::size_t>(p.variables[0])];
    const Tuple<3, 1>& b = variables[static_cast<std::size_t>(p.variables[1])];
    const Tuple<3, 1>& c = variables[static_cast<std::size_t>(p.variables[2])];
    plane[k].c[0] =
        visit_kind(p.kind, [&](auto kind) { return plane_value<kind(), true>(p.form, a.c[0], b.c[0], c.c[0]); });
    for (int j = 1; j <= 3; ++j) plane[k].c[j] = plane_partial(p, a.c[0], c.c[0], a.c[j], b.c[j], c.c[j]);
  }
  const Tuple<3, 1> s = square(plane[0]);
  const Tuple<3, 1> u = r0_combine(plane[1], plane[2], face.first_sign);
  const Tuple<3, 1> t =
      face.trimming_first ? r0_combine(u, plane[3], face.second_sign) : r0_combine(plane[3], u, face.second_sign);
  return lane::smooth_trim_operators(face.trim, t, plane[0], s);
}

// values[l] = the plane's value at lanes [start, start + n), the kind
// chosen once per chunk.
template <bool Tuples>
[[gnu::always_inline]] inline void plane_values(const FacePlane& plane, const std::array<const double*, 3>& coordinates,
                                                std::size_t start, std::size_t n, double* values) {
  const double* a = coordinates[static_cast<std::size_t>(plane.variables[0])] + start;
  const double* b = coordinates[static_cast<std::size_t>(plane.variables[1])] + start;
  const double* c = coordinates[static_cast<std::size_t>(plane.variables[2])] + start;
  const LinearForm f = plane.form;
  visit_kind(plane.kind, [&](auto kind) {
    for (std::size_t l = 0; l < n; ++l) values[l] = plane_value<kind(), Tuples>(f, a[l], b[l], c[l]);
  });
}

// The face at one lane from its planes' values, on the regular branches:
// false where the operators must compute it. On their regular branches
// R0's value and partials are symmetric in its arguments, bit for bit
// (sums and products commute), so the second R0's order does not matter
// here; the operators follow it.
template <bool Scale>
[[gnu::always_inline]] inline bool regular_face(const TrimmedFace& face, const double* values, double* w) {
  double plane[4][4];
  for (std::size_t k = 0; k < 4; ++k) {
    plane[k][0] = values[k];
    for (std::size_t j = 0; j < 3; ++j) plane[k][j + 1] = face.planes[k].partials[j];
  }
  double s[4], u[4], t[4];
  lane::square<3>(plane[0], s);
  const bool regular_u = lane::r0<3>(plane[1], plane[2], face.first_sign, u);
  const bool regular_t = lane::r0<3>(u, plane[3], face.second_sign, t);
  const bool regular_w = lane::smooth_trim<3, Scale>(face.trim, t, plane[0], s, w);
  return regular_u & regular_t & regular_w;
}

template <bool Scale>
[[gnu::always_inline]] inline void face_tuples(const TrimmedFace& face_in, Lanes3 x, Lanes3 y, Lanes3 z,
                                               FirstOrderLanes<3> out, std::size_t count) {
  const TrimmedFace face = face_in;  // copied: stores to `out` cannot change it
  const std::array<const double*, 3> coordinates{x.component(0), y.component(0), z.component(0)};
  double* o[4] = {out.component(0), out.component(1), out.component(2), out.component(3)};
  constexpr double kLargest = std::numeric_limits<double>::max();
  auto finite = [&](std::size_t i) {
    return (std::abs(coordinates[0][i]) <= kLargest) & (std::abs(coordinates[1][i]) <= kLargest) &
           (std::abs(coordinates[2][i]) <= kLargest);
  };
  double values[4][kChunk];
  for (std::size_t start = 0; start < count; start += kChunk) {
    const std::size_t n = std::min(kChunk, count - start);
    for (std::size_t k = 0; k < 4; ++k) plane_values<true>(face.planes[k], coordinates, start, n, values[k]);
    // Only whether any lane is singular: a flag per lane, stored from the
    // vector loop, made the kernel 1.6 times slower.
    std::size_t any_singular = 0;
#pragma GCC ivdep
    for (std::size_t l = 0; l < n; ++l) {
      const std::size_t i = start + l;
      const double lane_values[4] = {values[0][l], values[1][l], values[2][l], values[3][l]};
      double w[4];
      const bool regular = regular_face<Scale>(face, lane_values, w);
      for (int k = 0; k < 4; ++k) o[k][i] = w[k];
      any_singular |= static_cast<std::size_t>(!(regular & finite(i)));
    }
    if (any_singular == 0) continue;
    for (std::size_t l = 0; l < n; ++l) {  // rare: find the lanes again
      const std::size_t i = start + l;
      const double lane_values[4] = {values[0][l], values[1][l], values[2][l], values[3][l]};
      double w[4];
      if (!(regular_face<Scale>(face, lane_values, w) & finite(i)))
        out.store(i, face_operators(face, {x.load(i), y.load(i), z.load(i)}));
    }
  }
}

template <bool Scale>
[[gnu::always_inline]] inline void face_values(const TrimmedFace& face_in, const double* x, const double* y,
                                               const double* z, double* out, std::size_t count) {
  const TrimmedFace face = face_in;
  const std::array<const double*, 3> coordinates{x, y, z};
  double values[4][kChunk];
  for (std::size_t start = 0; start < count; start += kChunk) {
    const std::size_t n = std::min(kChunk, count - start);
    for (std::size_t k = 0; k < 4; ++k) plane_values<false>(face.planes[k], coordinates, start, n, values[k]);
#pragma GCC ivdep
    for (std::size_t l = 0; l < n; ++l) {
      const double h = values[0][l];
      const double u = lane::r0(values[1][l], values[2][l], face.first_sign);
      const double t = lane::r0(u, values[3][l], face.second_sign);
      out[start + l] = lane::smooth_trim<Scale>(face.trim, t, h, h * h);
    }
  }
}

}  // namespace

SAGE_VECTOR_CLONES void trimmed_face_lanes(const TrimmedFace& face, ConstFirstOrderLanes<3> x,
                                           ConstFirstOrderLanes<3> y, ConstFirstOrderLanes<3> z, FirstOrderLanes<3> out,
                                           std::size_t count) {
  if (face.trim.has_scale)
    face_tuples<true>(face, x, y, z, out, count);
  else
    face_tuples<false>(face, x, y, z, out, count);
}
SAGE_VECTOR_CLONES void trimmed_face_values(const TrimmedFace& face, const double* x, const double* y, const double* z,
                                            double* out, std::size_t count) {
  if (face.trim.has_scale)
    face_values<true>(face, x, y, z, out, count);
  else
    face_values<false>(face, x, y, z, out, count);
}

}  // namespace sage
