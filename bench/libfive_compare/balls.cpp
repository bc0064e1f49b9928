// libfive's evaluators on sage's 1,000-ball benchmark (far_field_bench
// balls): the union of the balls of /tmp/far_field_bench_balls_minmax.json,
// by max and by R0 (x + y + sqrt(x^2 + y^2)), sampled on an N^3 grid
// (lo + i (hi - lo) / (N - 1) per axis), values and values + gradients, ONE
// thread, float (libfive evaluates in float only). Balls are sage's
// normalized ones, f = (r^2 - |p - c|^2) / (2 r), positive inside, united in
// sage's balanced pairwise order, so values can be compared with sage's.
//
// Variants:
//   brute   ArrayEvaluator / DerivArrayEvaluator on every point, base tape
//   pruned  libfive's renderer scheme (Heightmap::recurse, Voxels::View
//           split): split the index box along its longest axis; at every box
//           above ArrayEvaluator::N (256) points, IntervalEvaluator::
//           intervalAndPush on the box's point extent; leaves are evaluated
//           with the pushed tape. No box is skipped: every value is needed.
// Tree shapes:
//   libfive  what libfive's Deck builds: Deck(tree) always runs
//            Tree::optimized(), which flattens nested max into one
//            commutative list (re-folded as a left-leaning chain sorted by
//            node address) and collects nested sums into affine forms
//   balanced sage's balanced tree as written (optimizer bypassed by marking
//            the tree as optimized) - closer to sage's own tape
//
// Checks: positive count and value sum per variant; the largest deviation
// from a double-precision reference computed here directly (no libfive);
// and, if sage's values are in /tmp/libfive_compare_sage_<union>.f64 (raw
// float64, x fastest; written by sage_checksum), the largest deviation from
// sage and the number of sign disagreements.
//
// Usage: balls [--grid N] [--runs R] [--cap S] [--skip-brute-grad] [BALLS.json]
//        R runs each (default 3), the fastest counts; a variant whose run
//        takes over S seconds (default 10) is run once.

#include <libfive/eval/deck.hpp>
#include <libfive/eval/eval_array.hpp>
#include <libfive/eval/eval_deriv_array.hpp>
#include <libfive/eval/eval_interval.hpp>
#include <libfive/eval/tape.hpp>
#include <libfive/tree/tree.hpp>

#include <nlohmann/json.hpp>
#include <sage/scalars/rfunction.hpp>  // reduce_balanced: sage's tree order, header only

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

using libfive::Tree;

namespace {

struct Ball {
  double c[3], r;
};

struct Problem {
  std::vector<Ball> balls;
  double lo[3], hi[3];
};

Problem load(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path + " (run far_field_bench 0 200,128 balls first)");
  const auto j = nlohmann::json::parse(in);
  Problem p;
  for (int a = 0; a < 3; ++a) {
    p.lo[a] = j.at("bounds").at("min").at(a).get<double>();
    p.hi[a] = j.at("bounds").at("max").at(a).get<double>();
  }
  for (const auto& b : j.at("field").at("args")) {
    if (b.at("primitive") != "ball") throw std::runtime_error("not a ball");
    Ball ball;
    for (int a = 0; a < 3; ++a) ball.c[a] = b.at("center").at(a).get<double>();
    ball.r = b.at("radius").get<double>();
    p.balls.push_back(ball);
  }
  return p;
}

enum class Union { MinMax, R0 };
const char* name(Union u) { return u == Union::MinMax ? "minmax" : "r0"; }

Tree ball_tree(const Ball& b) {
  const Tree q = square(Tree::X() - Tree(b.c[0])) + square(Tree::Y() - Tree(b.c[1])) + square(Tree::Z() - Tree(b.c[2]));
  return (Tree(b.r * b.r) - q) / Tree(2.0 * b.r);
}

Tree union_tree(const Problem& p, Union u) {
  std::vector<Tree> leaves;
  for (const Ball& b : p.balls) leaves.push_back(ball_tree(b));
  if (u == Union::MinMax) return sage::reduce_balanced(leaves, [](const Tree& a, const Tree& b) { return max(a, b); });
  return sage::reduce_balanced(leaves,
                               [](const Tree& a, const Tree& b) { return a + b + sqrt(square(a) + square(b)); });
}

