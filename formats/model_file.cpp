// Reading model files: the file, its format (by the root element), the readers.

#include "formats/model_file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include "core/constants.hpp"
#include "core/input_error.hpp"
#include "formats/xml_util.hpp"

namespace soda {

namespace {

constexpr std::size_t kMaxFileBytes = static_cast<std::size_t>(kMaxModelBytes);

} // namespace

LoadedModel read_model_text(std::string_view text, const std::string& source_name) {
  if (text.size() > kMaxFileBytes) {
    throw InputError(source_name + ": cannot read model: it is larger than " +
                     std::to_string(kMaxFileBytes >> 20) + " MiB, far more than any model");
  }
  const xml::SourceText source(text, source_name);
  pugi::xml_document doc;
  source.parse(doc);

  LoadedModel loaded;
  xml::ReadContext ctx(source, loaded.warnings);
  pugi::xml_node root;
  for (pugi::xml_node child : doc.children()) {
    if (child.type() != pugi::node_element) continue;
    if (root)
      ctx.fail(child, nullptr,
               "expected one root element, got a second one after <" + std::string(root.name()) + ">");
    root = child;
  }
  // pugixml reports a document without any element as a syntax error, so root exists.
  const std::string_view tag = root.name();
  if (tag == "model") {
    loaded.format = ModelFormat::V1;
    xml::read_v1_model(ctx, root, loaded.def);
  } else if (tag == "object") {
    loaded.format = ModelFormat::V2;
    xml::read_v2_model(ctx, root, loaded.def);
  } else if (tag == "race") {
    throw InputError(
        ctx.where(root) +
        ": this is a Sodarace race file (<race>), not a model; race files are not supported yet");
  } else {
    ctx.fail(root, nullptr,
             "expected a SodaConstructor model as the root element: <model> (v1) or "
             "<object type=\"com.sodaplay.soda.constructor2.ConstructorApplication\"> (v2), got <" +
                 std::string(tag) + ">");
  }
  ctx.finish();
  return loaded;
}

LoadedModel read_model_file(const std::filesystem::path& path) {
  // An empty path would otherwise report ": cannot open model file", naming nothing.
  if (path.empty()) throw InputError("model file: expected a path, got an empty one");
  const std::string name = path.string();
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw InputError(name + ": cannot read model file: it is a directory");
  }
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (!ec && size > kMaxFileBytes) {
    throw InputError(name + ": cannot read model file: it is larger than " +
                     std::to_string(kMaxFileBytes >> 20) + " MiB, far more than any model");
  }
  struct Closer {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  std::unique_ptr<std::FILE, Closer> file(std::fopen(path.c_str(), "rb"));
  if (!file) throw InputError(name + ": cannot open model file: " + std::strerror(errno));

  std::string text;
  char buffer[1 << 16];
  for (;;) {
    const std::size_t n = std::fread(buffer, 1, sizeof buffer, file.get());
    if (n < sizeof buffer && std::ferror(file.get())) {
      throw InputError(name + ": cannot read model file: " + std::strerror(errno));
    }
    text.append(buffer, n);
    if (text.size() > kMaxFileBytes) {
      throw InputError(name + ": cannot read model file: it is larger than " +
                       std::to_string(kMaxFileBytes >> 20) + " MiB, far more than any model");
    }
    if (n < sizeof buffer) break;
  }
  return read_model_text(text, name);
}

} // namespace soda
