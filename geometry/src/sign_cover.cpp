#include "sign_cover.hpp"

#include <algorithm>
#include <stdexcept>

namespace sage::geometry {

bool SignTerm::covers(const SignVector& v) const {
  for (std::size_t w = 0; w < mask.size(); ++w)
    if ((v[w] ^ bits[w]) & mask[w]) return false;
  return true;
}

namespace {

bool covers_any(const SignTerm& term, const std::vector<SignVector>& vectors) {
  return std::any_of(vectors.begin(), vectors.end(), [&](const SignVector& v) { return term.covers(v); });
}

void clear(SignVector& v, std::size_t l) { v[l / 64] &= ~(std::uint64_t{1} << (l % 64)); }
void set(SignVector& v, std::size_t l) { v[l / 64] |= std::uint64_t{1} << (l % 64); }

}  // namespace

std::vector<SignTerm> prime_terms(const std::vector<SignVector>& inside, const std::vector<SignVector>& outside,
                                  std::size_t literals, const std::vector<std::vector<std::size_t>>& drop_orders) {
  const std::size_t words = (literals + 63) / 64;
  SignVector all(words, 0);
  for (std::size_t l = 0; l < literals; ++l) set(all, l);

  std::vector<SignTerm> terms;
  for (const SignVector& v : inside)
    for (const auto& order : drop_orders) {
      SignTerm term{all, v};
      if (covers_any(term, outside))
        throw std::invalid_argument("prime_terms: a sign vector is both inside and outside");
      for (std::size_t l : order) {
        clear(term.mask, l);
        if (covers_any(term, outside)) set(term.mask, l);
      }
      for (std::size_t w = 0; w < words; ++w) term.bits[w] &= term.mask[w];
      terms.push_back(std::move(term));
    }

  // A term is dropped when another covers every inside vector it covers
  // (of two covering the same vectors, the first stays): x > 1 AND z < 1
  // inside x > 0 AND z < 1, say, which no literal shows.
  std::vector<std::vector<bool>> covered(terms.size(), std::vector<bool>(inside.size()));
  for (std::size_t t = 0; t < terms.size(); ++t)
    for (std::size_t i = 0; i < inside.size(); ++i) covered[t][i] = terms[t].covers(inside[i]);
  const auto within = [&](std::size_t t, std::size_t u) {
    for (std::size_t i = 0; i < inside.size(); ++i)
      if (covered[t][i] && !covered[u][i]) return false;
    return true;
  };
  std::vector<bool> dropped(terms.size(), false);
  std::vector<SignTerm> kept;
  for (std::size_t t = 0; t < terms.size(); ++t) {
    for (std::size_t u = 0; u < terms.size() && !dropped[t]; ++u)
      dropped[t] = u != t && !dropped[u] && within(t, u) && (!within(u, t) || u < t);
    if (!dropped[t]) kept.push_back(terms[t]);
  }
  return kept;
}

}  // namespace sage::geometry
