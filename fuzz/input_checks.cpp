#include "fuzz/input_checks.hpp"

#include "core/input_error.hpp"
#include "core/model.hpp"
#include "evolve/config/run_config.hpp"
#include "evolve/store/run_store.hpp"
#include "formats/model_file.hpp"

namespace sodaevo::fuzz {

namespace {

template <typename Read>
CheckResult run_reader(Read&& read) {
  CheckResult r;
  try {
    read();
    r.accepted = true;
  } catch (const soda::InputError& e) {
    r.error = e.what();
    if (r.error.empty()) throw PropertyViolation("InputError with an empty message");
  }
  return r;
}

} // namespace

CheckResult check_model_xml(std::string_view bytes) {
  return run_reader([&] {
    const soda::LoadedModel loaded = soda::read_model_text(bytes, "fuzz.xml");
    const std::string written = soda::write_model_text(loaded.def);
    soda::LoadedModel again;
    try {
      again = soda::read_model_text(written, "rewritten.xml");
    } catch (const soda::InputError& e) {
      throw PropertyViolation(std::string("a loaded model, written, does not read back: ") + e.what());
    }
    if (!(again.def == soda::canonical_form(loaded.def))) {
      throw PropertyViolation("a loaded model, written and read back, differs from its canonical form");
    }
    try {
      (void)soda::build_model(loaded.def);
    } catch (const soda::InputError&) {
      // a model may be readable but not buildable (the message is the point)
    }
  });
}

CheckResult check_run_config(std::string_view bytes) {
  return run_reader([&] {
    const std::string text(bytes);
    const RunConfig config = parse_run_config(text, "fuzz.json", "/nonexistent-sodaevo-fuzz");
    RunConfig again;
    try {
      again = parse_run_config(to_json(config).dump(), "resolved.json", "/nonexistent-sodaevo-fuzz");
    } catch (const soda::InputError& e) {
      throw PropertyViolation(std::string("an accepted config's resolved form is refused: ") + e.what());
    }
    if (!(again == config)) throw PropertyViolation("an accepted config's resolved form reads back different");
  });
}

CheckResult check_checkpoint(std::string_view bytes) {
  return run_reader([&] {
    const Checkpoint c = parse_checkpoint(std::string(bytes), "checkpoint.json");
    Generation again;
    try {
      again = generation_from_xml(generation_to_xml(c.generation), "rewritten.xml");
    } catch (const soda::InputError& e) {
      throw PropertyViolation(std::string("an accepted checkpoint's generation does not read back: ") + e.what());
    }
    if (again.index != c.generation.index || again.individuals.size() != c.generation.individuals.size()) {
      throw PropertyViolation("an accepted checkpoint's generation reads back with a different size or index");
    }
    for (std::size_t i = 0; i < again.individuals.size(); ++i) {
      const Individual& a = c.generation.individuals[i];
      const Individual& b = again.individuals[i];
      // Saved creatures are written in canonical form (the genome always is).
      if (a.id != b.id || a.parents != b.parents || !(soda::canonical_form(a.creature) == b.creature) ||
          a.evaluation.status != b.evaluation.status) {
        throw PropertyViolation("creature " + a.id + " of an accepted checkpoint reads back different");
      }
    }
  });
}

} // namespace sodaevo::fuzz
