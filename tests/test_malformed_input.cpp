// The malformed-input corpus: for each reader a user or a crashed run can feed
// (model XML, run config JSON, checkpoint JSON), the damage real files suffer —
// truncation, wrong types, duplicate ids or keys, enormous numbers, NaN, deep
// nesting, wrong encodings — each with the message it must give. Every expected
// position and text here was worked out by hand from the input, not copied from
// a run. (test_model_file.cpp and test_run_config.cpp hold the format-specific
// cases; this file adds the hostile ones and the limits.)
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "core/constants.hpp"
#include "core/input_error.hpp"
#include "evolve/config/input_limits.hpp"
#include "evolve/config/run_config.hpp"
#include "evolve/store/run_store.hpp"
#include "formats/atomic_file.hpp"
#include "formats/model_file.hpp"
#include "fuzz/input_checks.hpp"
#include "test_support.hpp"

using namespace sodaevo;
namespace fs = std::filesystem;

namespace {

template <typename Read>
std::string error_from(Read&& read) {
  try {
    read();
  } catch (const soda::InputError& e) {
    return e.what();
  }
  FAIL_CHECK("no InputError");
  return "";
}

std::string xml_error(const std::string& text) {
  return error_from([&] { (void)soda::read_model_text(text, "m.xml"); });
}
std::string config_error(const std::string& text) {
  return error_from([&] { (void)parse_run_config(text, "c.json", "/nonexistent"); });
}
std::string checkpoint_error(const std::string& text) {
  return error_from([&] { (void)parse_checkpoint(text, "checkpoint.json"); });
}

std::string repeat(const std::string& s, int n) {
  std::string out;
  for (int i = 0; i < n; ++i) out += s;
  return out;
}

const std::string kTwoMasses =
    "<model>\n<nodes>\n<mass id=\"a\" x=\"1\" y=\"2\" vx=\"0\" vy=\"0\"/>\n"
    "<mass id=\"b\" x=\"5\" y=\"2\" vx=\"0\" vy=\"0\"/>\n</nodes>\n"
    "<links>\n<spring a=\"a\" b=\"b\" restlength=\"4\"/>\n</links>\n</model>\n";

/// A valid checkpoint of one generation holding one creature.
std::string checkpoint_text(const std::string& generation_attr = "1", const std::string& extra_json = "",
                            const std::string& model_attrs = "id=\\\"g1-0\\\" parents=\\\"\\\" status=\\\"ok\\\" "
                                                             "fitness=\\\"3.5\\\" distance=\\\"3.5\\\" reason=\\\"\\\"") {
  return "{\"format\":\"sodaevo-checkpoint-1\",\"generation\":1,\"evaluations\":12,\"wall_seconds\":0.5," +
         extra_json + "\"population_xml\":\"<generation index=\\\"" + generation_attr + "\\\">\\n<model " +
         model_attrs +
         "><nodes><mass id=\\\"a\\\" x=\\\"1\\\" y=\\\"2\\\" vx=\\\"0\\\" vy=\\\"0\\\"/>"
         "<mass id=\\\"b\\\" x=\\\"5\\\" y=\\\"2\\\" vx=\\\"0\\\" vy=\\\"0\\\"/></nodes>"
         "<links><spring a=\\\"a\\\" b=\\\"b\\\" restlength=\\\"4\\\"/></links></model>\\n</generation>\\n\"}";
}

} // namespace

TEST_CASE("malformed XML: truncation anywhere gives a syntax error with a position", "[malformed]") {
  REQUIRE_NOTHROW(soda::read_model_text(kTwoMasses, "m.xml"));
  const std::string full = soda::read_whole_file(sodaevo::test::models_dir() / "dainty_walker.xml");
  // Every cut inside the root element; the last one removes only "</model>\n"'s '>'.
  const std::size_t root_end = full.rfind("</model>");
  REQUIRE(root_end != std::string::npos);
  int checked = 0;
  for (std::size_t n = 0; n < root_end + 8; n += (n < 200 || n > root_end - 50) ? 1 : 37) {
    const std::string msg = xml_error(full.substr(0, n));
    INFO("cut after " << n << " bytes: " << msg);
    CHECK(msg.rfind("m.xml:", 0) == 0);
    // Either a syntax error, or a cut before any element was complete enough to read.
    const bool syntax = msg.find("XML syntax error") != std::string::npos;
    const bool encoding = msg.find("XML declaration") != std::string::npos;
    CHECK((syntax || encoding));
    ++checked;
  }
  CHECK(checked > 250);
}

