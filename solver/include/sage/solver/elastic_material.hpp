#pragma once
// An isotropic linear elastic material (Young's modulus E, Poisson's ratio
// nu) and what the elasticity solver needs of it:
//
//     sigma = 2 mu eps + lambda tr(eps) I,
//     mu = E / (2 (1 + nu)),  lambda = E nu / ((1 + nu) (1 - 2 nu)).
//
// In 2D, plane strain (eps_zz = 0: the same lambda, sigma_zz = lambda tr eps)
// or plane stress (sigma_zz = 0: lambda* = 2 lambda mu / (lambda + 2 mu)).
//
// Voigt notation with engineering shear strains: eps_v = (eps_xx, eps_yy,
// gamma_xy) in 2D, (eps_xx, eps_yy, eps_zz, gamma_yz, gamma_xz, gamma_xy)
// in 3D, gamma_ab = 2 eps_ab; sigma_v = C eps_v in the same order, and the
// energy density is eps_v . C eps_v / 2.

#include <sage/solver/data_error.hpp>

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sage::solver {

enum class PlaneMode { Strain, Stress };

/// Parses "strain" or "stress"; throws std::invalid_argument.
inline PlaneMode parse_plane_mode(const std::string& text) {
  if (text == "strain") return PlaneMode::Strain;
  if (text == "stress") return PlaneMode::Stress;
  throw std::invalid_argument("expected \"strain\" or \"stress\", not \"" + text + "\"");
}

/// Components of a symmetric tensor in Voigt order: 3 in 2D, 6 in 3D.
constexpr int voigt_size(int dimension) { return dimension * (dimension + 1) / 2; }

/// The axes (a, b) of Voigt component v (normal components first).
constexpr std::array<int, 2> voigt_axes(int dimension, int v) {
  if (v < dimension) return {v, v};
  if (dimension == 2) return {0, 1};
  return v == 3 ? std::array<int, 2>{1, 2} : v == 4 ? std::array<int, 2>{0, 2} : std::array<int, 2>{0, 1};
}

struct ElasticMaterial {
  double young = 1.0;
  double poisson = 0.3;
  PlaneMode plane = PlaneMode::Strain;  // 2D only

  /// Throws std::invalid_argument unless E > 0 (within kSmallestModulus
  /// and kLargestDatum, where the stiffness neither under- nor overflows)
  /// and -1 < nu < 1/2.
  void check() const {
    if (!(young >= kSmallestModulus && young <= kLargestDatum))
      throw std::invalid_argument(young > 0.0 ? "Young's modulus E must lie within 1e-100 and 1e100 (change the units)"
                                              : "Young's modulus E must be positive");
    if (!(poisson > -1.0 && poisson < 0.5))
      throw std::invalid_argument("Poisson's ratio nu must lie in (-1, 0.5), not " + std::to_string(poisson));
  }
  double mu() const { return young / (2.0 * (1.0 + poisson)); }
  /// lambda of the 3D material (plane strain too).
  double lambda3() const { return young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson)); }
  /// The lambda of the equations in `dimension` (plane stress: lambda*).
  double lambda(int dimension) const {
    const double l = lambda3(), m = mu();
    return dimension == 2 && plane == PlaneMode::Stress ? 2.0 * l * m / (l + 2.0 * m) : l;
  }
  /// 2 mu + lambda: the largest stress per strain on a direction, which
  /// scales Nitsche's penalty.
  double stiffness_scale(int dimension) const { return 2.0 * mu() + lambda(dimension); }

  /// C in Voigt notation (voigt_size x voigt_size).
  Eigen::MatrixXd voigt(int dimension) const {
    const int size = voigt_size(dimension);
    const double l = lambda(dimension), m = mu();
    Eigen::MatrixXd c = Eigen::MatrixXd::Zero(size, size);
    for (int a = 0; a < dimension; ++a) {
      for (int b = 0; b < dimension; ++b) c(a, b) = l;
      c(a, a) = l + 2.0 * m;
    }
    for (int v = dimension; v < size; ++v) c(v, v) = m;
    return c;
  }

  /// The stress tensor in VTK's symmetric layout (xx, yy, zz, xy, yz, xz)
  /// from the displacement gradient g (g[a * D + b] = d u_a / d x_b); in
  /// 2D, sigma_zz is lambda tr(eps) for plane strain and 0 for plane stress.
  template <int D>
  std::array<double, 6> stress(const double* g) const {
    const double m = mu(), l = lambda(D);
    double trace = 0.0;
    for (int a = 0; a < D; ++a) trace += g[a * D + a];
    std::array<double, 6> s{};
    for (int a = 0; a < D; ++a) s[static_cast<std::size_t>(a)] = 2.0 * m * g[a * D + a] + l * trace;
    s[3] = m * (g[1] + g[D]);  // xy
    if constexpr (D == 3) {
      s[4] = m * (g[5] + g[7]);  // yz
      s[5] = m * (g[2] + g[6]);  // xz
    } else if (plane == PlaneMode::Strain) {
      s[2] = lambda3() * trace;
    }
    return s;
  }
};

/// The von Mises stress of a stress in VTK's layout.
inline double von_mises(const std::array<double, 6>& s) {
  const double dxy = s[0] - s[1], dyz = s[1] - s[2], dzx = s[2] - s[0];
  return std::sqrt(0.5 * (dxy * dxy + dyz * dyz + dzx * dzx) + 3.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]));
}

}  // namespace sage::solver
