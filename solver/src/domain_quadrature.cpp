#include "cut_cell_rule.hpp"

#include <sage/expression/derivative.hpp>
#include <sage/solver/domain_quadrature.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <functional>
#include <limits>

namespace sage::solver {

namespace {

std::vector<Expr> value_and_gradient(const Expr& f, int dimension) {
  std::vector<Expr> roots{f};
  for (const Expr& g : gradient(f, dimension)) roots.push_back(g);
  return roots;
}

}  // namespace

DomainPieces::DomainPieces(const Expr& omega, int dimension_) : dimension(dimension_) {
  const BooleanForm form = boolean_form(omega);
  formula = form.formula;
  value.reserve(form.pieces.size());
  enclosure.reserve(form.pieces.size());
  for (const Expr& piece : form.pieces) {
    const std::vector<Expr> roots = value_and_gradient(piece, dimension_);
    value.emplace_back(piece, dimension_);
    enclosure.emplace_back(roots, dimension_);
    planar.push_back(std::all_of(roots.begin() + 1, roots.end(), [](const Expr& g) { return g.is_constant(); }) ? 1
                                                                                                                : 0);
  }
}

// ---------------------------------------------------------------------------
// Classification of the grid's cells, blocks first.

namespace {

/// Interval evaluators of the pieces, made when first asked (a thread
/// touches only the pieces near its blocks).
class PieceIntervals {
 public:
  explicit PieceIntervals(const DomainPieces& pieces) : pieces_(pieces), eval_(pieces.piece_count()) {}
  template <int D>
  Interval over(std::uint32_t piece, const std::array<Interval, D>& box) {
    auto& e = eval_[piece];
    if (!e) e = std::make_unique<Evaluator<Interval>>(pieces_.value[piece]);
    e->evaluate_with(box.data());
    return e->result();
  }

 private:
  const DomainPieces& pieces_;
  std::vector<std::unique_ptr<Evaluator<Interval>>> eval_;
};

template <int D>
class GridClassifier {
 public:
  GridClassifier(const DomainPieces& pieces, const BackgroundGrid<D>& grid, std::vector<ClassifiedCell>& out)
      : grid_(grid), out_(out), intervals_(pieces), sign_(pieces.piece_count(), 0) {}

  /// Cells lo[a] <= i[a] < hi[a].
  void classify(std::array<int, D> lo, std::array<int, D> hi, const BooleanFormula& formula) {
    if (formula.is_constant()) return fill(lo, hi, formula.constant_value() ? CellKind::Inside : CellKind::Outside);
    std::array<Interval, D> box{};
    for (int a = 0; a < D; ++a) box[a] = Interval(grid_.lo[a] + lo[a] * grid_.h, grid_.lo[a] + hi[a] * grid_.h);
    const std::vector<std::uint32_t> pieces = formula.pieces();
    for (const std::uint32_t p : pieces) sign_[p] = static_cast<signed char>(sign_of(intervals_.over<D>(p, box)));
    const BooleanFormula restricted = formula.restricted([&](std::size_t p) { return int{sign_[p]}; });
    if (restricted.is_constant())
      return fill(lo, hi, restricted.constant_value() ? CellKind::Inside : CellKind::Outside);
    int widest = 0;
    for (int a = 1; a < D; ++a)
      if (hi[a] - lo[a] > hi[widest] - lo[widest]) widest = a;
    if (hi[widest] - lo[widest] == 1) {
      out_[linear(lo)] = classified_cell(restricted, [&](std::uint32_t p) { return intervals_.over<D>(p, box); });
      return;
    }
    const int middle = (lo[widest] + hi[widest]) / 2;
    std::array<int, D> split_hi = hi, split_lo = lo;
    split_hi[widest] = middle;
    split_lo[widest] = middle;
    classify(lo, split_hi, restricted);
    classify(split_lo, hi, restricted);
  }

 private:
  std::size_t linear(const std::array<int, D>& c) const {
    std::size_t k = 0;
    for (int a = D - 1; a >= 0; --a) k = k * static_cast<std::size_t>(grid_.cells[a]) + static_cast<std::size_t>(c[a]);
    return k;
  }
  void fill(const std::array<int, D>& lo, const std::array<int, D>& hi, CellKind kind) {
    std::array<int, D> c = lo;
    while (true) {
      out_[linear(c)].kind = kind;
      int a = 0;
      for (; a < D; ++a) {
        if (++c[a] < hi[a]) break;
        c[a] = lo[a];
      }
      if (a == D) return;
    }
  }

