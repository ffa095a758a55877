// The animation player: self-contained HTML for watching pre-computed motion.
//
// A page holds the player's style and script once, and one element per player
// with its motion embedded as compact JSON (positions in tenths of a px). The
// script draws on a canvas: the camera follows the creature's centroid over the
// floor, distance marks show px from the start, masses round, fixed nodes square,
// springs grey, fixed bars black, muscles red by contraction (creature_style.hpp);
// play/pause, speed, a frame slider, the frame counter and the distance walked.
// No network, no external scripts.
//
// For tests and screenshots: a URL fragment "#frame=N" stops every player at the
// last sample at or before frame N, and each player then reads its canvas back
// and writes into its element data-frame, data-ink (drawn pixels in the
// creature's box) and data-hash (of those pixels). Script errors are collected
// in <html data-errors="n"> and the #page-errors element.
#pragma once

#include <string>

#include "app/motion.hpp"

namespace sodaevo::app {

/// The motion as the player's JSON (safe inside a <script> element);
/// `scored_from`: the frame from which a fitness counts (-1: none).
std::string motion_json(const Motion& motion, long long scored_from = -1);

/// For <head>: the style and the error catcher (first, so it sees every error).
std::string player_head();

struct PlayerView {
  std::string id;           ///< unique in the page
  std::string caption;      ///< plain text shown above the canvas
  long long scored_from = -1; ///< frame from which the distance counts (marked); -1: none
  int width = 720, height = 300;
};

/// One player element with its motion.
std::string player_element(const Motion& motion, const PlayerView& view);

/// For the end of <body>: the script that starts every player of the page.
std::string player_script();

/// A whole page with one player (what `sodaevo render X.html` writes).
std::string render_player_page(const Motion& motion, const std::string& title, const std::string& subtitle);

/// The creature colours and sizes of creature_style.hpp as JSON for a page's
/// scripts (safe inside a <script> element).
std::string creature_style_json();

/// JSON text made safe inside a <script> element: < > & and the line separators
/// U+2028/9 as \\u escapes (JSON reads them back as the same characters), so no
/// string in it can close the element or open a comment or another script.
std::string script_safe(const std::string& json);

/// Text for HTML content or attributes: & < > " ' escaped.
std::string html_escape(const std::string& text);

} // namespace sodaevo::app