TEST_CASE("malformed XML: hostile inputs and the limits", "[malformed]") {
  struct Case {
    const char* what;
    std::string text;
    std::vector<std::string> expected;
  };
  const std::string deep = "<model>" + repeat("<a>", 200) + repeat("</a>", 200) + "</model>";
  const std::string long_number = repeat("9", 400);
  const std::vector<Case> cases = {
      // <model> is at depth 0, the k-th <a> at depth k: the 100th <a> is the first
      // too deep; it starts after "<model>" (7 bytes) and 99 "<a>" (297): column 305.
      {"nesting deeper than the limit", deep,
       {"m.xml:1:305: <a>: expected elements nested at most 100 levels deep", "got deeper"}},
      {"UTF-16 (little-endian BOM)", std::string("\xFF\xFE<\0m\0", 6), {"m.xml:1:1:", "UTF-16 or UTF-32"}},
      {"UTF-16 without BOM", std::string("\0<\0m\0o", 6), {"m.xml:1:1:", "UTF-16 or UTF-32"}},
      {"UTF-32", std::string("\0\0\0<", 4), {"m.xml:1:1:", "UTF-16 or UTF-32"}},
      {"an unsupported declared encoding", "<?xml version=\"1.0\" encoding=\"Shift_JIS\"?>\n<model/>",
       {"m.xml:1:1: XML declaration attribute 'encoding'", "UTF-8 or ISO-8859-1", "got 'Shift_JIS'"}},
      {"a UTF-8 sequence cut at the end of the file", "<model>\n<comment>caf\xC3", {"m.xml:2:13: invalid UTF-8 byte 0xC3"}},
      {"an overlong UTF-8 encoding of '<'", "<model>\xC0\xBC</model>", {"m.xml:1:8: invalid UTF-8 byte 0xC0"}},
      {"a NUL byte (binary file)", std::string("<model>\0</model>", 16),
       {"m.xml:1:8: character U+0000 is not allowed", "binary file"}},
      {"a number of 400 digits", "<model><nodes><mass id=\"a\" x=\"" + long_number + "\" y=\"0\" vx=\"0\" vy=\"0\"/></nodes></model>",
       // the value is shown cut after 80 characters
       {"m.xml:1:28: <mass id=\"a\"> attribute 'x': expected a finite number, got '" + repeat("9", 80) + "...'"}},
      {"the largest double is a number, one digit more is not",
       "<model><nodes><mass id=\"a\" x=\"1.7976931348623157e308\" y=\"1.8e308\" vx=\"0\" vy=\"0\"/></nodes></model>",
       {"m.xml:1:55: <mass id=\"a\"> attribute 'y': expected a finite number, got '1.8e308'"}},
      {"NaN as a velocity", "<model><nodes><mass id=\"a\" x=\"0\" y=\"0\" vx=\"NaN\" vy=\"0\"/></nodes></model>",
       {"m.xml:1:40: <mass id=\"a\"> attribute 'vx': expected a finite number, got 'NaN'"}},
      {"a container side above int range", "<model><container width=\"99999999999999999999\"/></model>",
       {"m.xml:1:19: <container> attribute 'width': expected an integer in [1, 2000000000]"}},
      {"a wrong type: a word for a rest length",
       "<model><nodes><mass id=\"a\" x=\"0\" y=\"0\" vx=\"0\" vy=\"0\"/><mass id=\"b\" x=\"0\" y=\"1\" vx=\"0\" vy=\"0\"/></nodes>"
       "<links><spring a=\"a\" b=\"b\" restlength=\"long\"/></links></model>",
       {"<spring> attribute 'restlength': expected a finite number, got 'long'"}},
      {"duplicate ids, the second far from the first",
       "<model><nodes>\n<node id=\"n\" x=\"0\" y=\"0\"/>\n" + repeat("<mass id=\"m\" x=\"0\" y=\"0\" vx=\"0\" vy=\"0\"/>\n", 1) +
           "<node id=\"n\" x=\"1\" y=\"1\"/>\n</nodes></model>",
       {"m.xml:4:7: <node id=\"n\"> attribute 'id': expected an id not used before, got 'n' (already the id of the node at index 0)"}},
  };
  for (const Case& c : cases) {
    INFO(c.what);
    const std::string msg = xml_error(c.text);
    INFO(msg);
    for (const std::string& e : c.expected) CHECK(msg.find(e) != std::string::npos);
  }
  SECTION("a text larger than the model size limit is refused before parsing") {
    const std::string huge(static_cast<std::size_t>(soda::kMaxModelBytes) + 1, ' ');
    CHECK(xml_error(huge) == "m.xml: cannot read model: it is larger than 256 MiB, far more than any model");
  }
}

