// A design (ModelDef) and its reader's warnings as bytes, for moving it between
// two WebAssembly engines of the designer: the page's and its worker's
// (web/designer_replicas.js). Reading a big file's XML costs seconds there; the
// worker reads it and hands the page these bytes, which the page takes in a few
// milliseconds. The page's edits go back to the worker the same way, instead of
// being written as XML and read again.
//
// Doubles travel as their bits, so the design that arrives is the one that left,
// to the last bit. The layout is private to one build of the engine (both ends
// are always the same build): a tag, then fields in ModelDef's order, each
// integer 4 bytes and each double 8, little-endian as WebAssembly is; strings as
// a length and their bytes.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "core/model_def.hpp"

namespace soda::web {

std::string design_to_bytes(const ModelDef& design, const std::vector<std::string>& warnings);

/// The design and warnings of design_to_bytes' bytes. Throws InputError for bytes
/// it did not write (a wrong tag, a short buffer, a link to no node).
void design_from_bytes(std::string_view bytes, ModelDef& design, std::vector<std::string>& warnings);

} // namespace soda::web
