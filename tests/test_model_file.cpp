// Tests of the model file layer (formats/model_file.hpp): reading v1 and v2 files,
// refusing race files and malformed input with precise messages, and writing
// canonical v1 that reads back exactly.
//
// Expected values come from the files themselves (independent string counts), from
// docs/file-formats.md (defaults, layout) or are written by hand; none is computed
// with the code under test.

#include <catch2/catch.hpp>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/input_error.hpp"
#include "core/model.hpp"
#include "core/model_def.hpp"
#include "formats/model_file.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using soda::InputError;
using sodaevo::test::same_bits;
using sodaevo::test::xml_files_under;
using soda::LinkDef;
using soda::LinkKind;
using soda::ModelDef;
using soda::NodeDef;

namespace {

const fs::path kSodaDir = fs::path(SODAEVO_TEST_DATA_DIR) / "soda";

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  REQUIRE(in);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::size_t count_of(const std::string& text, const std::string& needle) {
  std::size_t n = 0;
  for (std::size_t pos = text.find(needle); pos != std::string::npos; pos = text.find(needle, pos + 1)) ++n;
  return n;
}

/// Name of the first element of an XML text, found without an XML parser: skips
/// the declaration, processing instructions, the DOCTYPE and comments.
std::string root_element_name(const std::string& text) {
  std::size_t i = 0;
  while (i < text.size()) {
    i = text.find('<', i);
    if (i == std::string::npos) return "";
    if (text.compare(i, 4, "<!--") == 0) {
      i = text.find("-->", i);
    } else if (text.compare(i, 2, "<?") == 0 || text.compare(i, 2, "<!") == 0) {
      i = text.find('>', i);
    } else {
      std::size_t end = i + 1;
      while (end < text.size() && (std::isalnum(static_cast<unsigned char>(text[end])) || text[end] == '_'))
        ++end;
      return text.substr(i + 1, end - i - 1);
    }
    if (i == std::string::npos) return "";
  }
  return "";
}

struct Counts {
  std::size_t masses = 0, fixed = 0, springs = 0, muscles = 0, bars = 0;
};

Counts counts_of(const ModelDef& def) {
  Counts c;
  for (const NodeDef& n : def.nodes) (n.fixed ? c.fixed : c.masses)++;
  for (const LinkDef& l : def.links) {
    (l.kind == LinkKind::Spring ? c.springs : l.kind == LinkKind::Muscle ? c.muscles : c.bars)++;
  }
  return c;
}

soda::LoadedModel read_text(const std::string& text) { return soda::read_model_text(text, "test.xml"); }

/// The message of the InputError reading `text` throws ("" and a failure if none).
std::string error_of(const std::string& text) {
  try {
    (void)read_text(text);
  } catch (const InputError& e) {
    return e.what();
  }
  FAIL_CHECK("no InputError for:\n" << text);
  return "";
}

bool contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

bool any_contains(const std::vector<std::string>& list, const std::string& needle) {
  return std::any_of(list.begin(), list.end(), [&](const std::string& s) { return contains(s, needle); });
}

const std::string kOneMass = "<nodes><mass id=\"a\" x=\"1\" y=\"2\" vx=\"0\" vy=\"0\"/></nodes>";

/// Checks the model files of one directory tree: every <model> and v2 file loads
/// with the counts of its elements; every <race> file is refused.
void check_corpus(const fs::path& dir, std::size_t& v1, std::size_t& v2, std::size_t& races) {
  for (const fs::path& path : xml_files_under(dir)) {
    INFO(path.string());
    const std::string text = slurp(path);
    const std::string root = root_element_name(text);
    if (root == "race") {
      try {
        (void)soda::read_model_file(path);
        FAIL_CHECK("race file accepted");
      } catch (const InputError& e) {
        CHECK_THAT(e.what(), Catch::Contains("race file") && Catch::Contains(path.string()) &&
                                 Catch::Contains("not supported"));
      }
      ++races;
      continue;
    }
    REQUIRE((root == "model" || root == "object"));
    if (text.find("gravity=\"Infinity\"") != std::string::npos) {
      // A racer's lane of a contender scaled by +inf (golden terrain/components,
      // README there: these lane files do not load): refused, naming the gravity.
      CHECK_THROWS_WITH(soda::read_model_file(path), Catch::Contains("gravity") && Catch::Contains("Infinity"));
      continue;
    }
    const soda::LoadedModel m = soda::read_model_file(path);
    const Counts c = counts_of(m.def);
    if (root == "model") {
      ++v1;
      CHECK(m.format == soda::ModelFormat::V1);
      CHECK(c.masses == count_of(text, "<mass "));
      CHECK(c.fixed == count_of(text, "<node "));
      CHECK(c.springs == count_of(text, "<spring "));
      CHECK(c.muscles == count_of(text, "<muscle "));
      CHECK(c.bars == count_of(text, "<fixedbar "));
    } else {
      ++v2;
      CHECK(m.format == soda::ModelFormat::V2);
      CHECK(c.masses == count_of(text, "constructor2.model.Mass\""));
      CHECK(c.fixed == count_of(text, "constructor2.model.Node\""));
      CHECK(c.springs == count_of(text, "constructor2.model.Spring\""));
      CHECK(c.muscles == count_of(text, "constructor2.model.Muscle\""));
      CHECK(c.bars == 0);
    }
  }
}

/// A small valid v1 model, one element per line, so tests can replace line n.
std::vector<std::string> base_lines() {
  return {
      "<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>",      // 1
      "<model>",                                              // 2
      "<environment gravity=\"0.3\"/>",                       // 3
      "<nodes>",                                              // 4
      "<mass id=\"m0\" x=\"0\" y=\"0\" vx=\"0\" vy=\"0\"/>",  // 5
      "<mass id=\"m1\" x=\"10\" y=\"0\" vx=\"0\" vy=\"0\"/>", // 6
      "</nodes>",                                             // 7
      "<links>",                                              // 8
      "<spring a=\"m0\" b=\"m1\" restlength=\"10\"/>",        // 9
      "</links>",                                             // 10
      "</model>",                                             // 11
  };
}

std::string with_line(int line, const std::string& replacement) {
  std::vector<std::string> lines = base_lines();
  lines.at(static_cast<std::size_t>(line - 1)) = replacement;
  std::string out;
  for (const std::string& l : lines) out += l + "\n";
  return out;
}

/// A small v2 file; `model_fields` and `node_list`/`spring_list` are spliced in.
std::string v2_text(const std::string& model_fields, const std::string& extra_nodes = "",
                    const std::string& springs = "") {
  const std::string p = "com.sodaplay.soda.constructor2.model.";
  auto mass = [&](int k, const char* x) {
    return "<object id=\"Mass#" + std::to_string(k) + "\" type=\"" + p +
           "Mass\">\n"
           "<field name=\"vx\"><double>0.0</double></field>\n"
           "<field name=\"vy\"><double>0.0</double></field>\n"
           "<field name=\"x\"><double>" +
           x +
           "</double></field>\n"
           "<field name=\"y\"><double>0.0</double></field>\n"
           "</object>\n";
  };
  return "<object id=\"ConstructorApplication#1\" "
         "type=\"com.sodaplay.soda.constructor2.ConstructorApplication\">\n"
         "<field name=\"model\">\n"
         "<object id=\"Model#1\" type=\"" +
         p + "Model\">\n" + model_fields + "<field name=\"nodes\"><list class=\"java.util.Vector\">\n" +
         mass(1, "0.0") + mass(2, "10.0") + extra_nodes +
         "</list></field>\n"
         "<field name=\"springs\"><list class=\"java.util.Vector\">\n" +
         springs +
         "</list></field>\n"
         "</object>\n"
         "</field>\n"
         "</object>\n";
}

std::string v2_spring(const char* a, const char* b) {
  return std::string("<object id=\"Spring#1\" type=\"com.sodaplay.soda.constructor2.model.Spring\">\n") +
         "<field name=\"a\"><ref refid=\"" + a + "\" /></field>\n" + "<field name=\"b\"><ref refid=\"" + b +
         "\" /></field>\n" + "<field name=\"restLength\"><double>10.0</double></field>\n" + "</object>\n";
}

} // namespace

