#include "schwarz_preconditioner.hpp"

#include "freed_memory.hpp"
#include "threads.hpp"

#include <sage/solver/memory_estimate.hpp>

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <unordered_map>
#include <utility>

namespace sage::solver {

namespace {

/// Levels end when the next would have at most this many unknowns (its
/// sparse Cholesky then costs about one matrix product per iteration), or
/// when coarsening stops paying (fewer than a third of the unknowns go).
constexpr Eigen::Index kCoarsestUnknowns = 2000;
constexpr double kLeastCoarsening = 2.0 / 3.0;
constexpr int kMostLevels = 12;

/// A coarse B-spline is kept when the fine unknowns hold at least this
/// share of its two-scale weights (squared): one fine child alone makes
/// it a copy of that child, and two such copies a singular P^T A P.
constexpr double kCoarseShare = 0.1;

/// Blocks whose entries agree to this relative precision share an inverse.
constexpr double kSharedBlockPrecision = 0x1p-36;

/// The share of the available memory the distinct blocks may take at most.
constexpr double kDistinctBlockMemoryShare = 0.25;

/// Columns of P per piece of the Galerkin product L P.
constexpr Eigen::Index kGalerkinColumns = 256;

/// Blocks applied together in one matrix product.
constexpr int kBlocksPerProduct = 64;

/// The boxes of grid positions the unknowns' indices span, widened by
/// `below` cells, times the components: a dense numbering of the keys
/// (position, component).
struct KeyBox {
  int dimension = 3;
  std::array<int, 3> lo{}, size{1, 1, 1};
  int components = 1;

