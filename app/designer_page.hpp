// The designer: one self-contained page (no network; it opens from a file) with the
// exact engine in WebAssembly, for building, tuning and sharing creatures
// (`sodaevo designer`; web/README.md describes the page and its API).
//
// A model reaches the page in its address: "designer.html#model=b:<base64url of
// the XML file's bytes>" ("z:" instead of "b:" when the page itself compressed
// the XML for a share link). Run reports link every creature that way.
#pragma once

#include <string>
#include <string_view>

namespace sodaevo::app {

/// Whether this binary holds the WebAssembly engine; if not, why (a sentence).
bool designer_available();
std::string designer_unavailable_reason();

/// The page; `initial_xml` (a model file's bytes, may be empty) is the design it
/// opens with when its address names none. Throws std::runtime_error with
/// designer_unavailable_reason() when the engine was not built.
std::string designer_page(std::string_view initial_xml = {}, std::string_view initial_name = {});

/// "model=b:..." for the page's address (after '#'): the model file's bytes.
std::string designer_model_fragment(std::string_view xml_bytes);

/// base64url without padding (RFC 4648 section 5), as the page decodes it.
std::string base64url(std::string_view bytes);

} // namespace sodaevo::app
