#pragma once
// Upper bounds of |d op / d argument| over a box, from the arguments'
// enclosures there: far-field approximation chains them from the roots
// down to every subtree (TapeSpecializer::sensitivities()), so that a patch's error,
// amplified by the exact operations above it, stays within the tolerance.
// (R-function partial derivatives reach 2 where an argument has the
// "wrong" sign: a patch under a few such nodes deviates several times its
// tail.) Internal to libsage.

#include <sage/scalars/interval.hpp>
#include <sage/tape/tape.hpp>

#include <cstdint>
#include <vector>

namespace sage::detail {

/// An upper bound of |d ins / d argument k| (k = 0: a, 1: b) over the box
/// where a and b lie in the given enclosures; infinity where none is known
/// (a root or a division whose argument may vanish), 0 for arguments an
/// operation does not read.
double partial_bound(const Instruction& ins, const Interval& a, const Interval& b, int k);

}  // namespace sage::detail