  KeyBox(const SplinePlacement& placement, int below, int divide) : dimension(placement.dimension) {
    std::array<int, 3> hi{};
    lo.fill(std::numeric_limits<int>::max());
    hi.fill(std::numeric_limits<int>::min());
    components = 1;
    for (std::size_t u = 0; u < placement.index.size(); ++u) {
      if (placement.component[u] < 0) continue;
      components = std::max(components, placement.component[u] + 1);
      for (int a = 0; a < dimension; ++a) {
        lo[a] = std::min(lo[a], floor_divide(placement.index[u][a] - below, divide));
        hi[a] = std::max(hi[a], floor_divide(placement.index[u][a], divide));
      }
    }
    for (int a = 0; a < 3; ++a) {
      if (a >= dimension || lo[a] > hi[a]) {
        lo[a] = 0;
        size[a] = 1;
      } else {
        size[a] = hi[a] - lo[a] + 1;
      }
    }
  }
  static int floor_divide(int x, int d) { return x >= 0 ? x / d : -((-x + d - 1) / d); }
  std::size_t count() const {
    return static_cast<std::size_t>(size[0]) * size[1] * size[2] * static_cast<std::size_t>(components);
  }
  std::size_t key(const std::array<int, 3>& p, int component) const {
    std::size_t k = static_cast<std::size_t>(component);
    for (int a = 2; a >= 0; --a) k = k * static_cast<std::size_t>(size[a]) + static_cast<std::size_t>(p[a] - lo[a]);
    return k;
  }
  std::array<int, 3> position(std::size_t key) const {
    std::array<int, 3> p{};
    for (int a = 0; a < 3; ++a) {
      p[a] = lo[a] + static_cast<int>(key % static_cast<std::size_t>(size[a]));
      key /= static_cast<std::size_t>(size[a]);
    }
    return p;
  }
};

/// Calls visit(offset) for each offset in {0..n}^D (unused axes 0).
template <class Visit>
void for_each_offset(int dimension, int n, Visit&& visit) {
  std::array<int, 3> o{};
  const int span = n + 1;
  int total = 1;
  for (int a = 0; a < dimension; ++a) total *= span;
  for (int k = 0; k < total; ++k) {
    int rest = k;
    for (int a = 0; a < dimension; ++a) {
      o[a] = rest % span;
      rest /= span;
    }
    visit(o);
  }
}

/// The dense block of `lower`'s symmetric matrix on the sorted `members`.
Eigen::MatrixXd dense_block(const Eigen::SparseMatrix<double>& lower, const int* members, int m) {
  Eigen::MatrixXd block = Eigen::MatrixXd::Zero(m, m);
  for (int j = 0; j < m; ++j) {
    int i = j;
    for (Eigen::SparseMatrix<double>::InnerIterator e(lower, members[j]); e && i < m; ++e) {
      while (i < m && members[i] < e.row()) ++i;
      if (i < m && members[i] == e.row()) {
        block(i, j) = e.value();
        block(j, i) = e.value();
      }
    }
  }
  return block;
}

/// 128 bits of a hash, from two 64-bit mixers.
using Hash = std::pair<std::uint64_t, std::uint64_t>;

struct HashMixer {
  std::uint64_t a = 0x9e3779b97f4a7c15ULL, b = 0xc2b2ae3d27d4eb4fULL;
  void add(std::uint64_t q) {
    a = (a ^ q) * 0x100000001b3ULL;
    b = (b + q) * 0xff51afd7ed558ccdULL;
    b ^= b >> 29;
  }
  void add(const Hash& h) {
    add(h.first);
    add(h.second);
  }
  Hash value() const { return {a, b}; }
};

/// Per unknown, a hash of its column of the lower triangle as the unknown
/// sees it: each entry's row as an offset of B-spline indices with its
/// component, and its value rounded to kSharedBlockPrecision of the
/// diagonal. Blocks whose members have equal hashes, in the same places,
/// are equal (their entries are those columns' entries).
std::vector<Hash> column_hashes(const Eigen::SparseMatrix<double>& lower, const SplinePlacement& placement) {
  std::vector<Hash> hashes(static_cast<std::size_t>(lower.cols()));
#pragma omp parallel for schedule(static)
  for (Eigen::Index u = 0; u < lower.cols(); ++u) {
    HashMixer mix;
    const auto& at = placement.index[static_cast<std::size_t>(u)];
    Eigen::SparseMatrix<double>::InnerIterator e(lower, u);
    const double diagonal = e && e.row() == u ? std::abs(e.value()) : 1.0;
    const double per_unit = diagonal > 0.0 ? 1.0 / (diagonal * kSharedBlockPrecision) : 1.0;
    for (; e; ++e) {
      const auto& row = placement.index[static_cast<std::size_t>(e.row())];
      mix.add(static_cast<std::uint64_t>(placement.component[static_cast<std::size_t>(e.row())] + 1));
      for (int k = 0; k < 3; ++k) mix.add(static_cast<std::uint64_t>(row[k] - at[k]));
      // Rounded and clamped into int64's range (an entry may dwarf its column's diagonal).
      const double q = std::nearbyint(e.value() * per_unit);
      mix.add(static_cast<std::uint64_t>(std::isfinite(q) ? static_cast<std::int64_t>(std::clamp(q, -0x1p62, 0x1p62))
                                                          : std::int64_t{0}));
    }
    hashes[static_cast<std::size_t>(u)] = mix.value();
  }
  return hashes;
}

/// A block's hash: its members' places relative to the first, their components and column hashes.
Hash block_hash(const int* members, int m, const SplinePlacement& placement, const std::vector<Hash>& columns) {
  HashMixer mix;
  mix.add(static_cast<std::uint64_t>(m));
  const auto& first = placement.index[static_cast<std::size_t>(members[0])];
  for (int i = 0; i < m; ++i) {
    const auto u = static_cast<std::size_t>(members[i]);
    for (int k = 0; k < 3; ++k) mix.add(static_cast<std::uint64_t>(placement.index[u][k] - first[k]));
    mix.add(static_cast<std::uint64_t>(placement.component[u]));
    mix.add(columns[u]);
  }
  return mix.value();
}

/// G = L^-1 for the Cholesky factor L of an SPD block (block = L L^T), in
/// single precision: the block's inverse is G^T G, which stays positive
/// definite whatever G's rounding (G is triangular with a nonzero
/// diagonal), at half the bytes of a double inverse and a third of its
/// set-up flops. Round-off can leave a block of a nearly dependent set
/// short of definite: a relative shift of the diagonal restores it.
Eigen::MatrixXf inverse_factor(Eigen::MatrixXd block) {
  Eigen::LLT<Eigen::MatrixXd> factor(block);
  for (double shift = 1e-12; factor.info() != Eigen::Success && shift < 1.0; shift *= 100.0) {
    block.diagonal() *= 1.0 + shift;
    factor.compute(block);
  }
  if (factor.info() != Eigen::Success)
    throw std::runtime_error("a block of the Schwarz preconditioner is not positive definite");
  Eigen::MatrixXd inverse = Eigen::MatrixXd::Identity(block.rows(), block.cols());
  factor.matrixL().solveInPlace(inverse);
  return inverse.triangularView<Eigen::Lower>().toDenseMatrix().cast<float>();
}

struct HashOfPair {
  std::size_t operator()(const Hash& p) const { return static_cast<std::size_t>(p.first ^ (p.second * 31)); }
};

/// The (cell, component) pairs of the unknowns' supports, numbered in
/// KeyBox order, with their unknowns (increasing): the blocks before any
/// is dropped.
struct CellMembers {
  std::vector<std::size_t> start;
  std::vector<int> members;
  std::vector<char> even;  // the cell's coordinates are all even
};

CellMembers cell_members(const SplinePlacement& placement) {
  const int d = placement.dimension, n = placement.degree;
  const KeyBox cells(placement, n, 1);
  const auto unknowns = static_cast<int>(placement.index.size());
  // Cell i - o for each offset o holds unknown i: count, then fill.
  auto for_each_cell = [&](int u, auto&& visit) {
    for_each_offset(d, n, [&](const std::array<int, 3>& o) {
      std::array<int, 3> cell = placement.index[u];
      for (int a = 0; a < d; ++a) cell[a] -= o[a];
      visit(cells.key(cell, placement.component[u]));
    });
  };
  std::vector<int> count(cells.count(), 0);
  for (int u = 0; u < unknowns; ++u)
    if (placement.component[u] >= 0) for_each_cell(u, [&](std::size_t key) { ++count[key]; });
  CellMembers blocks;
  std::vector<std::size_t> block_of_key(cells.count(), 0);
  blocks.start.push_back(0);
  for (std::size_t key = 0; key < cells.count(); ++key)
    if (count[key] > 0) {
      block_of_key[key] = blocks.start.size() - 1;
      blocks.start.push_back(blocks.start.back() + static_cast<std::size_t>(count[key]));
      const auto cell = cells.position(key % (cells.count() / static_cast<std::size_t>(cells.components)));
      bool even = true;
      for (int a = 0; a < d; ++a) even = even && (cell[a] % 2 == 0);
      blocks.even.push_back(even ? 1 : 0);
    }
  blocks.members.resize(blocks.start.back());
  std::vector<std::size_t> fill(blocks.start.begin(), blocks.start.end() - 1);
  for (int u = 0; u < unknowns; ++u)
    if (placement.component[u] >= 0)
      for_each_cell(u, [&](std::size_t key) { blocks.members[fill[block_of_key[key]]++] = u; });
  return blocks;
}

SchwarzPreconditioner::Blocks cell_blocks(const Eigen::SparseMatrix<double>& lower, const SplinePlacement& placement) {
  const CellMembers cells = cell_members(placement);
  const std::size_t cell_count = cells.start.size() - 1;
  const auto size_of = [&](std::size_t b) { return static_cast<int>(cells.start[b + 1] - cells.start[b]); };
  // Equal blocks share an inverse: hash them all, number the distinct ones.
  const std::vector<Hash> columns = column_hashes(lower, placement);
  std::vector<Hash> hashes(cell_count);
#pragma omp parallel for schedule(static)
  for (std::size_t b = 0; b < cell_count; ++b)
    hashes[b] = block_hash(cells.members.data() + cells.start[b], size_of(b), placement, columns);
  std::unordered_map<Hash, std::vector<std::size_t>, HashOfPair> cells_of_hash;
  std::vector<Hash> distinct;
  for (std::size_t b = 0; b < cell_count; ++b) {
    auto [it, added] = cells_of_hash.try_emplace(hashes[b]);
    if (added) distinct.push_back(hashes[b]);
    it->second.push_back(b);
  }
  // Keep every distinct block (near the boundary, where the cuts make
  // them differ) and the shared ones on even cells only: inside, blocks
  // two cells apart still overlap, at an eighth of the cost. When the
  // distinct ones would take over a quarter of the memory available
  // (coefficients that vary everywhere make every block distinct), they
  // too are kept on even cells only.
  double distinct_megabytes = 0.0;
  for (const auto& hash : distinct) {
    const std::vector<std::size_t>& same = cells_of_hash[hash];
    if (same.size() == 1) distinct_megabytes += std::pow(size_of(same.front()), 2) * 4.0 / (1024.0 * 1024.0);
  }
  const double available = available_megabytes();
  const bool thin_out = available > 0.0 && distinct_megabytes > kDistinctBlockMemoryShare * available;
  SchwarzPreconditioner::Blocks blocks;
  blocks.start.push_back(0);
  std::vector<std::size_t> representative;
  for (const auto& hash : distinct) {
    const std::vector<std::size_t>& same = cells_of_hash[hash];
    std::vector<int> users;
    for (const std::size_t b : same) {
      if ((same.size() > 1 || thin_out) && !cells.even[b]) continue;
      users.push_back(static_cast<int>(blocks.start.size() - 1));
      blocks.members.insert(blocks.members.end(), cells.members.begin() + static_cast<std::ptrdiff_t>(cells.start[b]),
                            cells.members.begin() + static_cast<std::ptrdiff_t>(cells.start[b + 1]));
      blocks.start.push_back(blocks.members.size());
    }
    if (users.empty()) continue;
    representative.push_back(same.front());
    blocks.users.push_back(std::move(users));
  }
  // Each unknown's share: 1 / sqrt(the blocks it lies in), on both sides.
  blocks.share = Eigen::VectorXd::Zero(lower.rows());
  for (const int u : blocks.members) blocks.share[u] += 1.0;
  for (Eigen::Index u = 0; u < blocks.share.size(); ++u)
    blocks.share[u] = blocks.share[u] > 0.0 ? 1.0 / std::sqrt(blocks.share[u]) : 0.0;
  for (std::size_t f = 0; f < blocks.users.size(); ++f)
    for (std::size_t k = 0; k < blocks.users[f].size(); k += kBlocksPerProduct)
      blocks.batches.push_back({static_cast<int>(f), k, std::min(blocks.users[f].size(), k + kBlocksPerProduct)});
  // Inverses of one block each are packed, the shared ones kept whole.
  const std::size_t inverses = representative.size();
  blocks.order.resize(inverses);
  blocks.factors.resize(inverses);
  blocks.packed_at.assign(inverses, 0);
  std::size_t packed = 0;
  for (std::size_t f = 0; f < inverses; ++f) {
    const int m = size_of(representative[f]);
    blocks.order[f] = m;
    if (blocks.users[f].size() > 1) continue;
    blocks.packed_at[f] = packed;
    packed += static_cast<std::size_t>(m) * static_cast<std::size_t>(m + 1) / 2;
  }
  blocks.packed.resize(packed);
#pragma omp parallel for schedule(dynamic, 16)
  for (std::size_t f = 0; f < inverses; ++f) {
    const std::size_t b = representative[f];
    Eigen::MatrixXf factor = inverse_factor(dense_block(lower, cells.members.data() + cells.start[b], size_of(b)));
    if (blocks.users[f].size() > 1) {
      blocks.factors[f] = std::move(factor);
      continue;
    }
    float* column = blocks.packed.data() + blocks.packed_at[f];
    for (Eigen::Index j = 0; j < factor.cols(); ++j) {
      std::copy(factor.col(j).data() + j, factor.col(j).data() + factor.rows(), column);
      column += factor.rows() - j;
    }
  }
  for (int u = 0; u < static_cast<int>(placement.component.size()); ++u)
    if (placement.component[u] < 0) blocks.lone.push_back(u);
  blocks.lone_inverse.resize(static_cast<Eigen::Index>(blocks.lone.size()));
  for (std::size_t k = 0; k < blocks.lone.size(); ++k) {
    const double diagonal = lower.coeff(blocks.lone[k], blocks.lone[k]);
    blocks.lone_inverse[static_cast<Eigen::Index>(k)] = diagonal > 0.0 ? 1.0 / diagonal : 0.0;
  }
  return blocks;
}

/// x = G^T G x for a lower triangular G packed column by column; `work`: m floats.
void apply_packed_inverse(const float* g, Eigen::Index m, float* x, float* work) {
  using Column = Eigen::Map<const Eigen::VectorXf>;
  using Segment = Eigen::Map<Eigen::VectorXf>;
  Segment y(work, m);
  y.setZero();
  const float* column = g;
  for (Eigen::Index j = 0; j < m; ++j) {  // y = G x
    Segment(work + j, m - j) += x[j] * Column(column, m - j);
    column += m - j;
  }
  column = g;
  for (Eigen::Index j = 0; j < m; ++j) {  // x = G^T y
    x[j] = Column(column, m - j).dot(Column(work + j, m - j));
    column += m - j;
  }
}

/// result += S r = W sum over blocks of R_b^T A_b^-1 R_b W r, W the
/// shares, on all cores; blocks that share an inverse go kBlocksPerProduct
/// at a time through one matrix product.
void add_blocks(const SchwarzPreconditioner::Blocks& blocks, const Eigen::VectorXd& unscaled_r,
                Eigen::VectorXd& result) {
  const Eigen::VectorXd r = blocks.share.cwiseProduct(unscaled_r);
  Eigen::VectorXd z = Eigen::VectorXd::Zero(r.size());
  const std::vector<SchwarzPreconditioner::Blocks::Batch>& items = blocks.batches;
  const int threads = thread_count();
  std::vector<Eigen::VectorXd> partial(static_cast<std::size_t>(threads - 1));
#pragma omp parallel
  {
    const int thread = thread_number();
    Eigen::VectorXd* own = &z;
    if (thread > 0) {
      partial[static_cast<std::size_t>(thread - 1)] = Eigen::VectorXd::Zero(z.size());
      own = &partial[static_cast<std::size_t>(thread - 1)];
    }
    Eigen::MatrixXf gathered, product;
    Eigen::VectorXf vector;
#pragma omp for schedule(static)
    for (std::size_t w = 0; w < items.size(); ++w) {
      const SchwarzPreconditioner::Blocks::Batch& item = items[w];
      const auto f = static_cast<std::size_t>(item.inverse);
      const Eigen::MatrixXf& factor = blocks.factors[f];
      const std::vector<int>& users = blocks.users[f];
      const Eigen::Index m = blocks.order[f];
      const auto k = static_cast<Eigen::Index>(item.last - item.first);
      gathered.resize(m, k);
      for (Eigen::Index c = 0; c < k; ++c) {
        const int* members = blocks.members.data() + blocks.start[static_cast<std::size_t>(users[item.first + c])];
        for (Eigen::Index i = 0; i < m; ++i) gathered(i, c) = static_cast<float>(r[members[i]]);
      }
      if (factor.size() == 0) {
        vector.resize(m);
        apply_packed_inverse(blocks.packed.data() + blocks.packed_at[f], m, gathered.data(), vector.data());
      } else if (k == 1) {  // a shared inverse's last user alone: matrix-vector products
        vector.noalias() = factor.triangularView<Eigen::Lower>() * gathered.col(0);
        gathered.col(0).noalias() = factor.transpose().triangularView<Eigen::Upper>() * vector;
      } else {
        product.noalias() = factor.triangularView<Eigen::Lower>() * gathered;
        gathered.noalias() = factor.transpose().triangularView<Eigen::Upper>() * product;
      }
      for (Eigen::Index c = 0; c < k; ++c) {
        const int* members = blocks.members.data() + blocks.start[static_cast<std::size_t>(users[item.first + c])];
        for (Eigen::Index i = 0; i < m; ++i) (*own)[members[i]] += gathered(i, c);
      }
    }
  }
  for (const Eigen::VectorXd& p : partial) z += p;
  result += blocks.share.cwiseProduct(z);
  for (std::size_t k = 0; k < blocks.lone.size(); ++k)
    result[blocks.lone[k]] += blocks.lone_inverse[static_cast<Eigen::Index>(k)] * unscaled_r[blocks.lone[k]];
}

/// binom(n + 1, l) / 2^n: the two-scale weights of a degree-n B-spline.
std::vector<double> two_scale_weights(int n) {
  std::vector<double> w(static_cast<std::size_t>(n + 2));
  double binomial = 1.0;
  for (int l = 0; l <= n + 1; ++l) {
    w[static_cast<std::size_t>(l)] = binomial / std::ldexp(1.0, n);
    binomial = binomial * (n + 1 - l) / (l + 1);
  }
  return w;
}

/// The prolongation from the B-splines of width 2h to the unknowns, and
/// the placement of the coarse unknowns it keeps. Coarse spline K is the
/// sum over l in {0..n+1}^D of w_l times fine spline 2K + l.
Eigen::SparseMatrix<double> coarse_prolongation(const SplinePlacement& fine, SplinePlacement& coarse) {
  const int d = fine.dimension, n = fine.degree;
  const std::vector<double> w = two_scale_weights(n);
  double full_mass = 1.0;
  {
    double axis = 0.0;
    for (double v : w) axis += v * v;
    for (int a = 0; a < d; ++a) full_mass *= axis;
  }
  const KeyBox parents(fine, n + 1, 2);
  // The parents of fine unknown u: K_a in [ceil((i_a - n - 1) / 2), floor(i_a / 2)].
  auto for_each_parent = [&](int u, auto&& visit) {
    const std::array<int, 3>& i = fine.index[u];
    std::array<int, 3> first{}, last{};
    for (int a = 0; a < 3; ++a) {
      first[a] = a < d ? KeyBox::floor_divide(i[a] - n, 2) : 0;  // ceil((i - n - 1) / 2)
      last[a] = a < d ? KeyBox::floor_divide(i[a], 2) : 0;
    }
    for (int z = first[2]; z <= last[2]; ++z)
      for (int y = first[1]; y <= last[1]; ++y)
        for (int x = first[0]; x <= last[0]; ++x) {
          const std::array<int, 3> K{x, y, z};
          double weight = 1.0;
          for (int a = 0; a < d; ++a) weight *= w[static_cast<std::size_t>(i[a] - 2 * K[a])];
          visit(K, weight);
        }
  };
  const auto unknowns = static_cast<int>(fine.index.size());
  std::vector<double> mass(parents.count(), 0.0);
  std::vector<int> children(parents.count(), 0);
  for (int u = 0; u < unknowns; ++u) {
    if (fine.component[u] < 0) continue;
    for_each_parent(u, [&](const std::array<int, 3>& K, double weight) {
      const std::size_t key = parents.key(K, fine.component[u]);
      mass[key] += weight * weight;
      ++children[key];
    });
  }
  std::vector<int> column(parents.count(), -1);
  coarse.dimension = d;
  coarse.degree = n;
  coarse.index.clear();
  coarse.component.clear();
  for (std::size_t key = 0; key < parents.count(); ++key)
    if (children[key] >= 2 && mass[key] >= kCoarseShare * full_mass) {
      column[key] = static_cast<int>(coarse.index.size());
      const std::size_t cells = parents.count() / static_cast<std::size_t>(parents.components);
      coarse.index.push_back(parents.position(key % cells));
      coarse.component.push_back(static_cast<int>(key / cells));
    }
  std::vector<Eigen::Triplet<double>> entries;
  for (int u = 0; u < unknowns; ++u) {
    if (fine.component[u] < 0) continue;
    for_each_parent(u, [&](const std::array<int, 3>& K, double weight) {
      const int c = column[parents.key(K, fine.component[u])];
      if (c >= 0) entries.emplace_back(u, c, weight);
    });
  }
  Eigen::SparseMatrix<double> p(unknowns, static_cast<Eigen::Index>(coarse.index.size()));
  p.setFromTriplets(entries.begin(), entries.end());
  return p;
}

/// The lower triangle of S + S^T - P^T D P, S given by its columns, in
/// order, in `parts` (released as they are read). S(r, a) goes to column
/// min(r, a): each column gets two sorted runs (its own rows r >= a, then
/// the rows a > r of the later columns), merged with their sums. P^T D P
/// has no entry outside S's pattern (D is L's diagonal).
Eigen::SparseMatrix<double> symmetric_part(std::vector<Eigen::SparseMatrix<double>>& parts, Eigen::Index n,
                                           const Eigen::SparseMatrix<double>& p, const Eigen::VectorXd& diagonal) {
  auto for_each_entry = [&](auto&& visit, bool release) {
    Eigen::Index a = 0;
    for (auto& part : parts) {
      for (Eigen::Index c = 0; c < part.outerSize(); ++c, ++a)
        for (Eigen::SparseMatrix<double>::InnerIterator e(part, c); e; ++e) visit(e.row(), a, e.value());
      if (release) Eigen::SparseMatrix<double>().swap(part);
    }
  };
  std::vector<std::size_t> start(static_cast<std::size_t>(n) + 1, 0);
  for_each_entry([&](Eigen::Index r, Eigen::Index a, double) { ++start[static_cast<std::size_t>(std::min(r, a)) + 1]; },
                 false);
  std::vector<std::size_t> mid(static_cast<std::size_t>(n));  // where each column's second run begins
  for (Eigen::Index a = 0; a < n; ++a) start[a + 1] += start[a];
  std::vector<int> rows(start.back());
  std::vector<double> values(start.back());
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for_each_entry(
      [&](Eigen::Index r, Eigen::Index a, double v) {
        const auto column = static_cast<std::size_t>(std::min(r, a));
        if (r >= a) mid[column] = fill[column] + 1;
        rows[fill[column]] = static_cast<int>(std::max(r, a));
        values[fill[column]++] = r == a ? 2.0 * v : v;
      },
      true);
  Eigen::SparseMatrix<double> result(n, n);
  std::vector<std::pair<int, double>> merged;
  std::size_t kept = 0;
  for (Eigen::Index a = 0; a < n; ++a) {
    const std::size_t first = start[a], second = std::max(first, mid[a]), last = start[a + 1];
    merged.clear();
    for (std::size_t i = first, j = second; i < second || j < last;) {
      const bool from_first = j == last || (i < second && rows[i] <= rows[j]);
      const std::size_t k = from_first ? i++ : j++;
      if (!merged.empty() && merged.back().first == rows[k])
        merged.back().second += values[k];
      else
        merged.emplace_back(rows[k], values[k]);
    }
    start[a] = kept;
    for (const auto& [row, value] : merged) {
      rows[kept] = row;
      values[kept++] = value;
    }
  }
  start[n] = kept;
  // Minus P^T D P: for each fine unknown u, its coarse pairs (r >= a).
  const Eigen::SparseMatrix<double, Eigen::RowMajor> p_rows = p;
  for (Eigen::Index u = 0; u < p_rows.rows(); ++u)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator ea(p_rows, u); ea; ++ea)
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator er(p_rows, u); er; ++er) {
        if (er.col() < ea.col()) continue;
        const auto column = static_cast<std::size_t>(ea.col());
        const auto begin = rows.begin() + static_cast<std::ptrdiff_t>(start[column]);
        const auto end = rows.begin() + static_cast<std::ptrdiff_t>(start[column + 1]);
        const auto at = std::lower_bound(begin, end, static_cast<int>(er.col()));
        if (at != end && *at == er.col())
          values[static_cast<std::size_t>(at - rows.begin())] -= er.value() * diagonal[u] * ea.value();
      }
  result.resizeNonZeros(static_cast<Eigen::Index>(kept));
  std::copy(rows.begin(), rows.begin() + static_cast<std::ptrdiff_t>(kept), result.innerIndexPtr());
  std::copy(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(kept), result.valuePtr());
  for (Eigen::Index a = 0; a <= n; ++a) result.outerIndexPtr()[a] = static_cast<int>(start[a]);
  return result;
}

}  // namespace