/// Tree::with_flags is protected; a pointer to it through a derived class is
/// the standard way to reach it. Marking the tree "optimized" makes Deck
/// take it as written (no max-chain flattening, no affine collection).
struct TreeAccess : Tree {
  static Tree as_optimized(const Tree& t) {
    auto with_flags = &TreeAccess::with_flags;
    return (t.*with_flags)(TREE_FLAG_IS_OPTIMIZED);
  }
};

/// Double-precision reference, directly (sage's formulas, sage's order).
std::vector<double> reference(const Problem& p, Union u, int n, const std::vector<double> axis[3]) {
  std::vector<double> out(std::size_t(n) * n * n);
  auto work = [&](int k0, int k1) {
    std::vector<double> v(p.balls.size());
    for (int k = k0; k < k1; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const double x = axis[0][i], y = axis[1][j], z = axis[2][k];
          for (std::size_t b = 0; b < p.balls.size(); ++b) {
            const Ball& B = p.balls[b];
            const double dx = x - B.c[0], dy = y - B.c[1], dz = z - B.c[2];
            v[b] = (B.r * B.r - (dx * dx + dy * dy + dz * dz)) / (2.0 * B.r);
          }
          std::size_t m = v.size();
          while (m > 1) {  // in-place pairwise reduction, same order as sage::reduce_balanced
            std::size_t w = 0;
            for (std::size_t a = 0; a + 1 < m; a += 2)
              v[w++] = u == Union::MinMax ? std::max(v[a], v[a + 1])
                                          : v[a] + v[a + 1] + std::sqrt(v[a] * v[a] + v[a + 1] * v[a + 1]);
            if (m % 2) v[w++] = v[m - 1];
            m = w;
          }
          out[i + std::size_t(n) * (j + std::size_t(n) * k)] = v[0];
        }
  };
  const int threads = std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) pool.emplace_back(work, n * t / threads, n * (t + 1) / threads);
  for (auto& t : pool) t.join();
  return out;
}

std::vector<double> read_sage(Union u, std::size_t size) {
  const std::string path = std::string("/tmp/libfive_compare_sage_") + name(u) + ".f64";
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  std::vector<double> v(size);
  in.read(reinterpret_cast<char*>(v.data()), std::streamsize(size * sizeof(double)));
  if (!in) return {};
  return v;
}

struct Output {
  std::vector<float> value;     // n^3
  std::vector<float> gradient;  // 3 n^3 (x, y, z per point), empty for values only
};

class Bench {
 public:
  Bench(const Tree& tree, int n, const std::vector<double> axis[3])
      : deck_(std::make_shared<libfive::Deck>(tree)), array_(deck_), deriv_(deck_), interval_(deck_), n_(n) {
    for (int a = 0; a < 3; ++a)
      for (double x : axis[a]) axis_[a].push_back(float(x));
  }
  std::size_t tape_size() const { return deck_->tape->size(); }
  std::size_t interval_evaluations = 0, leaves = 0, leaf_tape_total = 0;

  void brute(Output& out, bool gradient) {
    constexpr std::size_t N = libfive::ArrayEvaluator::N;
    const std::size_t total = std::size_t(n_) * n_ * n_;
    libfive::ArrayEvaluator& e = gradient ? deriv_ : array_;
    std::size_t start = 0, count = 0;
    auto flush = [&] {
      if (gradient) {
        auto d = deriv_.derivs(count);
        for (std::size_t q = 0; q < count; ++q) {
          out.value[start + q] = d(3, q);
          for (int a = 0; a < 3; ++a) out.gradient[3 * (start + q) + a] = d(a, q);
        }
      } else {
        auto v = array_.values(count);
        for (std::size_t q = 0; q < count; ++q) out.value[start + q] = v[q];
      }
      start += count;
      count = 0;
    };
    for (std::size_t index = 0; index < total; ++index) {
      const std::size_t i = index % n_, j = (index / n_) % n_, k = index / n_ / n_;
      e.set(Eigen::Vector3f(axis_[0][i], axis_[1][j], axis_[2][k]), count++);
      if (count == N) flush();
    }
    if (count) flush();
  }

  void pruned(Output& out, bool gradient) {
    interval_evaluations = leaves = leaf_tape_total = 0;
    recurse(deck_->tape, {0, 0, 0}, {n_, n_, n_}, out, gradient);
  }

