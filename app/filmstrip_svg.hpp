// The filmstrip: a still SVG of a creature at regular frames, one panel per frame
// in a row like frames of film. Each panel follows the creature (centred on its
// mass centroid) over the floor, whose distance marks (px from where the
// centroid started) show how far it has walked. Plain SVG 1.1 without scripts or
// CSS, so it shows the same in a browser and in a README on GitHub.
#pragma once

#include <string>

#include "app/motion.hpp"

namespace sodaevo::app {

struct FilmstripOptions {
  int stills = 8;          ///< panels, at evenly spaced samples from the first to the last
  int panel_width = 190;   ///< px
  std::string title;       ///< default: the motion's name
};

std::string render_filmstrip_svg(const Motion& motion, const FilmstripOptions& options = {});

} // namespace sodaevo::app