TEST_CASE("malformed config JSON: hostile inputs and the limits", "[malformed]") {
  struct Case {
    const char* what;
    std::string text;
    std::string expected; // the message starts with this
  };
  const std::string rf = R"("population": {"random_fraction": 1})";
  const std::vector<Case> cases = {
      {"truncated in a string", "{\"name\": \"qu", "c.json:1:13: invalid JSON: "},
      {"truncated after a key", "{\n  \"seed\"", "c.json:2:9: invalid JSON: "},
      {"NaN is not JSON", "{\"seed\": NaN}", "c.json:1:10: invalid JSON: "},
      {"Infinity is not JSON", "{\"seed\": Infinity}", "c.json:1:10: invalid JSON: "},
      {"an enormous number", "{\"seed\": 1e400}", "c.json:1:10: invalid JSON: number 1e400 is too large"},
      {"an integer beyond 64 bits",
       "{" + rf + ", \"seed\": 123456789012345678901234567890}",
       "c.json: /seed: expected an integer in [0, 9007199254740992], got 1.2345678901234568e+29"},
      {"a wrong type: a string for a number", "{" + rf + ", \"generations\": \"40\"}",
       "c.json: /generations: expected an integer in [1, 1000000], got \"40\""},
      {"a wrong type: an array for an object", "{\"population\": [1]}",
       "c.json: /population: expected an object with keys "},
      {"a fraction for an integer", "{" + rf + ", \"generations\": 2.5}",
       "c.json: /generations: expected an integer in [1, 1000000], got 2.5"},
      {"duplicate key", "{" + rf + ", \"name\": \"a\", \"name\": \"b\"}", "c.json: /name: duplicate key"},
      // The top-level object is depth 0; the array opened at depth kMaxJsonDepth is refused.
      {"nesting deeper than the limit", "{\"comment\": " + repeat("[", 40) + repeat("]", 40) + "}",
       // the 32nd array, element 0 of the 31st: /comment then 31 times /0
       "c.json: /comment" + repeat("/0", 31) + ": expected JSON nested at most 32 levels deep, got deeper"},
      {"UTF-16", std::string("\xFF\xFE{\0}\0", 6), "c.json:1:1: invalid JSON: "},
      {"invalid UTF-8 in a string", "{\"name\": \"caf\xC3\"}", "c.json:1:"},
      {"a lone surrogate escape", "{\"name\": \"\\ud800\"}", "c.json:1:"},
      {"a NUL byte", std::string("{\"name\"\0: 1}", 12), "c.json:1:8: invalid JSON: "},
      {"not an object at all", "[]", "c.json: (top level): expected an object with keys "},
  };
  for (const Case& c : cases) {
    INFO(c.what);
    const std::string msg = config_error(c.text);
    INFO(msg);
    CHECK(msg.rfind(c.expected, 0) == 0);
  }
  SECTION("too many seed models") {
    std::string list = "[";
    for (std::size_t i = 0; i <= kMaxSeedModels; ++i) list += (i ? ",\"m.xml\"" : "\"m.xml\"");
    list += "]";
    CHECK(config_error("{\"population\": {\"seed_models\": " + list + "}}")
              .rfind("c.json: /population/seed_models: expected at most 10000 model file paths, got 10001", 0) == 0);
  }
  SECTION("thousands of errors are cut to a screenful") {
    std::string list = "[";
    for (int i = 0; i < 500; ++i) list += (i ? ",1" : "1");
    list += "]";
    const std::string msg = config_error("{\"population\": {\"seed_models\": " + list + "}}");
    CHECK(std::count(msg.begin(), msg.end(), '\n') == 50);
    INFO(msg);
    // 500 bad items, 500 errors (the random_fraction rule is not checked against a bad list)
    CHECK(msg.find("c.json: 450 more errors not shown") != std::string::npos);
  }
  SECTION("a config larger than the limit") {
    const std::string huge(kMaxConfigBytes + 1, ' ');
    CHECK(config_error(huge).rfind("c.json: expected a config of at most 1024 KiB", 0) == 0);
  }
}

