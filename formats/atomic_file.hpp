// Writing files so that a reader (or a crash) never sees half of one: the text
// goes to a temporary file beside the target, is flushed to disk, then renamed
// over the target (rename is atomic within a file system).
#pragma once

#include <filesystem>
#include <string_view>

namespace soda {

/// Throws InputError naming the path and the system's reason on failure; the
/// previous content of `path`, if any, is then left untouched.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);

/// Reads a whole file. Throws InputError naming the path if it cannot.
std::string read_whole_file(const std::filesystem::path& path);

} // namespace soda
