#include "app/designer_page.hpp"

#include <stdexcept>

#include "app/designer_assets.hpp"
#include "app/player_html.hpp"

namespace sodaevo::app {

namespace {

/// The page's scripts in the order they need each other: the engine factory, its
/// API, then the designer's parts (web/README.md).
constexpr const char* kScripts[] = {"soda_engine.js",    "designer_share.js",    "designer_view.js",
                                    "designer_wave_bar.js", "designer_replicas.js", "designer.js",
                                    "evolve_driver.js",  "evolve_workers.js",    "evolve_chart.js",
                                    "designer_evolve.js"};

void replace_marker(std::string& text, const std::string& marker, const std::string& with) {
  const std::size_t at = text.find(marker);
  if (at == std::string::npos) throw std::logic_error("web/designer.html has no marker " + marker);
  text.replace(at, marker.size(), with);
}

std::string asset(std::string_view name) {
  const std::string_view text = designer_asset(name);
  if (text.empty()) throw std::logic_error("the designer's file web/" + std::string(name) + " is not built in");
  return std::string(text);
}

} // namespace

bool designer_available() { return !designer_engine_js().empty(); }

std::string designer_unavailable_reason() {
  return "this sodaevo has no WebAssembly engine for the designer: " + std::string(designer_engine_missing()) +
         ". Install Debian's emscripten (apt-get install emscripten; ./build.sh build does it), then build again";
}

std::string base64url(std::string_view bytes) {
  static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = static_cast<unsigned char>(bytes[i]) << 16 | static_cast<unsigned char>(bytes[i + 1]) << 8 |
                       static_cast<unsigned char>(bytes[i + 2]);
    for (int k = 18; k >= 0; k -= 6) out += alphabet[(v >> k) & 63];
  }
  if (i < bytes.size()) {
    unsigned v = static_cast<unsigned char>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    out += alphabet[(v >> 18) & 63];
    out += alphabet[(v >> 12) & 63];
    if (i + 1 < bytes.size()) out += alphabet[(v >> 6) & 63];
  }
  return out;
}

std::string designer_model_fragment(std::string_view xml_bytes) { return "model=b:" + base64url(xml_bytes); }

std::string designer_page(std::string_view initial_xml, std::string_view initial_name) {
  if (!designer_available()) throw std::runtime_error(designer_unavailable_reason());
  std::string page = asset("designer.html");
  replace_marker(page, "<!--soda:style-->", "<style>\n" + asset("designer.css") + "</style>");
  std::string scripts = "<script type=\"application/json\" id=\"soda-style\">" + creature_style_json() + "</script>\n";
  // The initial model as base64url text: any bytes (latin-1 files too) fit in a script element.
  scripts += "<script type=\"text/plain\" id=\"initial-model\" data-name=\"" + html_escape(std::string(initial_name)) +
             "\">" + base64url(initial_xml) + "</script>\n";
  scripts += "<script id=\"soda-engine\">\n" + std::string(designer_engine_js()) + "\n</script>\n";
  // Evolve mode: the evolution's engine (its text is also each Web Worker's, from a
  // Blob URL) and the files runs are seeded with, as base64url by path.
  if (!designer_evolve_js().empty()) {
    scripts += "<script id=\"soda-evolve-engine\">\n" + std::string(designer_evolve_js()) + "\n</script>\n";
  }
  std::string bundled = "{";
  for (const auto& [path, bytes] : designer_bundled_files()) {
    bundled += std::string(bundled.size() > 1 ? ",\n" : "") + "\"" + std::string(path) + "\":\"" + base64url(bytes) + "\"";
  }
  scripts += "<script type=\"application/json\" id=\"soda-bundled\">" + bundled + "}</script>\n";
  // data-src: a worker takes a script's text (designer_replicas.js).
  for (const char* name : kScripts) scripts += "<script data-src=\"" + std::string(name) + "\">\n" + asset(name) + "\n</script>\n";
  replace_marker(page, "<!--soda:scripts-->", scripts);
  return page;
}

} // namespace sodaevo::app