TEST_CASE("malformed checkpoint JSON: a damaged checkpoint is named, never half-read", "[malformed]") {
  const std::string good = checkpoint_text();
  const Checkpoint c = parse_checkpoint(good, "checkpoint.json");
  REQUIRE(c.generation.index == 1);
  REQUIRE(c.evaluations == 12);
  REQUIRE(c.generation.individuals.size() == 1);
  CHECK(c.generation.individuals[0].evaluation.fitness == 3.5);

  SECTION("truncated anywhere") {
    for (std::size_t n = 0; n < good.size(); ++n) {
      const std::string msg = checkpoint_error(good.substr(0, n));
      INFO("cut after " << n << ": " << msg);
      CHECK(msg.rfind("checkpoint.json:1:", 0) == 0);
      CHECK(msg.find("corrupt checkpoint: invalid JSON (truncated or damaged file?)") != std::string::npos);
    }
  }
  struct Case {
    const char* what;
    std::string text;
    std::string expected; // the whole message
  };
  const std::string p = "checkpoint.json: corrupt checkpoint: ";
  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string s = good;
    s.replace(s.find(from), from.size(), to);
    return s;
  };
  const std::vector<Case> cases = {
      {"not an object", "[1]", p + "(top level): expected an object, got [1]"},
      {"another format", replaced("sodaevo-checkpoint-1", "sodaevo-checkpoint-9"),
       p + "/format: expected \"sodaevo-checkpoint-1\", got \"sodaevo-checkpoint-9\""},
      {"a missing key", replaced("\"evaluations\":12,", ""),
       p + "/evaluations: expected an integer in [0, 9007199254740992], got nothing (missing)"},
      {"an unknown key", checkpoint_text("1", "\"extra\":1,"),
       p + "/extra: unknown key (expected format, generation, evaluations, wall_seconds, sine, population_xml)"},
      {"a duplicate key", checkpoint_text("1", "\"generation\":2,"), p + "/generation: duplicate key"},
      {"a generation index too large for an int", replaced("\"generation\":1", "\"generation\":1e30"),
       p + "/generation: expected an integer in [0, 999999], got 1e+30"},
      {"a negative evaluation count", replaced("\"evaluations\":12", "\"evaluations\":-12"),
       p + "/evaluations: expected an integer in [0, 9007199254740992], got -12"},
      {"an evaluation count beyond 64 bits", replaced("\"evaluations\":12", "\"evaluations\":18446744073709551616"),
       p + "/evaluations: expected an integer in [0, 9007199254740992], got 1.8446744073709552e+19"},
      {"a string for a number", replaced("\"wall_seconds\":0.5", "\"wall_seconds\":\"0.5\""),
       p + "/wall_seconds: expected a number >= 0, got \"0.5\""},
      {"NaN", replaced("\"wall_seconds\":0.5", "\"wall_seconds\":NaN"),
       "checkpoint.json:1:81: corrupt checkpoint: invalid JSON (truncated or damaged file?): "},
      {"deep nesting", replaced("\"wall_seconds\":0.5", "\"wall_seconds\":" + repeat("[", 100) + repeat("]", 100)),
       p + "expected JSON nested at most 32 levels deep, got deeper"},
      {"a number for the population",
       R"({"format":"sodaevo-checkpoint-1","generation":1,"evaluations":12,"wall_seconds":0.5,"population_xml":1})",
       p + "/population_xml: expected a string holding a <generation>, got 1"},
      {"an index that does not match", checkpoint_text("2"),
       p + "/generation: expected the index of the saved population (2), got 1"},
      {"a huge generation index in the XML", checkpoint_text("99999999999"),
       p + "checkpoint.json /population_xml:1:1: <generation> attribute 'index': expected an integer in [0, 999999], got '99999999999'"},
      {"a duplicate creature id",
       replaced("</model>\\n</generation>",
                "</model><model id=\\\"g1-0\\\" status=\\\"ok\\\" fitness=\\\"1\\\" distance=\\\"1\\\"/>\\n</generation>"),
       p + "checkpoint.json /population_xml:2:"},
      {"NaN fitness", checkpoint_text("1", "", "id=\\\"g1-0\\\" status=\\\"ok\\\" fitness=\\\"nan\\\" distance=\\\"1\\\""),
       p + "checkpoint.json /population_xml:2:1: <model id=\"g1-0\">: fitness: expected a finite number, got 'nan'"},
      {"an unknown status", checkpoint_text("1", "", "id=\\\"g1-0\\\" status=\\\"great\\\" fitness=\\\"1\\\" distance=\\\"1\\\""),
       p + "checkpoint.json /population_xml:2:1: <model id=\"g1-0\">: status: expected ok, invalid or diverged, got 'great'"},
      {"an empty population", replaced(good.substr(good.find("<model "), good.find("</generation>") - good.find("<model ")), ""),
       p + "/population_xml: expected at least one creature, got none"},
  };
  for (const Case& c : cases) {
    INFO(c.what);
    const std::string msg = checkpoint_error(c.text);
    INFO(msg);
    CHECK(msg.rfind(c.expected, 0) == 0);
  }
}

