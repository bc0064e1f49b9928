#pragma once
// TapeSpecializer's internal state and helpers, shared by its two halves:
// exact pruning (tape_specialization.cpp) and far-field approximation
// (far_field.cpp).

#include <sage/tape/batch_evaluator.hpp>
#include <sage/tape/tape_specialization.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace sage::specialization {

inline bool is_min(const Instruction& ins) {
  return ins.op == Op::Min || (ins.op == Op::RAnd && static_cast<RKind>(static_cast<int>(ins.p0)) == RKind::MinMax);
}
inline bool is_max(const Instruction& ins) {
  return ins.op == Op::Max || (ins.op == Op::ROr && static_cast<RKind>(static_cast<int>(ins.p0)) == RKind::MinMax);
}

// Where a value of the specialized program comes from: an instruction of
// the original tape (>= 0), or a variable or constant (kVariable - v,
// kConstant - k for entry k of the constant table).
using Source = std::int64_t;
constexpr Source kVariable = -1;   // variable v: kVariable - v (v < 3)
constexpr Source kConstant = -16;  // constant k: kConstant - k
inline bool is_instruction(Source s) { return s >= 0; }

constexpr std::uint32_t kNoProducer = Tape::kInput;  // a variable or constant

}  // namespace sage::specialization

namespace sage {

struct TapeSpecializer::Bounds {
  std::vector<Interval> out;  // each instruction's enclosure, per box: out[i * lanes + lane]
  std::vector<double> up, low;
  std::vector<std::uint32_t> decisions;    // the mins, maxes, steps and classifiers
  std::vector<std::uint32_t> bound_nodes;  // the mins, maxes and negations
};

struct TapeSpecializer::Scratch {
  std::vector<char> needed, constant_live;
  std::vector<std::uint32_t> root_producers, constant_of_register, reads;
  std::vector<double> constants;
  std::vector<specialization::Source> source, arg_a, arg_b, roots;
  std::vector<std::uint32_t> constant_register, reg, free_registers;
  // fit_patches()'s: per instruction, then the sampled subtrees' values
  // (thousands of blocks per thread: allocating and clearing these for each
  // cost more than the fits).
  std::vector<std::size_t> size, row, sampled, pending;
  std::vector<char> read_by_analytic;
  std::vector<std::array<std::uint32_t, 2>> read;
  std::vector<double> xs;  // the samples: xs x rows
  std::vector<std::array<double, 2>> rows;
  std::vector<double> values;
  std::vector<double> sensitivity;
  std::unique_ptr<BatchEvaluator<double>> batch;
};

}  // namespace sage