// --- positions ----------------------------------------------------------------------

TEST_CASE("locate_offset gives 1-based line and byte column", "[model_file]") {
  const std::string text = "ab\ncd\r\nef\rgh";
  auto at = [&](std::ptrdiff_t off) {
    const soda::TextLocation loc = soda::locate_offset(text, off);
    return std::pair{loc.line, loc.column};
  };
  CHECK(at(0) == std::pair{1L, 1L});
  CHECK(at(1) == std::pair{1L, 2L});
  CHECK(at(3) == std::pair{2L, 1L}); // 'c'
  CHECK(at(4) == std::pair{2L, 2L});
  CHECK(at(7) == std::pair{3L, 1L});  // 'e' after CR LF
  CHECK(at(10) == std::pair{4L, 1L}); // 'g' after a lone CR
  CHECK(at(-5) == std::pair{1L, 1L});
  CHECK(at(1000) == std::pair{4L, 3L}); // clamped to the end
}

TEST_CASE("LineIndex locates every offset as a scan from the start does", "[model_file]") {
  // Reference: walk the bytes before the offset, one line per LF, per CR LF and per
  // lone CR, written here independently of LineIndex.
  const auto scan = [](const std::string& text, std::size_t end) {
    long line = 1, column = 1;
    for (std::size_t i = 0; i < end; ++i) {
      const bool crlf_cr = text[i] == '\r' && i + 1 < text.size() && text[i + 1] == '\n';
      if (text[i] == '\n' || (text[i] == '\r' && !crlf_cr)) {
        ++line;
        column = 1;
      } else {
        ++column;
      }
    }
    return std::pair{line, column};
  };
  std::mt19937 rng(7);
  const char alphabet[] = {'a', '<', '\n', '\r', ' '};
  for (int trial = 0; trial < 200; ++trial) {
    std::string text(static_cast<std::size_t>(rng() % 40), 'a');
    for (char& c : text) c = alphabet[rng() % sizeof alphabet];
    const soda::LineIndex index(text);
    for (std::size_t off = 0; off <= text.size(); ++off) {
      const soda::TextLocation loc = index.locate(static_cast<std::ptrdiff_t>(off));
      INFO("text of " << text.size() << " bytes, offset " << off);
      REQUIRE(std::pair{loc.line, loc.column} == scan(text, off));
      REQUIRE(index.line_start(loc.line) + static_cast<std::size_t>(loc.column - 1) == off);
    }
    const soda::TextLocation past = index.locate(static_cast<std::ptrdiff_t>(text.size()) + 9);
    CHECK(std::pair{past.line, past.column} == scan(text, text.size()));
  }
}

// --- the model files in the test data -------------------------------------------------

TEST_CASE("every model file in the test data loads and race files are refused", "[model_file]") {
  std::size_t v1 = 0, v2 = 0, races = 0;
  check_corpus(kSodaDir, v1, v2, races);
  // SOURCES.md: 14 v2 files, 37 race files, and v1 files in three repositories + golden/.
  CHECK(v2 == 14);
  CHECK(races == 37);
  CHECK(v1 >= 20);
}

TEST_CASE("the shared model directory loads too", "[model_file]") {
  const fs::path dir = fs::path(SODAEVO_SHARED_DIR) / "models" / "soda";
  if (!fs::is_directory(dir)) {
    WARN("skipped: " << dir.string() << " does not exist (the shared workspace is not beside the project)");
    return;
  }
  std::size_t v1 = 0, v2 = 0, races = 0;
  check_corpus(dir, v1, v2, races);
  CHECK(v1 + v2 > 0);
}

TEST_CASE("known files have the contents their documentation states", "[model_file]") {
  SECTION("carefulslug (v2): 60 masses, 172 springs, 13 muscles (SOURCES.md)") {
    const auto m = soda::read_model_file(kSodaDir / "KeniF_SodaSumo/carefulslug.xml");
    const Counts c = counts_of(m.def);
    CHECK(c.masses == 60);
    CHECK(c.fixed == 0);
    CHECK(c.springs == 172);
    CHECK(c.muscles == 13);
    CHECK(m.def.name == "carefulslug");
    CHECK(m.def.width == 657);
    CHECK(m.def.height == 430);
    CHECK(m.def.settings.wave_direction == soda::WaveDirection::Reverse);
    CHECK(m.def.settings.gravity_direction == soda::GravityDirection::Down);
    CHECK(m.def.settings.autoreverse);
    CHECK(m.warnings.empty());
  }
  SECTION("monster_truck (v2): 61 masses, 139 springs, 40 muscles (SOURCES.md)") {
    const Counts c = counts_of(soda::read_model_file(kSodaDir / "KeniF_SodaSumo/monster_truck.xml").def);
    CHECK(c.masses == 61);
    CHECK(c.springs == 139);
    CHECK(c.muscles == 40);
  }
  SECTION("treader (v2) has 6 fixed Nodes") {
    const auto m = soda::read_model_file(kSodaDir / "KeniF_SodaSumo/treader.xml");
    CHECK(counts_of(m.def).fixed == 6);
    CHECK(m.def.name == "roey_schurr_FourNodes");
    for (const NodeDef& n : m.def.nodes) {
      if (n.fixed) {
        CHECK(n.vx == 0.0);
        CHECK(n.vy == 0.0);
      }
    }
  }
  SECTION("KeniF_triangle (v2): ids and full-precision values kept") {
    const auto m = soda::read_model_file(kSodaDir / "KeniF_SodaSumo/KeniF_triangle.xml");
    REQUIRE(m.def.nodes.size() == 3);
    CHECK(m.def.nodes[0].id == "Mass#1");
    CHECK(m.def.nodes[0].x == 173.60420625497596);
    CHECK(m.def.nodes[0].vy == -1.2115243293454647);
    CHECK(m.def.nodes[2].id == "Mass#3");
    REQUIRE(m.def.links.size() == 3);
    const LinkDef& muscle = m.def.links[2];
    CHECK(muscle.kind == LinkKind::Muscle);
    CHECK(muscle.a == 0); // Mass#1
    CHECK(muscle.b == 2); // Mass#3
    CHECK(muscle.amplitude == 1.0);
    CHECK(muscle.phase == 0.2512363996043521);
    CHECK(muscle.rest_length == 210.6773334099998);
    CHECK(m.def.links[0].a == 1); // Spring#1: Mass#2 -> Mass#1
    CHECK(m.def.links[0].b == 0);
    CHECK(m.def.wave.phase == 0.010000000000002665);
    CHECK(m.def.name == "model");
    CHECK(m.def.comment.empty());
  }
  SECTION("ramp (v2): springyness 0.8 clamped into the v1 range with a warning") {
    const auto m = soda::read_model_file(kSodaDir / "KeniF_SodaSumo/ramp.xml");
    CHECK(m.def.environment.springyness == 0.5);
    CHECK(m.def.environment.friction == 1.0); // at the edge of [0, 1]: kept
    REQUIRE(m.warnings.size() == 1);
    CHECK_THAT(m.warnings[0], Catch::Contains("ramp.xml:") && Catch::Contains("springyness") &&
                                  Catch::Contains("0.8") && Catch::Contains("[0, 0.5]") &&
                                  Catch::Contains("reject"));
  }
  SECTION("MINS Dainty Walker (later v1): name read, polys ignored silently") {
    const auto m = soda::read_model_file(kSodaDir / "OptimusLime_MINS.js/daintywalker.xml");
    CHECK(m.def.name == "Dainty Walker - Ed Burton");
    CHECK(counts_of(m.def).masses == 10);
    CHECK(counts_of(m.def).muscles == 8);
    CHECK(counts_of(m.def).springs == 14);
    CHECK(m.def.environment.gravity == 0.38046992);
    CHECK(m.def.wave.speed == 0.012156863);
    CHECK(m.warnings.empty());
  }
  SECTION("turbine (bare <model>, no prolog) and mountain terrain") {
    const auto t = soda::read_model_file(kSodaDir / "OptimusLime_MINS.js/turbine.xml");
    CHECK(t.def.width == 5002);
    CHECK(t.def.height == 2406);
    const auto m = soda::read_model_file(kSodaDir / "OptimusLime_MINS.js/mountain_terrain.xml");
    CHECK(counts_of(m.def).fixed == 31);
    CHECK(counts_of(m.def).bars == 30);
    CHECK(m.def.width == 3000);
  }
  SECTION("wodka Model0: wave amplitude 34.16 clamped to 1 with a warning") {
    const auto m = soda::read_model_file(kSodaDir / "wwagner4_wodka/lib_wodka_jar/model/Model0.xml");
    CHECK(m.def.wave.amplitude == 1.0);
    CHECK(m.def.wave.speed == 0.27972109766367725);
    REQUIRE(m.warnings.size() == 1);
    CHECK_THAT(m.warnings[0], Catch::Contains("Model0.xml:7:") && Catch::Contains("<wave>") &&
                                  Catch::Contains("amplitude") && Catch::Contains("34.161588333679575"));
  }
  SECTION("golden random_16: muscle phase 1.000 wraps to 0 without a warning") {
    const auto m = soda::read_model_file(kSodaDir / "golden/random_16.xml");
    REQUIRE(!m.def.links.empty());
    CHECK(m.def.links[0].kind == LinkKind::Muscle);
    CHECK(same_bits(m.def.links[0].phase, 0.0));
    CHECK(m.def.links[0].amplitude == 0.084);
    CHECK(m.warnings.empty());
    CHECK(m.def.nodes.back().id == "f0");
    CHECK(m.def.nodes.back().fixed);
  }
}