TEST_CASE("every regression input found by fuzzing is handled cleanly", "[malformed][fuzz]") {
  // tests/data/fuzz_regressions/<target>/: inputs that once crashed, hung or broke
  // a property (fuzz/README.md). Each must now load or give an InputError.
  const fs::path root = sodaevo::test::data_dir() / "fuzz_regressions";
  int files = 0;
  for (const char* target : {"model_xml", "run_config", "checkpoint"}) {
    for (const fs::directory_entry& e : fs::directory_iterator(root / target)) {
      if (!e.is_regular_file() || e.path().filename() == "README.md") continue;
      INFO(e.path().string());
      const std::string bytes = soda::read_whole_file(e.path());
      const std::string t = target;
      fuzz::CheckResult r;
      REQUIRE_NOTHROW(r = t == "model_xml"    ? fuzz::check_model_xml(bytes)
                          : t == "run_config" ? fuzz::check_run_config(bytes)
                                              : fuzz::check_checkpoint(bytes));
      if (!r.accepted) CHECK(!r.error.empty());
      ++files;
    }
  }
  CHECK(files >= 3);
}

TEST_CASE("the fuzz properties hold on every real model and config", "[malformed][fuzz]") {
  // The seeds of the fuzz targets: what must hold for any input holds for these.
  int accepted = 0;
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(sodaevo::test::data_dir() / "soda")) {
    if (e.path().extension() != ".xml") continue;
    INFO(e.path().string());
    fuzz::CheckResult r;
    REQUIRE_NOTHROW(r = fuzz::check_model_xml(soda::read_whole_file(e.path())));
    accepted += r.accepted ? 1 : 0;
  }
  CHECK(accepted >= 30);
  for (const fs::directory_entry& e : fs::directory_iterator(fs::path(SODAEVO_MODELS_DIR) / "../configs")) {
    if (e.path().extension() != ".json") continue;
    INFO(e.path().string());
    fuzz::CheckResult r;
    REQUIRE_NOTHROW(r = fuzz::check_run_config(soda::read_whole_file(e.path())));
    // parse_run_config resolves seed models against a folder that does not exist
    // here, so configs naming some are refused for that reason only.
    if (!r.accepted) CHECK(r.error.rfind("fuzz.json: /population/seed_models/0: expected ", 0) == 0);
  }
  fuzz::CheckResult r;
  REQUIRE_NOTHROW(r = fuzz::check_checkpoint(checkpoint_text()));
  CHECK(r.accepted);
}
