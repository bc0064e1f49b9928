#pragma once
// Tuples of many points stored by component (a structure of arrays): lane
// l's coefficient k at data[k * stride + l]. BatchEvaluator keeps its
// registers so, and the kernels that run over its lanes (R-functions,
// far-field patches) read and write whole arrays of one component, which
// the compiler turns into vector instructions without shuffling the
// components of neighbouring tuples apart.

#include <sage/scalars/tuple.hpp>

#include <cstddef>
#include <type_traits>

namespace sage {

/// A view of `T` (Tuple<N, K>) lanes stored by component; D is double, or
/// const double for read-only lanes.
template <class T, class D = double>
struct TupleLanes {
  D* data;
  std::size_t stride;  // doubles from one component's lanes to the next's

  D* component(int k) const { return data + static_cast<std::size_t>(k) * stride; }

  T load(std::size_t l) const {
    T t;
    for (int k = 0; k < T::size; ++k) t.c[k] = component(k)[l];
    return t;
  }
  void store(std::size_t l, const T& t) const {
    static_assert(!std::is_const_v<D>, "read-only lanes");
    for (int k = 0; k < T::size; ++k) component(k)[l] = t.c[k];
  }
  operator TupleLanes<T, const double>() const  // NOLINT: implicit, a read-only view
      requires(!std::is_const_v<D>) {
    return {data, stride};
  }
};

template <class T>
using ConstTupleLanes = TupleLanes<T, const double>;

}  // namespace sage
