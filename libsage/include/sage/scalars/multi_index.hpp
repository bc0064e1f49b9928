#pragma once
// Multi-indices of N variables up to total order K, in graded order.
//
// Layout (used by every Tuple<N, K>): index 0 is the value, then all
// multi-indices of order 1, then order 2, and so on. Within one order the
// exponent of x descends first, then y, then z. For N = 2, K = 2:
//   0:(0,0)  1:(1,0)  2:(0,1)  3:(2,0)  4:(1,1)  5:(0,2)
// The tables are built at compile time; nothing here allocates.

#include <array>
#include <cstddef>

namespace sage {

constexpr int binomial(int n, int k) {
  if (k < 0 || k > n) return 0;
  long long r = 1;
  for (int i = 1; i <= k; ++i) r = r * (n - k + i) / i;
  return static_cast<int>(r);
}

/// Number of multi-indices of N variables with total order <= K.
constexpr int multi_index_count(int n, int k) { return binomial(n + k, n); }

template <int N>
using MultiIndex = std::array<int, N>;

template <int N>
constexpr int order_of(const MultiIndex<N>& a) {
  int s = 0;
  for (int e : a) s += e;
  return s;
}

/// All multi-indices of N variables up to order K, in the layout above.
template <int N, int K>
struct MultiIndexTable {
  static constexpr int size = multi_index_count(N, K);
  std::array<MultiIndex<N>, size> index{};

  constexpr MultiIndexTable() {
    int n = 0;
    for (int order = 0; order <= K; ++order) fill(order, 0, MultiIndex<N>{}, n);
  }

  /// Position of a multi-index in the layout, or -1 if its order exceeds K.
  constexpr int find(const MultiIndex<N>& a) const {
    for (int i = 0; i < size; ++i)
      if (index[i] == a) return i;
    return -1;
  }

 private:
  // Distribute `remaining` over variables var..N-1, first variable highest.
  constexpr void fill(int remaining, int var, MultiIndex<N> a, int& n) {
    if (var == N - 1) {
      a[var] = remaining;
      index[n++] = a;
      return;
    }
    for (int e = remaining; e >= 0; --e) {
      a[var] = e;
      fill(remaining - e, var + 1, a, n);
    }
  }
};

/// The Cauchy product table: every (i, j, k) with index[i] + index[j] =
/// index[k] and order <= K, sorted by the order of k, so that the terms
/// producing orders <= m are a prefix (prefix[m] of them). Multiplying two
/// tuples is one pass over it. With SkipConstantRhs, terms whose right
/// factor is the constant coefficient are left out: the table for
/// multiplying by a series with no constant term (see compose()).
template <int N, int K, bool SkipConstantRhs = false>
struct ProductTable {
  struct Term {
    unsigned short lhs, rhs, out;
  };
  static constexpr MultiIndexTable<N, K> table{};

  static constexpr bool kept(int i, int j) {
    if (SkipConstantRhs && j == 0) return false;
    return order_of<N>(table.index[i]) + order_of<N>(table.index[j]) <= K;
  }
  static constexpr int count() {
    int c = 0;
    for (int i = 0; i < table.size; ++i)
      for (int j = 0; j < table.size; ++j) c += kept(i, j);
    return c;
  }
  static constexpr int size = count();
  std::array<Term, size> terms{};
  std::array<int, K + 1> prefix{};

  constexpr ProductTable() {
    int c = 0;
    for (int order = 0; order <= K; ++order) {
      for (int i = 0; i < table.size; ++i)
        for (int j = 0; j < table.size; ++j) {
          if (!kept(i, j) || order_of<N>(table.index[i]) + order_of<N>(table.index[j]) != order) continue;
          MultiIndex<N> sum{};
          for (int v = 0; v < N; ++v) sum[v] = table.index[i][v] + table.index[j][v];
          terms[c++] = Term{static_cast<unsigned short>(i), static_cast<unsigned short>(j),
                            static_cast<unsigned short>(table.find(sum))};
        }
      prefix[order] = c;
    }
  }
};

}  // namespace sage
