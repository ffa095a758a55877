// The designer page's files (web/*.js, *.css, *.html) and the WebAssembly engine,
// built into the binary (web/embed_assets.cmake generates their definitions), so
// `sodaevo designer` works from an installed binary without the source tree.
#pragma once

#include <string_view>
#include <utility>
#include <vector>

namespace sodaevo::app {

/// The text of web/<name> (e.g. "designer.js"); empty if there is no such file.
std::string_view designer_asset(std::string_view name);

/// web/build_wasm.sh's soda_engine_wasm.js; empty when this binary was built
/// without it (then designer_engine_missing() says why).
std::string_view designer_engine_js();
std::string_view designer_engine_missing();
/// web/build_wasm.sh's soda_evolve_wasm.js (the evolution, for Evolve mode); empty
/// when it was not built.
std::string_view designer_evolve_js();
/// Every file of models/ and configs/*.json, by path under the source tree
/// ("models/dainty_walker.xml"), byte for byte: what Evolve mode seeds runs with.
std::vector<std::pair<std::string_view, std::string_view>> designer_bundled_files();

} // namespace sodaevo::app
