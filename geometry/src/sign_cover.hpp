#pragma once
// The Boolean formula of a solid over its literals, from sampled sign
// vectors: a union of conjunctions (terms) that covers every vector seen
// inside and none seen outside. Vectors never seen are free: no sample
// lies in that cell of the literals' arrangement.
//
// Each term is a prime implicant found by greedy expansion (Espresso's
// EXPAND step): start from an inside vector, drop its literals one by one
// in a given order, and keep a drop while no outside vector becomes
// covered. Every inside vector is expanded in every order given, and all
// primes are kept but those covering only inside vectors that another
// covers too: not a minimal cover, for R-functions want terms that overlap. Where two terms
// only touched (the L of two plates, split along the plane of one), their
// R-disjunction would vanish inside the solid; a greedy order alone often
// finds such a pair, another order the prime that spans both.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace sage::geometry {

/// Signs of literals 0..n-1, bit l of word l / 64 set where literal l > 0.
using SignVector = std::vector<std::uint64_t>;

/// Whether bit l of v is set: literal l > 0 in a vector, used (mask) or
/// positive (bits) in a term.
inline bool has_literal(const SignVector& v, std::size_t l) { return (v[l / 64] >> (l % 64)) & 1u; }

struct SignTerm {
  SignVector mask;  // the literals the term uses
  SignVector bits;  // their signs in the term

  bool covers(const SignVector& v) const;
};

/// The prime terms covering `inside` and no vector of `outside` (both of
/// vectors of `literals` literals), by expansion in each of `drop_orders`
/// (each a permutation of the literals). Throws std::invalid_argument if
/// a vector is in both sets.
std::vector<SignTerm> prime_terms(const std::vector<SignVector>& inside, const std::vector<SignVector>& outside,
                                  std::size_t literals, const std::vector<std::vector<std::size_t>>& drop_orders);

}  // namespace sage::geometry