/// The lower triangle of P^T A P, A given by its lower triangle L (the
/// diagonal D included): with S = P^T L P, P^T A P = S + S^T - P^T D P,
/// so the whole A is never formed (it would double the system's memory)
/// and the fine product L P has half the work of A P. L P is formed
/// kGalerkinColumns columns of P at a time: whole, it would hold several
/// times the coarse matrix's entries.
Eigen::SparseMatrix<double> galerkin_lower(const Eigen::SparseMatrix<double>& lower,
                                           const Eigen::SparseMatrix<double>& p) {
  const Eigen::SparseMatrix<double> p_transposed = p.transpose();
  const Eigen::Index coarse = p.cols(), chunks = (coarse + kGalerkinColumns - 1) / kGalerkinColumns;
  std::vector<Eigen::SparseMatrix<double>> parts(static_cast<std::size_t>(chunks));
#pragma omp parallel for schedule(dynamic, 1)
  for (Eigen::Index k = 0; k < chunks; ++k) {
    const Eigen::Index first = k * kGalerkinColumns, count = std::min(kGalerkinColumns, coarse - first);
    const Eigen::SparseMatrix<double> lp = lower * p.middleCols(first, count);
    parts[static_cast<std::size_t>(k)] = p_transposed * lp;
  }
  return symmetric_part(parts, coarse, p, lower.diagonal());
}