// --- read -> write -> read ------------------------------------------------------------

TEST_CASE("read, write, read gives the canonical form of the first read", "[model_file]") {
  std::size_t checked = 0;
  for (const fs::path& path : xml_files_under(kSodaDir)) {
    if (root_element_name(slurp(path)) == "race") continue;
    INFO(path.string());
    const soda::LoadedModel first = soda::read_model_file(path);
    const std::string text = soda::write_model_text(first.def);
    const soda::LoadedModel second = read_text(text);
    CHECK(second.format == soda::ModelFormat::V1);
    CHECK(second.warnings.empty());
    CHECK(second.def == soda::canonical_form(first.def));
    CHECK(soda::write_model_text(second.def) == text);
    ++checked;
  }
  CHECK(checked >= 34);
}

TEST_CASE("write then read round-trips any finite double exactly", "[model_file]") {
  std::mt19937_64 rng(20240611);
  std::vector<double> specials = {0.0,
                                  -0.0,
                                  std::numeric_limits<double>::denorm_min(),
                                  -std::numeric_limits<double>::denorm_min(),
                                  std::numeric_limits<double>::min(),
                                  std::nextafter(std::numeric_limits<double>::min(), 0.0),
                                  std::numeric_limits<double>::max(),
                                  std::numeric_limits<double>::lowest(),
                                  1e300,
                                  -1e300,
                                  1e-300,
                                  0.1,
                                  1.0 / 3.0,
                                  55.0,
                                  -2.0882535107713296,
                                  9007199254740993.0,
                                  123456789012345678901234567890.0};
  auto random_finite = [&]() {
    for (;;) {
      const double v = std::bit_cast<double>(rng());
      if (std::isfinite(v)) return v;
    }
  };
  std::size_t next_special = 0;
  auto value = [&]() { return next_special < specials.size() ? specials[next_special++] : random_finite(); };
  std::uniform_real_distribution<double> unit(0.0, 1.0);

  for (int round = 0; round < 20; ++round) {
    ModelDef def;
    def.comment = "round " + std::to_string(round);
    def.wave.speed = value();
    def.wave.phase = round == 0 ? std::numeric_limits<double>::denorm_min() : unit(rng);
    def.wave.amplitude = round == 0 ? std::nextafter(1.0, 0.0) : unit(rng);
    def.environment.gravity = round == 0 ? 4.0 : 4.0 * unit(rng);
    def.environment.springyness = round == 0 ? 0.5 : 0.5 * unit(rng);
    def.collisions.surface_reflection = round == 0 ? -1.0 : -unit(rng);
    const int n = 60;
    for (int i = 0; i < n; ++i) {
      NodeDef node;
      node.fixed = i % 7 == 3;
      node.id = "p" + std::to_string(i);
      node.x = value();
      node.y = value();
      if (!node.fixed) {
        node.vx = value();
        node.vy = value();
      }
      def.nodes.push_back(node);
    }
    for (int i = 0; i + 1 < n; ++i) {
      LinkDef link;
      link.kind = i % 3 == 0 ? LinkKind::Muscle : LinkKind::Spring;
      link.a = i;
      link.b = i + 1;
      link.rest_length = value();
      if (link.kind == LinkKind::Muscle) {
        link.amplitude = unit(rng);
        link.phase = i == 0 ? std::nextafter(1.0, 0.0) : unit(rng);
      }
      def.links.push_back(link);
    }
    const ModelDef expected = soda::canonical_form(def);
    const soda::LoadedModel back = read_text(soda::write_model_text(def));
    REQUIRE(back.def.nodes.size() == expected.nodes.size());
    REQUIRE(back.def.links.size() == expected.links.size());
    for (std::size_t i = 0; i < expected.nodes.size(); ++i) {
      INFO("round " << round << " node " << i);
      CHECK(same_bits(back.def.nodes[i].x, expected.nodes[i].x));
      CHECK(same_bits(back.def.nodes[i].y, expected.nodes[i].y));
      CHECK(same_bits(back.def.nodes[i].vx, expected.nodes[i].vx));
      CHECK(same_bits(back.def.nodes[i].vy, expected.nodes[i].vy));
    }
    for (std::size_t i = 0; i < expected.links.size(); ++i) {
      INFO("round " << round << " link " << i);
      CHECK(same_bits(back.def.links[i].rest_length, expected.links[i].rest_length));
      CHECK(same_bits(back.def.links[i].amplitude, expected.links[i].amplitude));
      CHECK(same_bits(back.def.links[i].phase, expected.links[i].phase));
    }
    CHECK(same_bits(back.def.wave.speed, expected.wave.speed));
    CHECK(same_bits(back.def.wave.phase, expected.wave.phase));
    CHECK(same_bits(back.def.wave.amplitude, expected.wave.amplitude));
    CHECK(same_bits(back.def.environment.gravity, expected.environment.gravity));
    CHECK(back.def == expected);
  }
  CHECK(next_special == specials.size());
}

