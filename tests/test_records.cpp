// `sodaevo records` (app/records_command.cpp, evolve/runs/record_book.hpp): the record
// book over two race files, with a racer of ours (results/bench/race_flat_champion.xml)
// and public contenders whose results are the original racer's
// (tests/data/terrain/races.tsv, an independent source).
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "test_support.hpp"

using namespace sodaevo::test;
namespace fs = std::filesystem;

TEST_CASE("records: the book names the record and the best public contender with the original racer's frames",
          "[records][race]") {
  const fs::path dir = fresh_temp_dir("records");
  const fs::path root = models_dir().parent_path();
  fs::create_directories(dir / "terrains");
  fs::create_directories(dir / "ours");
  fs::copy_file(models_dir() / "terrains" / "TerrainFlat.xml", dir / "terrains" / "TerrainFlat.xml");
  fs::copy_file(models_dir() / "terrains" / "race08.xml", dir / "terrains" / "race08.xml");
  fs::copy_file(root / "results" / "bench" / "race_flat_champion.xml", dir / "ours" / "flat.xml");
  std::ofstream(dir / "ours" / "flat.json") << R"({"config": "configs/sodarace_flat.json", "seed": 1, "generations": 300, "wall_seconds": 25})";
  const fs::path walker = data_dir() / "terrain" / "contenders" / "walker_430.xml";
  const fs::path slug = data_dir() / "soda" / "golden" / "carefulslug_v2converted_wide100000.xml";
  std::ofstream(dir / "public.txt") << "# two golden contenders\n" << walker.string() << "\n" << slug.string() << "  \n";
  const ShellResult r = run_sodaevo("records --terrains " + (dir / "terrains").string() + " --candidates " +
                                    (dir / "ours").string() + " --public " + (dir / "public.txt").string() +
                                    " --out " + (dir / "book").string() + " --replicas 4 --threads 2");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  std::ifstream in(dir / "book" / "records.json");
  const nlohmann::json book = nlohmann::json::parse(in);
  REQUIRE(book["records"].size() == 2);
  const nlohmann::json& flat = book["records"][0];
  CHECK(flat["race_file"] == "TerrainFlat.xml");
  CHECK(flat["frames"] == 62.0); // results/bench/race_flat.md
  CHECK(flat["best_public"] == walker.string());
  CHECK(flat["best_public_frames"] == 769.0); // races.tsv: walker_430 on TerrainFlat, the original racer
  CHECK(flat["ratio"] == 62.0 / 769.0);
  CHECK(flat["how_found"]["generations"] == 300);
  // race08: nothing here finishes; the best public contender still listed, no ratio.
  const nlohmann::json& hard = book["records"][1];
  CHECK(hard["race_file"] == "race08.xml");
  CHECK(hard["racer"].is_null());
  CHECK_FALSE(hard.contains("ratio"));
  CHECK(book["generalist"]["racer"] == (dir / "ours" / "flat.xml").string());
  std::ifstream md(dir / "book" / "README.md");
  const std::string text((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  CHECK_THAT(text, Catch::Contains("| TerrainFlat.xml | `") && Catch::Contains("| **62** |") &&
                       Catch::Contains("configs/sodarace_flat.json`, seed 1, 300 generations"));
  // The page opens with the table: each file linked to its races, the record's
  // frames, the public contender's (the original racer's 769) and the ratio.
  std::ifstream page_in(dir / "book" / "index.html");
  const std::string page((std::istreambuf_iterator<char>(page_in)), std::istreambuf_iterator<char>());
  CHECK_THAT(page, Catch::Contains("<a href=\"#TerrainFlat.xml\">TerrainFlat.xml</a></td><td>flat.xml</td><td class=\"n\"><b>62</b>") &&
                       Catch::Contains("<td>walker_430.xml</td><td class=\"n\">769</td><td class=\"n\">0.081</td>") &&
                       Catch::Contains("<a href=\"#race08.xml\">race08.xml</a></td><td colspan=\"3\">none of ours finishes"));
  CHECK(page.find("id=\"TerrainFlat.xml\"") != std::string::npos);

  // A missing public contender is named with the list's line.
  std::ofstream(dir / "bad.txt") << walker.string() << "\nno/such/file.xml\n";
  const ShellResult bad = run_sodaevo("records --terrains " + (dir / "terrains").string() + " --candidates " +
                                      (dir / "ours").string() + " --public " + (dir / "bad.txt").string() +
                                      " --out " + (dir / "book2").string());
  CHECK(bad.exit_code != 0);
  CHECK_THAT(bad.output, Catch::Contains("bad.txt:2: expected an existing contender file, got \"no/such/file.xml\""));
}