SchwarzPreconditioner::SchwarzPreconditioner(const Eigen::SparseMatrix<double>& lower,
                                             const SplinePlacement& placement) {
  if (placement.index.size() != static_cast<std::size_t>(lower.rows()) ||
      placement.component.size() != placement.index.size())
    throw std::invalid_argument("SchwarzPreconditioner: the placement does not match the matrix");
  // The coarse spaces and their Galerkin matrices first, the blocks after:
  // the products' temporaries never meet the blocks. (A vector of levels
  // reserved once: Eigen 3.4's SparseMatrix has no move constructor, and a
  // reallocation would copy every level.)
  std::vector<SplinePlacement> placements{placement};
  std::vector<Eigen::SparseMatrix<double>> prolongations, coarse_matrices;
  prolongations.reserve(kMostLevels);
  coarse_matrices.reserve(kMostLevels);
  const Eigen::SparseMatrix<double>* matrix = &lower;
  while (matrix->rows() > kCoarsestUnknowns && static_cast<int>(prolongations.size()) < kMostLevels) {
    SplinePlacement coarse;
    Eigen::SparseMatrix<double> p = coarse_prolongation(placements.back(), coarse);
    if (p.cols() == 0 || static_cast<double>(p.cols()) > kLeastCoarsening * static_cast<double>(matrix->rows())) break;
    Eigen::SparseMatrix<double> next = galerkin_lower(*matrix, p);
    coarse_matrices.emplace_back().swap(next);
    matrix = &coarse_matrices.back();
    prolongations.push_back(std::move(p));
    placements.push_back(std::move(coarse));
  }
  coarsest_size_ = matrix->rows();
  coarsest_.compute(*matrix);
  if (coarsest_.info() != Eigen::Success) {
    // Round-off may leave the Galerkin matrix of a nearly dependent coarse
    // space short of definite: a relative shift restores it.
    const double shift = 1e-10 * matrix->diagonal().cwiseAbs().maxCoeff();
    Eigen::SparseMatrix<double> identity(matrix->rows(), matrix->cols());
    identity.setIdentity();
    coarsest_.compute(*matrix + shift * identity);
    if (coarsest_.info() != Eigen::Success)
      throw std::runtime_error("the multilevel Schwarz preconditioner's coarsest level is not positive definite");
  }
  // Each level's blocks, the coarse ones first: a coarse matrix is
  // released once its blocks are built, before the largest level's.
  release_freed_memory();  // the Galerkin products' pieces
  levels_.resize(prolongations.size());
  for (std::size_t l = levels_.size(); l-- > 0;) {
    levels_[l].blocks = cell_blocks(l == 0 ? lower : coarse_matrices[l - 1], placements[l]);
    if (l > 0) Eigen::SparseMatrix<double>().swap(coarse_matrices[l - 1]);
    levels_[l].prolongation.swap(prolongations[l]);
  }
}