  const BackgroundGrid<D>& grid_;
  std::vector<ClassifiedCell>& out_;
  PieceIntervals intervals_;
  std::vector<signed char> sign_;
};

}  // namespace

template <int D>
std::vector<ClassifiedCell> classify_cells(const DomainPieces& pieces, const BackgroundGrid<D>& grid) {
  std::vector<ClassifiedCell> out(grid.cell_count());
  // Blocks of up to 8 cells per axis, shared among the threads.
  constexpr int kBlock = 8;
  std::array<int, D> blocks{};
  std::size_t block_count = 1;
  for (int a = 0; a < D; ++a) {
    blocks[a] = (grid.cells[a] + kBlock - 1) / kBlock;
    block_count *= static_cast<std::size_t>(blocks[a]);
  }
#pragma omp parallel
  {
    GridClassifier<D> classifier(pieces, grid, out);
#pragma omp for schedule(dynamic, 1)
    for (std::size_t b = 0; b < block_count; ++b) {
      std::array<int, D> lo{}, hi{};
      std::size_t rest = b;
      for (int a = 0; a < D; ++a) {
        const int index = static_cast<int>(rest % static_cast<std::size_t>(blocks[a]));
        rest /= static_cast<std::size_t>(blocks[a]);
        lo[a] = index * kBlock;
        hi[a] = std::min(grid.cells[a], lo[a] + kBlock);
      }
      classifier.classify(lo, hi, pieces.formula);
    }
  }
  return out;
}

template std::vector<ClassifiedCell> classify_cells<2>(const DomainPieces&, const BackgroundGrid<2>&);
template std::vector<ClassifiedCell> classify_cells<3>(const DomainPieces&, const BackgroundGrid<3>&);

// ---------------------------------------------------------------------------
// The pieces' tapes as the cut-cell rule reads them.

namespace {

template <int D>
class TapePieces final : public PieceSource<D> {
 public:
  explicit TapePieces(const DomainPieces& pieces)
      : pieces_(pieces),
        value_(pieces.piece_count()),
        gradient_(pieces.piece_count()),
        enclosure_(pieces.piece_count()) {}
  std::size_t count() const override { return pieces_.piece_count(); }
  double value(std::uint32_t i, const std::array<double, D>& p) override {
    auto& e = value_[i];
    if (!e) e = std::make_unique<Evaluator<double>>(pieces_.value[i]);
    e->evaluate(p.data());
    return e->result();
  }
  double gradient(std::uint32_t i, const std::array<double, D>& p, std::array<double, D>& g) override {
    auto& e = gradient_[i];
    if (!e) e = std::make_unique<Evaluator<Tuple<D, 1>>>(pieces_.value[i]);
    e->evaluate(p.data());
    g = e->result().gradient();
    return e->result().value();
  }
  std::array<Interval, D + 1> enclosure(std::uint32_t i, const std::array<Interval, D>& box) override {
    auto& e = enclosure_[i];
    if (!e) e = std::make_unique<Evaluator<Interval>>(pieces_.enclosure[i]);
    e->evaluate_with(box.data());
    std::array<Interval, D + 1> out{};
    for (int r = 0; r <= D; ++r) out[r] = e->result(static_cast<std::size_t>(r));
    return out;
  }
  bool planar(std::uint32_t i) const override { return pieces_.planar[i] != 0; }

 private:
  const DomainPieces& pieces_;
  std::vector<std::unique_ptr<Evaluator<double>>> value_;
  std::vector<std::unique_ptr<Evaluator<Tuple<D, 1>>>> gradient_;
  std::vector<std::unique_ptr<Evaluator<Interval>>> enclosure_;
};

}  // namespace

template <int D>
class ImplicitCellQuadrature<D>::Rule {
 public:
  Rule(const DomainPieces& pieces, QuadratureOptions options)
      : formula_(pieces.formula), tapes_(pieces), intervals_(pieces), rule_(options) {}

  ClassifiedCell classify(const Box<D>& box) {
    std::array<Interval, D> x{};
    for (int a = 0; a < D; ++a) x[a] = Interval(box.lo[a], box.hi[a]);
    auto enclosure = [&](std::uint32_t p) { return intervals_.over<D>(p, x); };
    const BooleanFormula f =
        formula_.restricted([&](std::size_t p) { return sign_of(enclosure(static_cast<std::uint32_t>(p))); });
    return classified_cell(f, enclosure);
  }
  void append(const Box<D>& box, const ClassifiedCell& cell, std::vector<VolumePoint<D>>& volume,
              std::vector<SurfacePoint<D>>* surface) {
    rule_.append(tapes_, box, cell, volume, surface);
  }
  const QuadratureCounts& counts() const { return rule_.counts(); }

 private:
  const BooleanFormula& formula_;
  TapePieces<D> tapes_;
  PieceIntervals intervals_;
  CutCellRule<D> rule_;
};

template <int D>
ImplicitCellQuadrature<D>::ImplicitCellQuadrature(const DomainPieces& pieces, QuadratureOptions options)
    : rule_(std::make_unique<Rule>(pieces, options)) {}

template <int D>
ImplicitCellQuadrature<D>::~ImplicitCellQuadrature() = default;

template <int D>
ImplicitCellQuadrature<D>::ImplicitCellQuadrature(ImplicitCellQuadrature&&) noexcept = default;

template <int D>
const QuadratureCounts& ImplicitCellQuadrature<D>::counts() const {
  return rule_->counts();
}

template <int D>
ClassifiedCell ImplicitCellQuadrature<D>::classify(const Box<D>& box) {
  return rule_->classify(box);
}

template <int D>
void ImplicitCellQuadrature<D>::append_rule(const Box<D>& box, const ClassifiedCell& cell,
                                            std::vector<VolumePoint<D>>& volume,
                                            std::vector<SurfacePoint<D>>* surface) {
  rule_->append(box, cell, volume, surface);
}

template class ImplicitCellQuadrature<2>;
template class ImplicitCellQuadrature<3>;

}  // namespace sage::solver
