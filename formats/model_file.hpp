// Reading and writing SodaConstructor model files.
//
// Reading accepts the two model formats and tells them apart by the root element:
//  - v1: `<model>` (SodaConstructor 1.x and Sodarace contenders);
//  - v2: `<object type="com.sodaplay.soda.constructor2.ConstructorApplication">`,
//    the SodaConstructor 2 object graph, mapped onto the v1 model
// (both described in docs/file-formats.md).
// A Sodarace race file (`<race>`) is recognised and refused with a clear message.
//
// The reader is order-independent (the original is not: docs/file-formats.md), applies the
// original's defaults, clamps and wraps, ignores unknown elements, and rejects
// everything else with an InputError naming file:line:column, the element, the
// attribute, what was expected and what it got. Numbers are parsed strictly
// (number_text.hpp).
//
// Writing always produces canonical v1 (docs/file-formats.md): the original's element order
// and layout, the comment escaped (the original did not), numbers shortest
// round-trip, so write -> read is exact.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/model_def.hpp"

namespace soda {

enum class ModelFormat { V1, V2 };

struct LoadedModel {
  ModelDef def;
  ModelFormat format = ModelFormat::V1;
  /// Things the reader changed or noticed but accepted (a clamp, a v2 value
  /// outside the v1 range, an ignored element), each a full sentence with location.
  std::vector<std::string> warnings;
};

/// Parses model XML held in memory. `source_name` is used in messages (a path).
/// Throws InputError.
LoadedModel read_model_text(std::string_view text, const std::string& source_name);

/// Reads a model file. Throws InputError (also for an empty path or a missing or
/// unreadable file).
LoadedModel read_model_file(const std::filesystem::path& path);

/// Canonical v1 XML text of canonical_form(def). Throws InputError if the model
/// holds a value no file may carry (non-finite number).
std::string write_model_text(const ModelDef& def);

/// Writes write_model_text(def) to `path` atomically (a temporary file beside it,
/// then rename), so a reader never sees a half-written file. Throws InputError on
/// I/O failure, naming the path and the system's reason.
void write_model_file(const std::filesystem::path& path, const ModelDef& def);

} // namespace soda