Eigen::VectorXd SchwarzPreconditioner::apply(std::size_t level, const Eigen::VectorXd& r) const {
  if (level == levels_.size()) return coarsest_.solve(r);
  const Level& here = levels_[level];
  Eigen::VectorXd z = Eigen::VectorXd::Zero(r.size());
  add_blocks(here.blocks, r, z);
  const Eigen::VectorXd coarse_r = here.prolongation.transpose() * r;
  z += here.prolongation * apply(level + 1, coarse_r);
  return z;
}

Eigen::VectorXd SchwarzPreconditioner::solve(const Eigen::VectorXd& r) const { return apply(0, r); }

std::string SchwarzPreconditioner::description() const {
  if (levels_.empty())
    return "multilevel Schwarz (one level: all " + std::to_string(coarsest_size_) + " unknowns by sparse Cholesky)";
  std::size_t inverses = 0;
  for (const Level& level : levels_) inverses += level.blocks.factors.size();
  return "multilevel Schwarz (" + std::to_string(levels()) + " levels of cell blocks, " + std::to_string(inverses) +
         " distinct block inverses, the coarsest " + std::to_string(coarsest_size_) + " unknowns by sparse Cholesky)";
}

std::size_t SchwarzPreconditioner::bytes() const {
  std::size_t total = 0;
  for (const Level& level : levels_) {
    const Blocks& b = level.blocks;
    total += b.members.size() * sizeof(int) + b.start.size() * sizeof(std::size_t);
    for (const Eigen::MatrixXf& inverse : b.factors) total += static_cast<std::size_t>(inverse.size()) * sizeof(float);
    total += b.packed.size() * sizeof(float);
    total += static_cast<std::size_t>(level.prolongation.nonZeros()) * (sizeof(double) + sizeof(int));
  }
  return total +
         static_cast<std::size_t>(coarsest_.matrixL().nestedExpression().nonZeros()) * (sizeof(double) + sizeof(int));
}

}  // namespace sage::solver
