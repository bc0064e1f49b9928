#pragma once
// Tape: an expression graph compiled into a flat list of instructions over
// registers, evaluated over many points.
//
// Ownership: a Tape owns its instructions and holds no reference to the
// graph it came from; it is immutable and may be shared by any number of
// Evaluators (one per thread). Compiling visits the graph once, in
// topological order, and reuses a register once its last reader has run,
// so the register count tracks the width of the graph, not its size.
//
// Several roots may be compiled together (a field and its gradient, say);
// shared subexpressions are then computed once per point.

#include <sage/expression/expression.hpp>

#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

namespace sage {

class ChebyshevPatch;  // chebyshev_patch.hpp: Op::Patch instructions point to one

struct Instruction {
  Op op;
  std::uint32_t out;
  std::uint32_t a;  // first argument register (unused for arity 0)
  std::uint32_t b;  // second argument register (unused for arity < 2)
  double p0;
  double p1;
  const PointClassifier* classifier = nullptr;  // Op::Classify; owned by the Tape
  const ChebyshevPatch* patch = nullptr;        // Op::Patch; owned by the Tape
};

class Tape {
 public:
  /// Compiles `roots` for evaluation in `dimension` (1, 2 or 3) variables.
  /// Throws std::invalid_argument if an expression uses a variable beyond
  /// the dimension (z in a 2D model).
  Tape(const std::vector<Expr>& roots, int dimension);
  Tape(const Expr& root, int dimension) : Tape(std::vector<Expr>{root}, dimension) {}

  int dimension() const { return dimension_; }
  std::size_t register_count() const { return registers_; }
  const std::vector<Instruction>& code() const { return code_; }
  /// Registers holding constants, loaded once per evaluator.
  const std::vector<std::pair<std::uint32_t, double>>& constants() const { return constants_; }
  /// Register of each root after evaluation, in the order given.
  const std::vector<std::uint32_t>& results() const { return results_; }
  /// Register holding variable i (0 = x), fixed: registers 0..dimension-1.
  static std::uint32_t variable_register(int i) { return static_cast<std::uint32_t>(i); }

  /// The graph behind the registers, for passes that walk it: for each
  /// instruction, the instructions whose results its arguments are
  /// (kInput for a variable or constant), and how many arguments of later
  /// instructions read each result (a root's counts two more: read forever).
  static constexpr std::uint32_t kInput = static_cast<std::uint32_t>(-1);
  const std::vector<std::array<std::uint32_t, 2>>& producers() const { return producers_; }
  const std::vector<std::uint32_t>& readers() const { return readers_; }
  /// The instruction computing each root (kInput: a variable or constant).
  const std::vector<std::uint32_t>& result_producers() const { return result_producers_; }
  /// Names this tape's code among all tapes of the run: copies share it,
  /// no two different tapes do (evaluators rebound to the same tape keep
  /// what they derived from it).
  std::uint64_t serial() const { return serial_; }

 private:
  friend class TapeSpecializer;  // builds tapes specialized to a box
  Tape() = default;
  void link();            // fills producers_, readers_ and result_producers_ from the code
  void constants_last();  // renumbers the registers: variables, working ones, constants

  int dimension_ = 0;
  std::size_t registers_ = 0;
  std::vector<Instruction> code_;
  std::vector<std::pair<std::uint32_t, double>> constants_;
  std::vector<std::uint32_t> results_;
  std::vector<std::array<std::uint32_t, 2>> producers_;
  std::vector<std::uint32_t> readers_;
  std::vector<std::uint32_t> result_producers_;
  std::vector<std::shared_ptr<const PointClassifier>> classifiers_;  // keeps them alive
  std::vector<std::shared_ptr<const ChebyshevPatch>> patches_;       // likewise
  std::uint64_t serial_ = next_serial();

  static std::uint64_t next_serial() {
    static std::atomic<std::uint64_t> counter{0};
    return ++counter;
  }
};

}  // namespace sage
