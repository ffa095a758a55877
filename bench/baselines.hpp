// Baselines the fast step is measured against (never used by the engine).
//
//  - SeedBaseline: the seed paper's Algorithm 1-2 (Yang & Hu, AICCSA 2009) written
//    as a straightforward C++ program: one heap object per mass, springs holding
//    pointers to their masses, the spring direction from atan and then sin and cos
//    per spring (the quadrant restored when dy < 0, else the literal formula makes
//    every creature explode), a force accumulator per mass, then the mass update
//    of Algorithm 2.
//    It is not SodaConstructor physics (bench/README.md); it is the speed yardstick.
//  - PlainLoop: the exact rules (physics_rules.hpp) as a plain, unoptimised scalar
//    loop: array of structs, one struct per link with its kind, branching per link
//    on the kind and on fixed ends, one sin per muscle per frame. Bit-identical to
//    the reference step (checked by the tests).
#pragma once

#include <memory>
#include <vector>

#include "core/model.hpp"

namespace sodaevo::bench {

class SeedBaseline {
 public:
  explicit SeedBaseline(const soda::Model& model);
  ~SeedBaseline();
  SeedBaseline(const SeedBaseline&) = delete;
  SeedBaseline& operator=(const SeedBaseline&) = delete;

  void reset();            ///< back to the model's initial state
  void run(long long frames);
  /// Sum of the positions (keeps the work observable; also a smoke value).
  [[nodiscard]] double checksum() const;

  struct Mass;
  struct Spring;

 private:
  const soda::Model* model_;
  std::vector<std::unique_ptr<Mass>> masses_;
  std::vector<std::unique_ptr<Spring>> springs_;
  std::vector<std::unique_ptr<Spring>> muscles_;
  double wave_angle_ = 0.0; ///< v of Algorithm 1 (radians)
};

class PlainLoop {
 public:
  explicit PlainLoop(const soda::Model& model);

  /// Steps `state` (a state of the model) like soda::run.
  void run(soda::State& state, long long frames);

 private:
  enum class Kind { Spring, Muscle, FixedBar };
  struct Node {
    double x, y, vx, vy;
    bool fixed;
  };
  struct Link {
    Kind kind;
    int a, b;
    double rest, amplitude, phase;
  };
  void step(soda::State& state);

  const soda::Model* model_;
  std::vector<Node> nodes_;
  std::vector<Link> links_;
};

} // namespace sodaevo::bench
