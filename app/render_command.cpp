// sodaevo render: a model's motion as an HTML player or an SVG filmstrip.
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "app/commands.hpp"
#include "app/filmstrip_svg.hpp"
#include "app/motion.hpp"
#include "app/player_html.hpp"
#include "app/stepping_options.hpp"
#include "core/input_error.hpp"
#include "core/number_text.hpp"
#include "formats/atomic_file.hpp"
#include "formats/model_file.hpp"

namespace sodaevo::app {

namespace {

struct RenderOptions {
  std::string model;
  std::string out;
  long long frames = 2000;
  int every = 0;
  int stills = 8;
  SteppingOptions stepping;
};

std::string lower_extension(const std::filesystem::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e;
}

void run_render(const RenderOptions& opt) {
  const std::filesystem::path out(opt.out);
  const std::string ext = lower_extension(out);
  if (ext != ".html" && ext != ".htm" && ext != ".svg") {
    throw soda::InputError(opt.out + ": the output must end in .html (animation player) or .svg (filmstrip)");
  }
  const soda::LoadedModel loaded = soda::read_model_file(opt.model);
  const int every = opt.every > 0 ? opt.every : sample_interval(opt.frames, ext == ".svg" ? 400 : 1000);
  const soda::Stepping stepping = stepping_of(opt.stepping);
  Motion motion = record_motion(loaded.def, opt.frames, every, stepping);
  if (motion.name.empty()) motion.name = std::filesystem::path(opt.model).stem().string();
  std::string text;
  if (ext == ".svg") {
    FilmstripOptions film;
    film.stills = opt.stills;
    text = render_filmstrip_svg(motion, film);
  } else {
    const std::string subtitle = std::filesystem::path(opt.model).filename().string() + ": " + std::to_string(opt.frames) +
                                 " frames in its own world" +
                                 (stepping == soda::Stepping{} ? std::string() : " (" + soda::stepping_label(stepping) + ")") + ", " +
                                 (every == 1 ? std::string("every frame") : "a picture every " + std::to_string(every) + " frames") +
                                 " shown; centroid moved " + soda::format_double_plain(std::round(motion.distance() * 10) / 10) +
                                 " px" + (motion.diverged.empty() ? "" : " (" + motion.diverged + ")") + ".";
    text = render_player_page(motion, motion.name, subtitle);
  }
  soda::write_file_atomically(out, text);
  std::cout << "wrote " << opt.out << " (" << motion.samples() << " pictures of " << motion.masses << " masses, "
            << opt.frames << " frames" << (motion.diverged.empty() ? "" : "; " + motion.diverged) << ")\n";
}

} // namespace

void add_render_command(CLI::App& app) {
  auto opt = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand(
      "render",
      "Watch a model move: run it in the engine (its own world and container, as loaded) and write\n"
      "  OUT.html  one self-contained page (no network) with an animation player: play/pause, speed,\n"
      "            frame slider; the camera follows the creature, the floor shows px from the start;\n"
      "  OUT.svg   a still filmstrip: the creature at evenly spaced frames, one panel each.\n"
      "To keep files small only every K-th frame is kept (see --every) and positions are rounded\n"
      "to 0.1 px. Masses are drawn round, fixed nodes square, springs grey, fixed bars black,\n"
      "muscles red: dark and thick when contracted, pale and thin when stretched.");
  cmd->add_option("model", opt->model, "Model file (SodaConstructor XML, v1 or v2)")->required()->check(non_empty_path());
  cmd->add_option("-o,--out", opt->out, "Output file: .html (player) or .svg (filmstrip)")->required();
  cmd->add_option("--frames", opt->frames, "Frames to simulate")->default_val(2000)->check(CLI::Range(1LL, 10000000LL));
  cmd->add_option("--every", opt->every,
                  "Keep a picture every K frames (0 = automatic: at most 1000 pictures for .html, 400 for .svg)")
      ->default_val(0)
      ->check(CLI::Range(0, 10000000));
  cmd->add_option("--stills", opt->stills, "Panels in an .svg filmstrip")->default_val(8)->check(CLI::Range(1, 100));
  add_stepping_options(cmd, opt->stepping);
  cmd->callback([opt] { run_render(*opt); });
}

} // namespace sodaevo::app