 private:
  void recurse(const libfive::Tape::Handle& tape, std::array<int, 3> lo, std::array<int, 3> hi, Output& out,
               bool gradient) {
    const std::size_t count = std::size_t(hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
    if (count <= libfive::ArrayEvaluator::N) {
      leaf(*tape, lo, hi, out, gradient);
      return;
    }
    ++interval_evaluations;
    const Eigen::Vector3f lower(axis_[0][lo[0]], axis_[1][lo[1]], axis_[2][lo[2]]);
    const Eigen::Vector3f upper(axis_[0][hi[0] - 1], axis_[1][hi[1] - 1], axis_[2][hi[2] - 1]);
    auto result = interval_.intervalAndPush(lower, upper, tape);
    int axis = 0;
    for (int a = 1; a < 3; ++a)
      if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
    const int mid = lo[axis] + (hi[axis] - lo[axis]) / 2;
    std::array<int, 3> hi_a = hi, lo_b = lo;
    hi_a[axis] = mid;
    lo_b[axis] = mid;
    recurse(result.second, lo, hi_a, out, gradient);
    recurse(result.second, lo_b, hi, out, gradient);
    if (result.second != tape) deck_->claim(std::move(result.second));
  }

  void leaf(const libfive::Tape& tape, std::array<int, 3> lo, std::array<int, 3> hi, Output& out, bool gradient) {
    ++leaves;
    leaf_tape_total += tape.size();
    libfive::ArrayEvaluator& e = gradient ? deriv_ : array_;
    std::size_t count = 0;
    for (int k = lo[2]; k < hi[2]; ++k)
      for (int j = lo[1]; j < hi[1]; ++j)
        for (int i = lo[0]; i < hi[0]; ++i) e.set(Eigen::Vector3f(axis_[0][i], axis_[1][j], axis_[2][k]), count++);
    count = 0;
    if (gradient) {
      auto d = deriv_.derivs(std::size_t(hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]), tape);
      for (int k = lo[2]; k < hi[2]; ++k)
        for (int j = lo[1]; j < hi[1]; ++j)
          for (int i = lo[0]; i < hi[0]; ++i, ++count) {
            const std::size_t index = i + std::size_t(n_) * (j + std::size_t(n_) * k);
            out.value[index] = d(3, count);
            for (int a = 0; a < 3; ++a) out.gradient[3 * index + a] = d(a, count);
          }
    } else {
      auto v = array_.values(std::size_t(hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]), tape);
      for (int k = lo[2]; k < hi[2]; ++k)
        for (int j = lo[1]; j < hi[1]; ++j)
          for (int i = lo[0]; i < hi[0]; ++i, ++count)
            out.value[i + std::size_t(n_) * (j + std::size_t(n_) * k)] = v[count];
    }
  }

  std::shared_ptr<libfive::Deck> deck_;
  libfive::ArrayEvaluator array_;
  libfive::DerivArrayEvaluator deriv_;
  libfive::IntervalEvaluator interval_;
  int n_;
  std::vector<float> axis_[3];
};