// --- the writer -----------------------------------------------------------------------

TEST_CASE("the writer produces the canonical v1 layout", "[model_file]") {
  ModelDef def; // defaults of an empty model
  def.nodes.push_back(NodeDef{"first", false, 10.0, 20.0, -1.5, 0.125});
  def.nodes.push_back(NodeDef{"second", true, 30.5, 20.0, 0.0, 0.0});
  def.nodes.push_back(NodeDef{"third", false, 0.0, -2.0, 0.0, 3.0});
  def.links.push_back(LinkDef{LinkKind::FixedBar, 1, 0, 0.0, 0.0, 0.0});
  def.links.push_back(LinkDef{LinkKind::Muscle, 0, 1, 15.0, 0.5, 0.25});
  def.links.push_back(LinkDef{LinkKind::Spring, 0, 2, 20.0, 0.0, 0.0});
  def.links.push_back(LinkDef{LinkKind::Spring, 2, 1, -7.5, 0.0, 0.0});

  // Written by hand from docs/file-formats.md (canonical form): fixed nodes first, one running
  // index for ids, links grouped springs, muscles, fixed bars.
  const std::string expected =
      "<?xml version=\"1.0\" encoding=\"ISO-8859-1\" standalone=\"no\"?>\n"
      "<!DOCTYPE sodaconstructor>\n"
      "<model>\n"
      "\t<comment></comment>\n"
      "\t<container width=\"651\" height=\"422\"/>\n"
      "\t<environment gravity=\"0.3\" friction=\"0.05\" springyness=\"0.2\"/>\n"
      "\t<collisions surface_friction=\"0.1\" surface_reflection=\"-0.75\"/>\n"
      "\t<wave amplitude=\"0.5\" phase=\"0.0\" speed=\"0.01\"/>\n"
      "\t<settings gravitydirection=\"down\" wavedirection=\"forward\" autoreverse=\"on\"/>\n"
      "\n"
      "\t<nodes>\n"
      "\t\t<node id=\"n0\" x=\"30.5\" y=\"20.0\"/>\n"
      "\t\t<mass id=\"m1\" x=\"10.0\" y=\"20.0\" vx=\"-1.5\" vy=\"0.125\"/>\n"
      "\t\t<mass id=\"m2\" x=\"0.0\" y=\"-2.0\" vx=\"0.0\" vy=\"3.0\"/>\n"
      "\t</nodes>\n"
      "\n"
      "\t<links>\n"
      "\t\t<spring a=\"m1\" b=\"m2\" restlength=\"20.0\"/>\n"
      "\t\t<spring a=\"m2\" b=\"n0\" restlength=\"-7.5\"/>\n"
      "\t\t<muscle a=\"m1\" b=\"n0\" restlength=\"15.0\" amplitude=\"0.5\" phase=\"0.25\"/>\n"
      "\t\t<fixedbar a=\"n0\" b=\"m1\"/>\n"
      "\t</links>\n"
      "</model>\n";
  CHECK(soda::write_model_text(def) == expected);

  SECTION("name, container and settings") {
    def.name = "Walker";
    def.width = 830;
    def.height = 542;
    def.settings = {soda::GravityDirection::Up, soda::WaveDirection::Manual, false};
    const std::string text = soda::write_model_text(def);
    CHECK(contains(
        text, "\t<comment></comment>\n\t<name>Walker</name>\n\t<container width=\"830\" height=\"542\"/>\n"));
    CHECK(contains(text,
                   "\t<settings gravitydirection=\"up\" wavedirection=\"manual\" autoreverse=\"off\"/>\n"));
    def.settings = {soda::GravityDirection::Off, soda::WaveDirection::Reverse, true};
    CHECK(contains(soda::write_model_text(def),
                   "\t<settings gravitydirection=\"off\" wavedirection=\"reverse\" autoreverse=\"on\"/>\n"));
  }
}

TEST_CASE("comment and name text is escaped for an ISO-8859-1 file and reads back", "[model_file]") {
  ModelDef def;
  def.nodes.push_back(NodeDef{"a", false, 1.0, 2.0, 0.0, 0.0});

  SECTION("markup characters, latin-1 and a CJK character") {
    def.comment = "a & b < c \"q\" > d \xC3\xA9t\xC3\xA9 \xE4\xB8\xAD"; // "été", U+4E2D
    def.name = "<na&me>";
    const std::string text = soda::write_model_text(def);
    CHECK(contains(text, "<comment>a &amp; b &lt; c &quot;q&quot; &gt; d \xE9t\xE9 &#20013;</comment>"));
    CHECK(contains(text, "<name>&lt;na&amp;me&gt;</name>"));
    CHECK(!contains(text, "\xC3")); // no UTF-8 in a latin-1 file
    const auto back = read_text(text);
    CHECK(back.def.comment == def.comment);
    CHECK(back.def.name == def.name);
    CHECK(back.warnings.empty());
  }
  SECTION("white space: tabs, line ends, CR, a comment of blanks only") {
    for (const std::string comment : {"  \n\t x \n ", "   ", "line1\r\nline2\rline3", "\t"}) {
      def.comment = comment;
      const auto back = read_text(soda::write_model_text(def));
      CHECK(back.def.comment == comment);
    }
  }
  SECTION("characters XML 1.0 forbids become U+FFFD, written as a reference") {
    def.comment = std::string("a\x01") + "b" + std::string(1, '\0') + "c\x1F" + "\xFF"; // \xFF: bad UTF-8
    const std::string text = soda::write_model_text(def);
    CHECK(contains(text, "<comment>a&#65533;b&#65533;c&#65533;&#65533;</comment>"));
    const auto back = read_text(text);
    CHECK(back.def.comment ==
          "a\xEF\xBF\xBD"
          "b\xEF\xBF\xBD"
          "c\xEF\xBF\xBD\xEF\xBF\xBD");
    CHECK(back.warnings.empty());
  }
  SECTION("C1 controls and DEL are written as references") {
    def.comment = "x\xC2\x85y\x7Fz"; // U+0085, U+007F
    const std::string text = soda::write_model_text(def);
    CHECK(contains(text, "<comment>x&#133;y&#127;z</comment>"));
    CHECK(read_text(text).def.comment == def.comment);
  }
}

// The original reads a link from a node to itself (the Sodarace racer counts its rest
// length in its scale: golden c09_links_kept_verbatim): kept, with a warning, written
// back; build_model refuses it (the engine would skip it: length 0).
TEST_CASE("a link from a node to itself is read with a warning, written back, refused by build_model",
          "[model_file]") {
  const auto m = read_text(with_line(9, "<spring a=\"m1\" b=\"m1\" restlength=\"10\"/>"));
  REQUIRE(m.def.links.size() == 1);
  CHECK(m.def.links[0].a == 1);
  CHECK(m.def.links[0].b == 1);
  CHECK(m.def.links[0].rest_length == 10.0);
  REQUIRE(m.warnings.size() == 1);
  CHECK_THAT(m.warnings[0], Catch::Contains("test.xml:9:") && Catch::Contains("'m1'") && Catch::Contains("itself"));
  CHECK(read_text(soda::write_model_text(m.def)).def == soda::canonical_form(m.def));
  CHECK_THROWS_WITH(soda::build_model(m.def), Catch::Contains("itself"));
}

