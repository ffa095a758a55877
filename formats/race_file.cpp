// Reader of Sodarace race files (race_file.hpp). The models inside are v1 <model>
// elements, read by the v1 reader with positions in this file.

#include "formats/race_file.hpp"

#include <cstring>
#include <fstream>
#include <sstream>

#include "core/constants.hpp"
#include "core/input_error.hpp"
#include "core/number_text.hpp"
#include "formats/xml_util.hpp"

namespace soda {

namespace {

constexpr const char* kRacerClass = "racer.Racer";
constexpr const char* kTerrainFilter = "racer.FilterFixedBars";
constexpr const char* kContenderFilter = "racer.FilterScaledSquare";

/// The one child element `tag` of `parent`, or an empty node; a second one is an error.
pugi::xml_node only_child(const xml::ReadContext& ctx, pugi::xml_node parent, const char* tag) {
  pugi::xml_node found;
  for (pugi::xml_node c : parent.children(tag)) {
    if (found) ctx.fail(c, nullptr, "expected one <" + std::string(tag) + "> in <" + parent.name() + ">, got a second");
    found = c;
  }
  return found;
}

/// An attribute that, when present, must have the value `expected`.
void require_value(const xml::ReadContext& ctx, pugi::xml_node e, const char* attribute, const char* expected,
                   const char* what) {
  pugi::xml_attribute a = e.attribute(attribute);
  if (a && std::strcmp(a.value(), expected) != 0) {
    ctx.fail(e, attribute, std::string("expected ") + what + " " + xml::quote(expected) + ", got " +
                               xml::quote(a.value()));
  }
}

RaceSource read_source(const xml::ReadContext& ctx, pugi::xml_node e, const char* attribute) {
  pugi::xml_attribute a = e.attribute(attribute);
  if (!a || std::strcmp(a.value(), "CONTENDER") == 0) return RaceSource::Contender;
  if (std::strcmp(a.value(), "RACER") == 0) return RaceSource::Racer;
  ctx.fail(e, attribute, "expected CONTENDER or RACER, got " + xml::quote(a.value()));
}

void read_constraints(const xml::ReadContext& ctx, pugi::xml_node rc, RaceConstraints& c) {
  if (!rc) return;
  if (pugi::xml_node e = only_child(ctx, rc, "environment")) {
    c.gravity = read_source(ctx, e, "gravity");
    c.friction = read_source(ctx, e, "friction");
    c.springyness = read_source(ctx, e, "springyness");
  }
  if (pugi::xml_node e = only_child(ctx, rc, "collisions")) {
    c.surface_friction = read_source(ctx, e, "surface_friction");
    c.surface_reflection = read_source(ctx, e, "surface_reflection");
  }
  if (pugi::xml_node e = only_child(ctx, rc, "wave")) {
    c.wave_amplitude = read_source(ctx, e, "amplitude");
    c.wave_phase = read_source(ctx, e, "phase");
    c.wave_speed = read_source(ctx, e, "speed");
  }
  if (pugi::xml_node e = only_child(ctx, rc, "settings")) {
    c.gravity_direction = read_source(ctx, e, "gravitydirection");
    c.wave_direction = read_source(ctx, e, "wavedirection");
    c.autoreverse = read_source(ctx, e, "autoreverse");
  }
}

int read_timeout(const xml::ReadContext& ctx, pugi::xml_node race) {
  pugi::xml_node t = only_child(ctx, race, "timeout");
  if (!t) ctx.fail(race, nullptr, "expected a <timeout value=\"frames\"/>, got none");
  pugi::xml_attribute v = t.attribute("value");
  if (!v) ctx.fail(t, "value", "expected an integer number of frames, got nothing");
  const std::optional<long long> frames = parse_integer(v.value());
  if (!frames || *frames < 1 || *frames > kMaxRaceTimeout) {
    ctx.fail(t, "value", "expected an integer in [1, " + std::to_string(kMaxRaceTimeout) +
                             "] (the racer stops after 50000 updates), got " + xml::quote(v.value()));
  }
  return static_cast<int>(*frames);
}

void read_terrain(xml::ReadContext& ctx, pugi::xml_node race, ModelDef& terrain) {
  pugi::xml_node t = only_child(ctx, race, "terrain");
  if (!t) ctx.fail(race, nullptr, "expected a <terrain> with a <model>, got none (a race needs a terrain)");
  require_value(ctx, t, "filter", kTerrainFilter, "the terrain filter");
  pugi::xml_node m = only_child(ctx, t, "model");
  if (!m) ctx.fail(t, nullptr, "expected a <model> (the terrain), got none");
  xml::read_v1_model(ctx, m, terrain);
  double lo = 0.0, hi = 0.0;
  bool any = false;
  for (const NodeDef& n : terrain.nodes) {
    if (!n.fixed) continue;
    lo = any ? std::min(lo, n.x) : n.x;
    hi = any ? std::max(hi, n.x) : n.x;
    any = true;
  }
  if (!any) ctx.fail(m, nullptr, "expected fixed <node>s in the terrain, got none (the lane starts at the leftmost one)");
  // The lane is 50000 px of platform on either side of the terrain.
  if (hi - lo + 100000.0 > static_cast<double>(kMaxContainerSide)) {
    ctx.fail(m, nullptr, "expected a terrain at most " + std::to_string(kMaxContainerSide - 100000) +
                             " px wide (the lane's container), got one " + std::to_string(hi - lo) + " px wide");
  }
}

void read_contenders(xml::ReadContext& ctx, const xml::SourceText& source, pugi::xml_node race, RaceDef& def) {
  pugi::xml_node cs = only_child(ctx, race, "contenders");
  if (!cs) return;
  require_value(ctx, cs, "filter", kContenderFilter, "the contender filter");
  for (pugi::xml_node c : cs.children("contender")) {
    RaceContenderDef contender;
    contender.line = source.locate(c.offset_debug()).line;
    pugi::xml_node m = only_child(ctx, c, "model");
    if (!m) ctx.fail(c, nullptr, "expected a <model> in the <contender>, got none");
    xml::read_v1_model(ctx, m, contender.model);
    if (pugi::xml_node r = only_child(ctx, c, "result")) {
      if (pugi::xml_attribute f = r.attribute("frames")) {
        const std::optional<double> v = parse_double(f.value());
        if (!v) ctx.fail(r, "frames", "expected a number of frames, got " + xml::quote(f.value()));
        contender.recorded_frames = *v;
      }
    }
    def.contenders.push_back(std::move(contender));
  }
}

std::string read_race_file_contents(const std::filesystem::path& path) {
  if (path.empty()) throw InputError("race file: expected a path, got an empty one");
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(path.string() + ": cannot read race file: it is a directory");
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (!ec && size > static_cast<std::uintmax_t>(kMaxModelBytes)) {
    throw InputError(path.string() + ": cannot read race file: it is larger than " +
                     std::to_string(kMaxModelBytes >> 20) + " MiB");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot open race file");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

} // namespace

RaceDef read_race_text(std::string_view text, const std::string& source_name) {
  if (text.size() > static_cast<std::size_t>(kMaxModelBytes)) {
    throw InputError(source_name + ": cannot read race file: it is larger than " +
                     std::to_string(kMaxModelBytes >> 20) + " MiB");
  }
  const xml::SourceText source(text, source_name);
  pugi::xml_document doc;
  source.parse(doc);
  std::vector<std::string> warnings;
  xml::ReadContext ctx(source, warnings);
  pugi::xml_node race = doc.document_element();
  if (std::strcmp(race.name(), "race") != 0) {
    ctx.fail(race, nullptr, "expected a Sodarace race file (root <race>), got <" + std::string(race.name()) + ">");
  }
  require_value(ctx, race, "racer", kRacerClass, "the racer class");
  RaceDef def;
  def.source = source_name;
  def.timeout = read_timeout(ctx, race);
  read_terrain(ctx, race, def.terrain);
  read_constraints(ctx, only_child(ctx, race, "race_constraints"), def.constraints);
  read_contenders(ctx, source, race, def);
  return def;
}

RaceDef read_race_file(const std::filesystem::path& path) {
  return read_race_text(read_race_file_contents(path), path.string());
}

std::string read_race_file_text(const std::filesystem::path& path) { return read_race_file_contents(path); }

bool looks_like_race(std::string_view text) {
  const std::size_t open = text.find("<race");
  if (open == std::string_view::npos) return false;
  const std::size_t model = text.find("<model");
  const std::size_t object = text.find("<object");
  return open < model && open < object;
}

} // namespace soda