std::string sci(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1e", x);
  return text;
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  int n = 128, runs = 3;
  double cap = 10.0;
  bool brute_gradient = true;
  std::string path = "/tmp/far_field_bench_balls_minmax.json";
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--grid") && i + 1 < argc)
      n = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--runs") && i + 1 < argc)
      runs = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--cap") && i + 1 < argc)
      cap = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--skip-brute-grad"))
      brute_gradient = false;
    else
      path = argv[i];
  }
  const Problem problem = load(path);
  std::vector<double> axis[3];
  for (int a = 0; a < 3; ++a)
    for (int i = 0; i < n; ++i) axis[a].push_back(problem.lo[a] + i * ((problem.hi[a] - problem.lo[a]) / (n - 1)));
  const std::size_t total = std::size_t(n) * n * n;
  std::printf(
      "libfive, %zu balls, grid %d^3 over [%g,%g]^3, one thread, float, best of %d runs\n"
      "(s: fastest run, (runs made): a variant whose run takes over %g s is run once)\n\n",
      problem.balls.size(), n, problem.lo[0], problem.hi[0], runs, cap);
  std::printf(
      "| union | tree | variant | tape | s | points > 0 | sum of values | max |f - ref| | max |f - sage| | signs != "
      "sage | sum |grad| | boxes / leaves / mean leaf tape |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");

  for (Union u : {Union::MinMax, Union::R0}) {
    const auto start_ref = std::chrono::steady_clock::now();
    const std::vector<double> ref = reference(problem, u, n, axis);
    const double t_ref = seconds_since(start_ref);
    const std::vector<double> sage = read_sage(u, total);
    std::size_t ref_positive = 0, near_zero = 0, sage_positive = 0, sage_ref_signs = 0;
    double sage_ref_dev = 0;
    for (std::size_t q = 0; q < total; ++q) {
      ref_positive += ref[q] > 0;
      near_zero += std::abs(ref[q]) < 1e-6;
      if (!sage.empty()) {
        sage_positive += sage[q] > 0;
        sage_ref_signs += (sage[q] > 0) != (ref[q] > 0);
        sage_ref_dev = std::max(sage_ref_dev, std::abs(sage[q] - ref[q]));
      }
    }
    std::printf(
        "| %s | - | double reference (this program, 2 threads, %.1f s, untimed) | - | - | %zu | - | - | %s | %s | - "
        "| %zu points with |ref| < 1e-6 |\n",
        name(u), t_ref, ref_positive, sage.empty() ? "no sage file" : sci(sage_ref_dev).c_str(),
        sage.empty() ? "-" : std::to_string(sage_ref_signs).c_str(), near_zero);
    if (!sage.empty())
      std::printf("| %s | - | sage values read from file | - | - | %zu | - | - | - | - | - | - |\n", name(u),
                  sage_positive);

    const Tree tree = union_tree(problem, u);
    for (bool balanced : {false, true}) {
      Bench bench(balanced ? TreeAccess::as_optimized(tree) : tree, n, axis);
      for (bool gradient : {false, true}) {
        for (bool prune : {false, true}) {
          if (gradient && !prune && !brute_gradient) continue;
          Output out;
          out.value.assign(total, 0.0f);
          if (gradient) out.gradient.assign(3 * total, 0.0f);
          double best = 1e300;
          int done = 0;
          while (done < runs) {
            const auto t = std::chrono::steady_clock::now();
            if (prune)
              bench.pruned(out, gradient);
            else
              bench.brute(out, gradient);
            const double s = seconds_since(t);
            best = std::min(best, s);
            ++done;
            if (s > cap) break;  // slow variants: one run is enough
          }
          std::size_t positive = 0, signs = 0;
          double sum = 0, dev = 0, sage_dev = 0, grad = 0;
          for (std::size_t q = 0; q < total; ++q) {
            positive += out.value[q] > 0;
            sum += out.value[q];
            dev = std::max(dev, std::abs(double(out.value[q]) - ref[q]));
            if (!sage.empty()) {
              sage_dev = std::max(sage_dev, std::abs(double(out.value[q]) - sage[q]));
              signs += (out.value[q] > 0) != (sage[q] > 0);
            }
            if (gradient)
              grad += std::sqrt(double(out.gradient[3 * q]) * out.gradient[3 * q] +
                                double(out.gradient[3 * q + 1]) * out.gradient[3 * q + 1] +
                                double(out.gradient[3 * q + 2]) * out.gradient[3 * q + 2]);
          }
          char stats[96] = "-";
          if (prune)
            std::snprintf(stats, sizeof stats, "%zu / %zu / %.1f", bench.interval_evaluations, bench.leaves,
                          double(bench.leaf_tape_total) / double(bench.leaves));
          char grad_text[32] = "-";
          if (gradient) std::snprintf(grad_text, sizeof grad_text, "%.6e", grad);
          std::printf("| %s | %s | %s%s | %zu | %.4f (%d) | %zu | %.6e | %.1e | %s | %s | %s | %s |\n", name(u),
                      balanced ? "balanced" : "libfive", prune ? "pruned" : "brute", gradient ? " + gradient" : "",
                      bench.tape_size(), best, done, positive, sum, dev, sage.empty() ? "-" : sci(sage_dev).c_str(),
                      sage.empty() ? "-" : std::to_string(signs).c_str(), grad_text, stats);
        }
      }
    }
  }
  return 0;
}