TEST_CASE("the writer refuses a model no file may carry", "[model_file]") {
  ModelDef def;
  def.nodes.push_back(NodeDef{"a", false, 1.0, 2.0, 0.0, 0.0});
  def.nodes.push_back(NodeDef{"b", false, 5.0, 2.0, 0.0, 0.0});
  def.links.push_back(LinkDef{LinkKind::Spring, 0, 1, 4.0, 0.0, 0.0});
  REQUIRE_NOTHROW(soda::write_model_text(def));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();

  SECTION("NaN position") {
    def.nodes[1].x = nan;
    CHECK_THROWS_WITH(soda::write_model_text(def), Catch::Contains("'b'") && Catch::Contains("x") &&
                                                       Catch::Contains("nan") && Catch::Contains("finite"));
  }
  SECTION("infinite rest length") {
    def.links[0].rest_length = -inf;
    CHECK_THROWS_WITH(soda::write_model_text(def), Catch::Contains("rest length") && Catch::Contains("inf"));
  }
  SECTION("infinite wave speed") {
    def.wave.speed = inf;
    CHECK_THROWS_AS(soda::write_model_text(def), InputError);
  }
  SECTION("link to a node that does not exist") {
    def.links[0].b = 2;
    CHECK_THROWS_AS(soda::write_model_text(def), InputError);
  }
  SECTION("gravity outside the range the reader accepts") {
    def.environment.gravity = 5.0;
    CHECK_THROWS_WITH(soda::write_model_text(def), Catch::Contains("gravity") && Catch::Contains("[0, 4]"));
  }
  SECTION("a phase not wrapped") {
    def.wave.phase = 1.0;
    CHECK_THROWS_AS(soda::write_model_text(def), InputError);
  }
  SECTION("no nodes") {
    def.links.clear();
    def.nodes.clear();
    CHECK_THROWS_AS(soda::write_model_text(def), InputError);
  }
}

TEST_CASE("model files are written atomically and read back", "[model_file]") {
  const fs::path dir = sodaevo::test::fresh_temp_dir("model_file_atomic");
  const fs::path path = dir / "walker.xml";
  const auto original = soda::read_model_file(kSodaDir / "OptimusLime_MINS.js/daintywalker.xml");

  soda::write_model_file(path, original.def);
  CHECK(soda::read_model_file(path).def == soda::canonical_form(original.def));
  // Overwrite an existing file.
  ModelDef changed = original.def;
  changed.comment = "second";
  soda::write_model_file(path, changed);
  CHECK(soda::read_model_file(path).def.comment == "second");
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    (void)entry;
    ++files;
  }
  CHECK(files == 1); // no temporary left behind

  SECTION("a directory that does not exist") {
    const fs::path bad = dir / "missing" / "x.xml";
    CHECK_THROWS_WITH(soda::write_model_file(bad, original.def),
                      Catch::Contains(bad.string()) && Catch::Contains("No such file"));
  }
  SECTION("reading a missing file names it and the reason") {
    const fs::path missing = dir / "nope.xml";
    CHECK_THROWS_WITH(soda::read_model_file(missing),
                      Catch::Contains(missing.string()) && Catch::Contains("No such file"));
  }
  SECTION("reading an empty path says so") {
    CHECK_THROWS_WITH(soda::read_model_file(""), "model file: expected a path, got an empty one");
  }
  SECTION("reading a directory") {
    CHECK_THROWS_WITH(soda::read_model_file(dir),
                      Catch::Contains(dir.string()) && Catch::Contains("directory"));
  }
  SECTION("a file far too large is refused before it is read") {
    const fs::path huge = dir / "huge.xml";
    { std::ofstream(huge, std::ios::binary) << "<model>"; }
    fs::resize_file(huge, (std::uintmax_t{256} << 20) + 1); // sparse
    CHECK_THROWS_WITH(soda::read_model_file(huge), Catch::Contains("huge.xml") && Catch::Contains("MiB"));
  }
  fs::remove_all(dir);
}

// --- reader rules ----------------------------------------------------------------------

TEST_CASE("a model with only <nodes> gets the documented defaults (docs/file-formats.md)", "[model_file]") {
  const auto m = read_text("<model>" + kOneMass + "</model>");
  const ModelDef& d = m.def;
  CHECK(d.comment.empty());
  CHECK(d.name.empty());
  CHECK(d.width == 651);
  CHECK(d.height == 422);
  CHECK(d.environment.gravity == 0.3);
  CHECK(d.environment.friction == 0.05);
  CHECK(d.environment.springyness == 0.2);
  CHECK(d.collisions.surface_friction == 0.1);
  CHECK(d.collisions.surface_reflection == -0.75);
  CHECK(d.wave.amplitude == 0.5);
  CHECK(d.wave.phase == 0.0);
  CHECK(d.wave.speed == 0.01);
  CHECK(d.settings.gravity_direction == soda::GravityDirection::Down);
  CHECK(d.settings.wave_direction == soda::WaveDirection::Forward);
  CHECK(d.settings.autoreverse);
  REQUIRE(d.nodes.size() == 1);
  CHECK(d.nodes[0] == NodeDef{"a", false, 1.0, 2.0, 0.0, 0.0});
  CHECK(d.links.empty());
  CHECK(m.warnings.empty());

  SECTION("each header attribute is optional") {
    const auto p = read_text(
        "<model><environment friction=\"0.5\"/><wave speed=\"-0.02\"/>"
        "<settings autoreverse=\"off\"/><container height=\"100\"/>" +
        kOneMass + "</model>");
    CHECK(p.def.environment.gravity == 0.3);
    CHECK(p.def.environment.friction == 0.5);
    CHECK(p.def.environment.springyness == 0.2);
    CHECK(p.def.wave.amplitude == 0.5);
    CHECK(p.def.wave.speed == -0.02);
    CHECK(p.def.settings.wave_direction == soda::WaveDirection::Forward);
    CHECK(!p.def.settings.autoreverse);
    CHECK(p.def.width == 651);
    CHECK(p.def.height == 100);
  }
}

TEST_CASE("the reader does not depend on element order", "[model_file]") {
  const std::string header_wave = "<wave amplitude=\"0.25\" phase=\"0.5\" speed=\"0.02\"/>";
  const std::string header_settings =
      "<settings gravitydirection=\"up\" wavedirection=\"reverse\" autoreverse=\"off\"/>";
  const std::string nodes =
      "<nodes><node id=\"n\" x=\"1\" y=\"1\"/><mass id=\"m\" x=\"5\" y=\"5\" vx=\"1\" vy=\"2\"/></nodes>";
  const std::string links = "<links><spring a=\"n\" b=\"m\" restlength=\"3\"/></links>";
  const std::string env = "<environment gravity=\"1\" friction=\"0.1\" springyness=\"0.3\"/>";
  const auto canonical = read_text("<model><comment>c</comment>" + env + header_wave + header_settings +
                                   nodes + links + "</model>");
  const auto shuffled = read_text("<model>" + links + header_settings + nodes + header_wave +
                                  "<comment>c</comment>" + env + "</model>");
  CHECK(shuffled.def == canonical.def);
  // The original would have left the wave in manual mode here (docs/file-formats.md, v1).
  CHECK(shuffled.def.settings.wave_direction == soda::WaveDirection::Reverse);
  CHECK(shuffled.def.settings.gravity_direction == soda::GravityDirection::Up);
  CHECK(shuffled.def.wave.phase == 0.5);
}

