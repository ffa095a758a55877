// The wire format the MPI evaluator sends creatures and evaluations in: exact
// round trips (every bit of every double) and clear errors on damaged messages.
#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <limits>

#include "evolve/wire_format.hpp"
#include "formats/model_file.hpp"
#include "test_support.hpp"

using namespace sodaevo;

TEST_CASE("creatures round-trip the wire format bit for bit", "[wire]") {
  soda::ModelDef d = soda::read_model_file(test::models_dir() / "dainty_walker.xml").def;
  d.comment = "a comment with <xml> & \"quotes\"";
  d.name = "walker";
  d.nodes[0].x = -0.0;
  d.nodes[0].vx = std::nextafter(1.0, 2.0);
  d.nodes[1].vy = 5e-324;
  d.links[0].phase = 0.1 + 0.2;
  d.settings.autoreverse = false;
  d.settings.gravity_direction = soda::GravityDirection::Up;
  d.settings.wave_direction = soda::WaveDirection::Reverse;
  const soda::ModelDef back = decode_creature(encode_creature(d));
  CHECK(back == d);
  CHECK(std::signbit(back.nodes[0].x));
  CHECK(std::bit_cast<std::uint64_t>(back.nodes[1].vy) == std::bit_cast<std::uint64_t>(d.nodes[1].vy));
}

TEST_CASE("evaluations round-trip the wire format", "[wire]") {
  Evaluation e;
  e.status = EvaluationStatus::Diverged;
  e.reason = "diverged at frame 12";
  e.fitness = kWorstFitness;
  e.distance = 1.0 / 3.0;
  e.px_per_frame = -1e-300;
  const Evaluation back = decode_evaluation(encode_evaluation(e));
  CHECK(back.status == e.status);
  CHECK(back.reason == e.reason);
  CHECK(back.fitness == e.fitness);
  CHECK(back.distance == e.distance);
  CHECK(back.px_per_frame == e.px_per_frame);
}

TEST_CASE("damaged messages are refused with a WireError", "[wire]") {
  const soda::ModelDef d = soda::read_model_file(test::models_dir() / "dainty_walker.xml").def;
  std::vector<char> bytes = encode_creature(d);
  // Every truncation is caught, never a read past the end.
  for (std::size_t cut = 0; cut < bytes.size(); cut += 7) {
    const std::vector<char> part(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(cut));
    CHECK_THROWS_AS(decode_creature(part), WireError);
  }
  std::vector<char> longer = bytes;
  longer.push_back(0);
  CHECK_THROWS_AS(decode_creature(longer), WireError);
  // A huge string length is refused before any allocation.
  std::vector<char> huge = bytes;
  for (int i = 0; i < 8; ++i) huge[static_cast<std::size_t>(i)] = static_cast<char>(0xff);
  CHECK_THROWS_AS(decode_creature(huge), WireError);
  std::vector<char> bad_status = encode_evaluation(Evaluation{});
  bad_status[0] = 9;
  CHECK_THROWS_WITH(decode_evaluation(bad_status), Catch::Contains("bad evaluation status"));
}