TEST_CASE("muscle and wave values are wrapped and clamped like the original", "[model_file]") {
  auto muscle = [](const std::string& amplitude, const std::string& phase) {
    return read_text(
        "<model><nodes><mass id=\"a\" x=\"0\" y=\"0\" vx=\"0\" vy=\"0\"/>"
        "<mass id=\"b\" x=\"9\" y=\"0\" vx=\"0\" vy=\"0\"/></nodes>\n<links>\n"
        "<muscle a=\"a\" b=\"b\" restlength=\"9\" amplitude=\"" +
        amplitude + "\" phase=\"" + phase + "\"/></links></model>");
  };
  SECTION("phases wrap into [0, 1) silently") {
    const auto one = muscle("0.5", "1.0");
    CHECK(same_bits(one.def.links.at(0).phase, 0.0));
    CHECK(one.warnings.empty());
    CHECK(muscle("0.5", "-0.25").def.links.at(0).phase == 0.75);
    CHECK(muscle("0.5", "2.5").def.links.at(0).phase == 0.5);
    CHECK(muscle("0.5", "0.999").def.links.at(0).phase == 0.999);
  }
  SECTION("amplitude above 1 becomes 1 with a warning") {
    const auto m = muscle("1.7", "0");
    CHECK(m.def.links.at(0).amplitude == 1.0);
    REQUIRE(m.warnings.size() == 1);
    CHECK_THAT(m.warnings[0], Catch::Contains("test.xml:3:") && Catch::Contains("<muscle>") &&
                                  Catch::Contains("'amplitude'") && Catch::Contains("'1.7'"));
  }
  SECTION("negative amplitude becomes 0 with a warning") {
    const auto m = muscle("-0.5", "0");
    CHECK(m.def.links.at(0).amplitude == 0.0);
    CHECK(m.warnings.size() == 1);
  }
  SECTION("wave amplitude above 1 becomes 1, wave phase wraps") {
    const auto m = read_text("<model><wave amplitude=\"34.16\" phase=\"1.25\"/>" + kOneMass + "</model>");
    CHECK(m.def.wave.amplitude == 1.0);
    CHECK(m.def.wave.phase == 0.25);
    REQUIRE(m.warnings.size() == 1);
    CHECK_THAT(m.warnings[0], Catch::Contains("<wave>") && Catch::Contains("'34.16'"));
  }
  SECTION("warnings are capped so a huge file cannot flood the output") {
    std::string text =
        "<model><nodes><mass id=\"a\" x=\"0\" y=\"0\" vx=\"0\" vy=\"0\"/>"
        "<mass id=\"b\" x=\"9\" y=\"0\" vx=\"0\" vy=\"0\"/></nodes><links>";
    for (int i = 0; i < 250; ++i)
      text += "<muscle a=\"a\" b=\"b\" restlength=\"9\" amplitude=\"2\" phase=\"0\"/>\n";
    const auto m = read_text(text + "</links></model>");
    CHECK(m.def.links.size() == 250);
    REQUIRE(m.warnings.size() > 10);
    CHECK(m.warnings.size() < 250);
    CHECK_THAT(m.warnings.back(), Catch::Contains("more warnings"));
  }
}

TEST_CASE("unknown things are ignored, most with a warning", "[model_file]") {
  const auto m = read_text(
      "<model><comment>hi</comment><name>Nm</name><foo/>"
      "<nodes><node id=\"n\" x=\"1\" y=\"2\" vx=\"5\"/><bar/>"
      "<mass id=\"m\" x=\"0\" y=\"0\" vx=\"0\" vy=\"0\"/></nodes>"
      "<links><fixedbar a=\"n\" b=\"m\"/><rope a=\"n\" b=\"m\"/></links>"
      "<polys><poly color=\"#770000\" points=\"m,n\" curvy=\"1\"/></polys></model>");
  CHECK(m.def.comment == "hi");
  CHECK(m.def.name == "Nm");
  REQUIRE(m.def.nodes.size() == 2);
  CHECK(m.def.nodes[0] == NodeDef{"n", true, 1.0, 2.0, 0.0, 0.0}); // a fixed node has no velocity
  REQUIRE(m.def.links.size() == 1);
  CHECK(m.def.links[0].kind == LinkKind::FixedBar);
  CHECK(m.warnings.size() == 4);
  CHECK(any_contains(m.warnings, "<foo>"));
  CHECK(any_contains(m.warnings, "<bar>"));
  CHECK(any_contains(m.warnings, "<rope>"));
  CHECK(any_contains(m.warnings, "attribute 'vx'"));
  CHECK(!any_contains(m.warnings, "poly"));
}

TEST_CASE("encodings: latin-1 is converted, positions count characters", "[model_file]") {
  SECTION("a latin-1 comment becomes UTF-8") {
    const auto m =
        read_text("<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>\n<model><comment>caf\xE9 \xA9</comment>" +
                  kOneMass + "</model>");
    CHECK(m.def.comment == "caf\xC3\xA9 \xC2\xA9");
  }
  SECTION("an error after latin-1 characters on the same line has the file's column") {
    const std::string msg = error_of(
        "<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>\n"
        "<model><comment>\xE9\xE9</comment><environment gravity=\"9\"/>" +
        kOneMass + "</model>");
    // Columns counted by hand, one per latin-1 character: '<environment' starts at
    // column 29 of line 2, 'gravity' at 42.
    CHECK_THAT(msg, Catch::StartsWith("test.xml:2:42: <environment> attribute 'gravity'"));
  }
  SECTION("a UTF-8 file (no declaration) keeps UTF-8") {
    const auto m = read_text("<model><name>\xE4\xB8\xAD</name>" + kOneMass + "</model>");
    CHECK(m.def.name == "\xE4\xB8\xAD");
  }
  SECTION("a UTF-8 BOM is accepted") {
    CHECK(read_text("\xEF\xBB\xBF<model>" + kOneMass + "</model>").def.nodes.size() == 1);
  }
  SECTION("latin-1 bytes without a declaration are an error") {
    CHECK_THAT(error_of("<model><comment>\nx\xE9</comment>" + kOneMass + "</model>"),
               Catch::StartsWith("test.xml:2:2:") && Catch::Contains("UTF-8") && Catch::Contains("0xE9"));
  }
  SECTION("an unsupported encoding is named") {
    CHECK_THAT(error_of("<?xml version=\"1.0\" encoding=\"EBCDIC\"?><model/>"),
               Catch::Contains("encoding") && Catch::Contains("'EBCDIC'"));
  }
  SECTION("a raw control character is an error") {
    CHECK_THAT(error_of("<model>\n<comment>a\x02</comment>" + kOneMass + "</model>"),
               Catch::StartsWith("test.xml:2:11:") && Catch::Contains("U+0002"));
  }
  SECTION("a forbidden character reference in a comment becomes U+FFFD with a warning") {
    const auto m = read_text("<model><comment>a&#1;b</comment>" + kOneMass + "</model>");
    CHECK(m.def.comment ==
          "a\xEF\xBF\xBD"
          "b");
    CHECK(m.warnings.size() == 1);
  }
  SECTION("CR LF line ends count as one line end") {
    CHECK_THAT(
        error_of("<model>\r\n<environment\r\n gravity=\"-1\"/>" + kOneMass + "</model>"),
        Catch::StartsWith("test.xml:3:2: <environment> attribute 'gravity'") && Catch::Contains("'-1'"));
  }
}

// --- malformed input --------------------------------------------------------------------

TEST_CASE("malformed v1 input is rejected with a precise message", "[model_file]") {
  REQUIRE(read_text(with_line(1, base_lines()[0])).def.links.size() == 1); // the base text is valid

  struct Case {
    const char* what;
    std::string text;
    std::vector<std::string> expected; // substrings of the message
  };
  const std::vector<Case> cases = {
      {"truncated XML",
       with_line(1, base_lines()[0])
           .substr(0, with_line(1, base_lines()[0]).find("vx=\"0\" vy=\"0\"/>\n<mass id=\"m1\"")),
       {"test.xml:5:", "XML syntax error"}},
      {"unknown link id",
       with_line(9, "<spring a=\"m0\" b=\"zz\" restlength=\"10\"/>"),
       {"test.xml:9:16: <spring> attribute 'b'", "'zz'", "no such id"}},
      {"missing required attribute",
       with_line(6, "<mass id=\"m1\" x=\"10\" y=\"0\" vx=\"0\"/>"),
       {"test.xml:6:1: <mass id=\"m1\"> attribute 'vy'", "required"}},
      {"missing muscle phase",
       with_line(9, "<muscle a=\"m0\" b=\"m1\" restlength=\"10\" amplitude=\"0.5\"/>"),
       {"test.xml:9:1: <muscle> attribute 'phase'", "required"}},
      {"missing spring rest length",
       with_line(9, "<spring a=\"m0\" b=\"m1\"/>"),
       {"test.xml:9:", "<spring> attribute 'restlength'"}},
      {"junk number",
       with_line(5, "<mass id=\"m0\" x=\"1.5abc\" y=\"0\" vx=\"0\" vy=\"0\"/>"),
       {"test.xml:5:15: <mass id=\"m0\"> attribute 'x'", "got '1.5abc'", "number"}},
      {"nan",
       with_line(5, "<mass id=\"m0\" x=\"0\" y=\"nan\" vx=\"0\" vy=\"0\"/>"),
       {"test.xml:5:", "attribute 'y'", "got 'nan'"}},
      {"inf",
       with_line(5, "<mass id=\"m0\" x=\"0\" y=\"0\" vx=\"inf\" vy=\"0\"/>"),
       {"test.xml:5:", "attribute 'vx'", "got 'inf'"}},
      {"overflow",
       with_line(9, "<spring a=\"m0\" b=\"m1\" restlength=\"1e999\"/>"),
       {"test.xml:9:", "<spring> attribute 'restlength'", "got '1e999'"}},
      {"empty number",
       with_line(5, "<mass id=\"m0\" x=\"\" y=\"0\" vx=\"0\" vy=\"0\"/>"),
       {"test.xml:5:", "attribute 'x'", "got ''"}},
      {"gravity out of range",
       with_line(3, "<environment gravity=\"5\"/>"),
       {"test.xml:3:14: <environment> attribute 'gravity'", "[0, 4]", "got '5'"}},
      {"springyness out of range",
       with_line(3, "<environment springyness=\"-0.1\"/>"),
       {"test.xml:3:", "<environment> attribute 'springyness'", "[0, 0.5]", "got '-0.1'"}},
      {"surface reflection out of range",
       with_line(3, "<collisions surface_reflection=\"0.5\"/>"),
       {"test.xml:3:", "<collisions> attribute 'surface_reflection'", "[-1, 0]", "got '0.5'"}},
      {"negative wave amplitude",
       with_line(3, "<wave amplitude=\"-0.1\"/>"),
       {"test.xml:3:", "<wave> attribute 'amplitude'", "got '-0.1'"}},
      {"bad gravitydirection",
       with_line(3, "<settings gravitydirection=\"sideways\"/>"),
       {"test.xml:3:", "<settings> attribute 'gravitydirection'", "down, up or off", "got 'sideways'"}},
      {"bad wavedirection",
       with_line(3, "<settings wavedirection=\"Forward\"/>"),
       {"test.xml:3:", "attribute 'wavedirection'", "forward, reverse or manual", "got 'Forward'"}},
      {"bad autoreverse",
       with_line(3, "<settings autoreverse=\"yes\"/>"),
       {"test.xml:3:", "attribute 'autoreverse'", "on or off", "got 'yes'"}},
      {"non-integer width",
       with_line(3, "<container width=\"651.5\" height=\"422\"/>"),
       {"test.xml:3:12: <container> attribute 'width'", "integer", "got '651.5'"}},
      {"zero height",
       with_line(3, "<container height=\"0\"/>"),
       {"test.xml:3:", "<container> attribute 'height'", "got '0'"}},
      {"duplicate id",
       with_line(6, "<mass id=\"m0\" x=\"10\" y=\"0\" vx=\"0\" vy=\"0\"/>"),
       {"test.xml:6:7: <mass id=\"m0\"> attribute 'id'", "got 'm0'"}},
      {"duplicate attribute",
       with_line(6, "<mass id=\"m1\" x=\"10\" x=\"11\" y=\"0\" vx=\"0\" vy=\"0\"/>"),
       {"test.xml:6:", "attribute 'x'", "twice"}},
      {"duplicate header element",
       with_line(7, "</nodes><environment friction=\"0.1\"/>"),
       {"test.xml:7:9: <environment>", "second", "test.xml:3:1"}},
      {"empty model", "<model>\n<nodes>\n</nodes>\n</model>\n", {"test.xml:2:1: <nodes>", "empty model"}},
      {"model without nodes",
       "<model>\n<comment>x</comment>\n</model>\n",
       {"test.xml:1:1: <model>", "empty model"}},
      {"wrong root element",
       "<?xml version=\"1.0\"?>\n<creature/>\n",
       {"test.xml:2:1: <creature>", "<model>", "got <creature>"}},
      {"race file",
       "<?xml version=\"1.0\"?>\n<!DOCTYPE sodarace>\n<race racer=\"racer.Racer\"><timeout "
       "value=\"1\"/></race>\n",
       {"test.xml:3:1:", "Sodarace race file (<race>), not a model; race files are not supported yet"}},
      {"empty text", "", {"test.xml:1:1:", "XML syntax error"}},
      {"mismatched tags", with_line(7, "</node>"), {"test.xml:7:", "XML syntax error"}},
  };
  for (const Case& c : cases) {
    INFO(c.what);
    const std::string msg = error_of(c.text);
    INFO(msg);
    for (const std::string& e : c.expected) CHECK(contains(msg, e));
  }
}

TEST_CASE("v2 files: mapping, clamping and malformed input", "[model_file]") {
  SECTION("a minimal v2 file maps onto the v1 model") {
    const auto m =
        read_text(v2_text("<field name=\"comment\"><string /></field>\n"
                          "<field name=\"gravityDirection\"><int>-1</int></field>\n"
                          "<field name=\"autoReverse\"><boolean>false</boolean></field>\n"
                          "<field name=\"metadata\"><object id=\"Metadata#1\" "
                          "type=\"com.sodaplay.soda.constructor2.model.Metadata\"/></field>\n"
                          "<field name=\"wave\"><object id=\"Wave#1\" "
                          "type=\"com.sodaplay.soda.constructor2.model.Wave\">"
                          "<field name=\"direction\"><string>manual</string></field>"
                          "<field name=\"phase\"><double>1.5</double></field></object></field>\n",
                          "", v2_spring("Mass#2", "Mass#1")));
    CHECK(m.format == soda::ModelFormat::V2);
    CHECK(m.warnings.empty());
    CHECK(m.def.settings.gravity_direction == soda::GravityDirection::Up);
    CHECK(!m.def.settings.autoreverse);
    CHECK(m.def.settings.wave_direction == soda::WaveDirection::Manual);
    CHECK(m.def.wave.phase == 0.5);
    CHECK(m.def.wave.speed == 0.01); // default: not in the file
    CHECK(m.def.width == 651);
    REQUIRE(m.def.nodes.size() == 2);
    CHECK(m.def.nodes[1] == NodeDef{"Mass#2", false, 10.0, 0.0, 0.0, 0.0});
    REQUIRE(m.def.links.size() == 1);
    CHECK(m.def.links[0] == LinkDef{LinkKind::Spring, 1, 0, 10.0, 0.0, 0.0});
  }
  SECTION("gravityDirection 0 is off") {
    const auto m = read_text(v2_text("<field name=\"gravityDirection\"><int>0</int></field>\n"));
    CHECK(m.def.settings.gravity_direction == soda::GravityDirection::Off);
  }
  SECTION("values outside the v1 ranges are clamped with a warning") {
    const auto m =
        read_text(v2_text("<field name=\"gravity\"><double>7.5</double></field>\n"
                          "<field name=\"surfaceReflection\"><double>0.25</double></field>\n",
                          "",
                          "<object id=\"Muscle#1\" type=\"com.sodaplay.soda.constructor2.model.Muscle\">"
                          "<field name=\"a\"><ref refid=\"Mass#1\" /></field>"
                          "<field name=\"amplitude\"><double>1.5</double></field>"
                          "<field name=\"b\"><ref refid=\"Mass#2\" /></field>"
                          "<field name=\"phase\"><double>-0.25</double></field>"
                          "<field name=\"restLength\"><double>10.0</double></field></object>\n"));
    CHECK(m.def.environment.gravity == 4.0);
    CHECK(m.def.collisions.surface_reflection == 0.0);
    REQUIRE(m.def.links.size() == 1);
    CHECK(m.def.links[0].amplitude == 1.0);
    CHECK(m.def.links[0].phase == 0.75);
    REQUIRE(m.warnings.size() == 3);
    CHECK_THAT(m.warnings[0], Catch::StartsWith("test.xml:4:1: <field name=\"gravity\">") &&
                                  Catch::Contains("7.5") && Catch::Contains("[0, 4]") &&
                                  Catch::Contains("clamped to 4") && Catch::Contains("reject"));
    CHECK_THAT(m.warnings[1], Catch::Contains("surfaceReflection") && Catch::Contains("[-1, 0]"));
    CHECK_THAT(m.warnings[2], Catch::Contains("amplitude") && Catch::Contains("1.5"));
  }
  SECTION("a fixed Node in v2") {
    const auto m =
        read_text(v2_text("",
                          "<object id=\"Node#1\" type=\"com.sodaplay.soda.constructor2.model.Node\">"
                          "<field name=\"x\"><double>3</double></field>"
                          "<field name=\"y\"><double>424</double></field></object>\n"));
    REQUIRE(m.def.nodes.size() == 3);
    CHECK(m.def.nodes[2] == NodeDef{"Node#1", true, 3.0, 424.0, 0.0, 0.0});
  }

  struct Case {
    const char* what;
    std::string text;
    std::vector<std::string> expected;
  };
  const std::vector<Case> cases = {
      {"unknown refid",
       v2_text("", "", v2_spring("Mass#1", "Mass#9")),
       {"<ref> attribute 'refid'", "'Mass#9'", "no such object"}},
      {"bad gravityDirection",
       v2_text("<field name=\"gravityDirection\"><int>2</int></field>\n"),
       {"test.xml:4:1: <field name=\"gravityDirection\">", "1 (down), -1 (up) or 0 (off)", "got '2'"}},
      {"gravityDirection not an int",
       v2_text("<field name=\"gravityDirection\"><double>1.0</double></field>\n"),
       {"<field name=\"gravityDirection\">", "expected a <int>", "got <double>"}},
      {"non-integer width",
       v2_text("<field name=\"width\"><int>651.0</int></field>\n"),
       {"test.xml:4:1: <field name=\"width\">", "integer", "got '651.0'"}},
      {"junk double",
       v2_text("<field name=\"friction\"><double>0.1x</double></field>\n"),
       {"<field name=\"friction\">", "got '0.1x'"}},
      {"NaN is not clamped",
       v2_text("<field name=\"gravity\"><double>NaN</double></field>\n"),
       {"<field name=\"gravity\">", "got 'NaN'"}},
      {"bad wave direction",
       v2_text(
           "<field name=\"wave\"><object id=\"Wave#1\" type=\"com.sodaplay.soda.constructor2.model.Wave\">"
           "<field name=\"direction\"><string>sideways</string></field></object></field>\n"),
       {"<field name=\"direction\">", "forward, reverse or manual", "got 'sideways'"}},
      {"bad boolean",
       v2_text("<field name=\"autoReverse\"><boolean>yes</boolean></field>\n"),
       {"<field name=\"autoReverse\">", "true or false", "got 'yes'"}},
      {"unknown object type in springs",
       v2_text("", "",
               "<object id=\"Bar#1\" type=\"com.sodaplay.soda.constructor2.model.Bar\">"
               "<field name=\"a\"><ref refid=\"Mass#1\" /></field></object>\n"),
       {"<object id=\"Bar#1\"> attribute 'type'", "'com.sodaplay.soda.constructor2.model.Bar'"}},
      {"unknown object type in nodes",
       v2_text("", "<object id=\"Ghost#1\" type=\"com.sodaplay.soda.constructor2.model.Ghost\"/>\n"),
       {"<object id=\"Ghost#1\"> attribute 'type'", "Ghost'"}},
      {"missing field of a Mass",
       v2_text("",
               "<object id=\"Mass#3\" type=\"com.sodaplay.soda.constructor2.model.Mass\">"
               "<field name=\"x\"><double>3</double></field>"
               "<field name=\"y\"><double>3</double></field></object>\n"),
       {"<object id=\"Mass#3\">", "'vx'"}},
      {"duplicate object id",
       v2_text("",
               "<object id=\"Mass#1\" type=\"com.sodaplay.soda.constructor2.model.Node\">"
               "<field name=\"x\"><double>3</double></field>"
               "<field name=\"y\"><double>3</double></field></object>\n"),
       {"<object id=\"Mass#1\"> attribute 'id'", "got 'Mass#1'"}},
      {"self-link",
       v2_text("", "", v2_spring("Mass#2", "Mass#2")),
       {"<object id=\"Spring#1\">", "two different nodes", "'Mass#2'"}},
      {"duplicate field",
       v2_text("<field name=\"gravity\"><double>1</double></field>\n"
               "<field name=\"gravity\"><double>2</double></field>\n"),
       {"test.xml:5:1: <field name=\"gravity\">", "second", "test.xml:4:1"}},
      {"wrong root object type",
       "<object id=\"X#1\" type=\"com.example.Thing\"/>",
       {"test.xml:1:18: <object id=\"X#1\"> attribute 'type'", "'com.example.Thing'"}},
      {"empty v2 model",
       "<object id=\"M#1\" type=\"com.sodaplay.soda.constructor2.model.Model\">\n"
       "<field name=\"nodes\"><list class=\"java.util.Vector\" /></field>\n</object>",
       {"test.xml:2:1: <field name=\"nodes\">", "empty model"}},
  };
  for (const Case& c : cases) {
    INFO(c.what);
    const std::string msg = error_of(c.text);
    INFO(msg);
    for (const std::string& e : c.expected) CHECK(contains(msg, e));
  }
}
