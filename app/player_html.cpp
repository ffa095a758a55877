#include "app/player_html.hpp"

#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/creature_style.hpp"
#include "charts/svg_chart.hpp"

namespace sodaevo::app {

using charts::svg_escape;

namespace {

long long tenths(double v) { return std::llround(v * 10.0); }

} // namespace

std::string script_safe(const std::string& json) {
  std::string out;
  out.reserve(json.size());
  for (std::size_t i = 0; i < json.size(); ++i) {
    const char c = json[i];
    if (c == '<') out += "\\u003c";
    else if (c == '>') out += "\\u003e";
    else if (c == '&') out += "\\u0026";
    else if (c == '\xE2' && i + 2 < json.size() && json[i + 1] == '\x80' && (json[i + 2] == '\xA8' || json[i + 2] == '\xA9')) {
      out += json[i + 2] == '\xA8' ? "\\u2028" : "\\u2029"; // UTF-8 of U+2028 and U+2029
      i += 2;
    } else {
      out += c;
    }
  }
  return out;
}

std::string creature_style_json() {
  using namespace style;
  nlohmann::json j = {
      {"background", kBackground}, {"floor", kFloor}, {"ground", kGround}, {"tick", kTick}, {"spring", kSpring},
      {"bar", kBar}, {"mass", kMass}, {"fixed", kFixed}, {"massRadius", kMassRadius}, {"fixedSide", kFixedSide},
      {"springWidth", kSpringWidth}, {"barWidth", kBarWidth}, {"muscleRange", kMuscleRange},
      {"muscleContracted", {kMuscleContracted[0], kMuscleContracted[1], kMuscleContracted[2]}},
      {"muscleRest", {kMuscleRest[0], kMuscleRest[1], kMuscleRest[2]}},
      {"muscleStretched", {kMuscleStretched[0], kMuscleStretched[1], kMuscleStretched[2]}},
      {"muscleWidthContracted", kMuscleWidthContracted}, {"muscleWidthStretched", kMuscleWidthStretched}};
  return script_safe(j.dump());
}

namespace {

constexpr const char* kCss = R"css(
.soda-player { display: inline-block; margin: 8px 12px 16px 0; vertical-align: top; }
.soda-player .caption { font-weight: bold; margin: 0 0 4px 0; overflow-wrap: anywhere; }
.soda-player canvas { display: block; border: 1px solid #cfc8bb; border-radius: 6px; max-width: 100%; }
.soda-player .controls { display: flex; align-items: center; gap: 8px; margin-top: 4px; font-size: 13px; }
.soda-player .controls input[type=range] { flex: 1; }
.soda-player .info { font-variant-numeric: tabular-nums; font-size: 13px; color: #333; margin-top: 2px; overflow-wrap: anywhere; }
#page-errors { color: #b00; background: #fee; padding: 8px; }
)css";

constexpr const char* kErrorCatcher = R"js(
window.sodaErrors = [];
function sodaReportError(message) {
  window.sodaErrors.push(String(message));
  document.documentElement.setAttribute('data-errors', String(window.sodaErrors.length));
  var box = document.getElementById('page-errors');
  if (box) { box.hidden = false; box.textContent += message + '\n'; }
}
window.addEventListener('error', function (e) {
  sodaReportError('error: ' + e.message + ' at ' + e.filename + ':' + e.lineno);
});
window.addEventListener('unhandledrejection', function (e) { sodaReportError('unhandled rejection: ' + e.reason); });
(function () {
  var original = console.error;
  console.error = function () {
    sodaReportError('console.error: ' + Array.prototype.join.call(arguments, ' '));
    return original.apply(console, arguments);
  };
})();
)js";

constexpr const char* kPlayerScript = R"js(
(function () {
  'use strict';
  var S = JSON.parse(document.getElementById('soda-style').textContent);
  var params = new URLSearchParams(location.hash.slice(1));
  var stopAt = params.has('frame') ? Number(params.get('frame')) : null;
  var FRAMES_PER_SECOND = 60; // simulated frames per second at speed 1x

  function niceStep(span, count) {
    var raw = Math.max(span / Math.max(count, 1), 1e-9);
    var mag = Math.pow(10, Math.floor(Math.log10(raw)));
    var ms = [1, 2, 5];
    for (var i = 0; i < ms.length; ++i) if (ms[i] * mag >= raw) return ms[i] * mag;
    return 10 * mag;
  }
  function muscleStretch(length, rest) {
    if (!(rest > 0)) return 0;
    return Math.max(-1, Math.min(1, (length / rest - 1) / S.muscleRange));
  }
  function muscleColor(stretch) {
    var to = stretch < 0 ? S.muscleContracted : S.muscleStretched, t = Math.abs(stretch), c = [];
    for (var i = 0; i < 3; ++i) c.push(Math.round(S.muscleRest[i] + (to[i] - S.muscleRest[i]) * t));
    return 'rgb(' + c.join(',') + ')';
  }
  function muscleWidth(stretch) {
    var mid = (S.muscleWidthContracted + S.muscleWidthStretched) / 2;
    return mid + (S.muscleWidthStretched - S.muscleWidthContracted) / 2 * stretch;
  }
  function signedPx(v) { return (v >= 0 ? '+' : '\u2212') + Math.abs(v).toFixed(1) + ' px'; }

  function Player(root) {
    var data = JSON.parse(document.getElementById(root.getAttribute('data-motion')).textContent);
    var canvas = root.querySelector('canvas'), ctx = canvas.getContext('2d');
    var W = canvas.width, H = canvas.height, n = data.frames.length;
    var playButton = root.querySelector('.play'), speedSelect = root.querySelector('.speed');
    var slider = root.querySelector('.slider'), info = root.querySelector('.info');
    var lastFrame = data.frames[n - 1];
    var scoredFrom = data.scored_from;
    var x0 = data.cx[0] / 10;
    // One scale for the whole clip: the reach from the centroid and the height the
    // creature stays within 90% of the time (the camera rises for higher jumps).
    var halves = [], tops = [];
    for (var s = 0; s < n; ++s) {
      var xy = data.xy[s], c = data.cx[s], h = 10, t = 10;
      for (var i = 0; i + 1 < xy.length; i += 2) {
        h = Math.max(h, Math.abs(xy[i] - c) / 10);
        t = Math.max(t, xy[i + 1] / 10);
      }
      halves.push(h);
      tops.push(t);
    }
    function ninetieth(values) { return values.slice().sort(function (a, b) { return a - b; })[Math.floor(0.9 * (n - 1))]; }
    var halfWidth = ninetieth(halves), top = ninetieth(tops);
    if (data.masses === 0) { // a bare scene: fit its fixed nodes
      for (var q = 0; q + 1 < data.fixed.length; q += 2) {
        halfWidth = Math.max(halfWidth, Math.abs(data.fixed[q] - data.cx[0]) / 10);
        top = Math.max(top, data.fixed[q + 1] / 10);
      }
    }
    // The ruler's floor: where the creature stands. In a race that is the terrain's
    // fixed bars (TerrainFlat's lie at y = 10), not the container's floor below them:
    // the floor goes at the bars' lowest end, so a flat terrain lies on the ruler.
    var groundY = Infinity;
    for (var bar = 0; bar + 3 < data.links.length; bar += 4) {
      if (data.links[bar + 2] !== 2) continue;
      [data.links[bar], data.links[bar + 1]].forEach(function (p) {
        if (p >= data.masses) groundY = Math.min(groundY, data.fixed[2 * (p - data.masses) + 1] / 10);
      });
    }
    if (!isFinite(groundY)) groundY = 0;
    var baseFloorY = H - 42;
    var scale = Math.min(W * 0.3 / halfWidth, (baseFloorY - 30) / top);
    var scoredIndex = 0;
    if (scoredFrom >= 0) while (scoredIndex + 1 < n && data.frames[scoredIndex] < scoredFrom) ++scoredIndex;
    var scoredX = data.cx[scoredIndex] / 10;
    slider.max = String(n - 1);

    var index = 0, simFrame = 0, playing = stopAt === null, speed = 1, lastTime = null;

    function point(xy, p) {
      if (p < data.masses) return [xy[2 * p] / 10, xy[2 * p + 1] / 10];
      var q = p - data.masses;
      return [data.fixed[2 * q] / 10, data.fixed[2 * q + 1] / 10];
    }

    // A race's finish line (record_race_motion marks it where the racer's rule ends the race).
    var finishMark = (data.marks || []).filter(function (m) { return m.label === 'finish'; })[0];

    function draw() {
      var xy = data.xy[index], cx = data.cx[index] / 10;
      var floorY = baseFloorY + Math.max(0, tops[index] - top) * scale; // below the canvas while it jumps high
      var sx = function (x) { return W / 2 + (x - cx) * scale; };
      var sy = function (y) { return floorY - (y - groundY) * scale; };
      ctx.fillStyle = S.background; ctx.fillRect(0, 0, W, H);
      ctx.fillStyle = S.ground; ctx.fillRect(0, floorY, W, H - floorY);
      ctx.strokeStyle = S.floor; ctx.lineWidth = 2;
      ctx.beginPath(); ctx.moveTo(0, floorY); ctx.lineTo(W, floorY); ctx.stroke();
      // Distance marks: px from where the centroid started.
      var left = cx - W / 2 / scale, right = cx + W / 2 / scale, step = niceStep(W / scale, 6);
      ctx.font = '11px Helvetica, Arial, sans-serif'; ctx.textAlign = 'center';
      ctx.fillStyle = S.tick; ctx.strokeStyle = S.tick; ctx.lineWidth = 1;
      for (var d = Math.ceil((left - x0) / step) * step; x0 + d <= right; d += step) {
        var tx = sx(x0 + d);
        ctx.beginPath(); ctx.moveTo(tx, floorY); ctx.lineTo(tx, floorY + (d === 0 ? 14 : 7)); ctx.stroke();
        ctx.fillText(d === 0 ? 'start' : String(Math.round(d)), tx, floorY + 26);
      }
      if (scoredFrom > 0 && index >= scoredIndex) {
        var fx = sx(scoredX);
        if (fx >= 0 && fx <= W) { // under the floor, out of the creature's way
          ctx.setLineDash([3, 3]); ctx.beginPath(); ctx.moveTo(fx, floorY); ctx.lineTo(fx, H); ctx.stroke(); ctx.setLineDash([]);
          ctx.textAlign = fx > W - 110 ? 'right' : 'left';
          ctx.fillText(' scoring starts here ', fx, floorY + 38);
        }
      }
      // Marks (a race's start and finish): dashed lines across the scene.
      (data.marks || []).forEach(function (mark) {
        var mx = sx(mark.x / 10);
        if (mx < 0 || mx > W) return;
        ctx.strokeStyle = S.tick; ctx.lineWidth = 1; ctx.setLineDash([6, 4]);
        ctx.beginPath(); ctx.moveTo(mx, 0); ctx.lineTo(mx, floorY); ctx.stroke(); ctx.setLineDash([]);
        ctx.textAlign = 'center'; ctx.fillStyle = S.tick; ctx.fillText(mark.label, mx, 14);
      });
      // Container walls and ceiling, where they are in view.
      ctx.strokeStyle = S.floor; ctx.lineWidth = 3;
      [0, data.width].forEach(function (wx) {
        if (wx >= left && wx <= right) { ctx.beginPath(); ctx.moveTo(sx(wx), 0); ctx.lineTo(sx(wx), floorY); ctx.stroke(); }
      });
      if (sy(data.height) >= 0) { ctx.beginPath(); ctx.moveTo(0, sy(data.height)); ctx.lineTo(W, sy(data.height)); ctx.stroke(); }
      ctx.lineCap = 'round';
      var L = data.links;
      for (var l = 0; l + 3 < L.length; l += 4) {
        var a = point(xy, L[l]), b = point(xy, L[l + 1]), kind = L[l + 2];
        if (kind === 1) {
          var st = muscleStretch(Math.hypot(b[0] - a[0], b[1] - a[1]), L[l + 3] / 10);
          ctx.strokeStyle = muscleColor(st); ctx.lineWidth = muscleWidth(st);
        } else if (kind === 2) {
          ctx.strokeStyle = S.bar; ctx.lineWidth = S.barWidth;
        } else {
          ctx.strokeStyle = S.spring; ctx.lineWidth = S.springWidth;
        }
        ctx.beginPath(); ctx.moveTo(sx(a[0]), sy(a[1])); ctx.lineTo(sx(b[0]), sy(b[1])); ctx.stroke();
      }
      ctx.fillStyle = S.fixed;
      for (var f = 0; f + 1 < data.fixed.length; f += 2) {
        ctx.fillRect(sx(data.fixed[f] / 10) - S.fixedSide / 2, sy(data.fixed[f + 1] / 10) - S.fixedSide / 2, S.fixedSide, S.fixedSide);
      }
      ctx.fillStyle = S.mass;
      for (var m = 0; m + 1 < xy.length; m += 2) {
        ctx.beginPath(); ctx.arc(sx(xy[m] / 10), sy(xy[m + 1] / 10), S.massRadius, 0, 2 * Math.PI); ctx.fill();
      }
      var frame = data.frames[index], moved = cx - x0;
      var text = 'frame ' + frame + ' / ' + lastFrame + '   moved ' + signedPx(moved);
      if (finishMark) { // a race: frames count, not speed; the finish rule takes the rearmost mass
        var rear = Infinity;
        for (var r = 0; r < xy.length; r += 2) rear = Math.min(rear, xy[r] / 10);
        var due = finishMark.x / 10 - rear;
        text += due > 0 ? '   ' + due.toFixed(1) + ' px to the finish' : '   past the finish';
      } else if (frame > 0) {
        text += ' (' + (moved / frame).toFixed(3) + ' px/frame)';
      }
      if (scoredFrom > 0 && index >= scoredIndex) text += '   since scoring ' + signedPx(cx - scoredX);
      if (data.diverged && index === n - 1) text += '   ' + data.diverged;
      info.textContent = text;
      slider.value = String(index);
      if (stopAt !== null) readBack(xy, sx, sy);
    }

    // Pixel read-back of the creature's box, for tests (only with #frame=N).
    function readBack(xy, sx, sy) {
      var x1 = W, y1 = H, x2 = 0, y2 = 0;
      for (var m = 0; m + 1 < xy.length; m += 2) {
        var px = sx(xy[m] / 10), py = sy(xy[m + 1] / 10);
        x1 = Math.min(x1, px); x2 = Math.max(x2, px); y1 = Math.min(y1, py); y2 = Math.max(y2, py);
      }
      x1 = Math.max(0, Math.floor(x1 - 8)); y1 = Math.max(0, Math.floor(y1 - 8));
      x2 = Math.min(W, Math.ceil(x2 + 8)); y2 = Math.min(H, Math.ceil(y2 + 8));
      var ink = 0, hash = 2166136261;
      if (x2 > x1 && y2 > y1) {
        var pixels = ctx.getImageData(x1, y1, x2 - x1, y2 - y1).data;
        var bg = [parseInt(S.background.substr(1, 2), 16), parseInt(S.background.substr(3, 2), 16), parseInt(S.background.substr(5, 2), 16)];
        for (var k = 0; k < pixels.length; k += 4) {
          if (Math.abs(pixels[k] - bg[0]) + Math.abs(pixels[k + 1] - bg[1]) + Math.abs(pixels[k + 2] - bg[2]) > 60) ++ink;
          hash = Math.imul(hash ^ pixels[k], 16777619) >>> 0;
          hash = Math.imul(hash ^ pixels[k + 1], 16777619) >>> 0;
          hash = Math.imul(hash ^ pixels[k + 2], 16777619) >>> 0;
        }
      }
      root.setAttribute('data-frame', String(data.frames[index]));
      root.setAttribute('data-box', [x1, y1, x2, y2].join(','));
      root.setAttribute('data-ink', String(ink));
      root.setAttribute('data-hash', hash.toString(16));
    }

    function indexOfFrame(frame) {
      var i = Math.min(n - 1, Math.max(0, Math.floor(frame / data.every)));
      while (i > 0 && data.frames[i] > frame) --i;
      while (i + 1 < n && data.frames[i + 1] <= frame) ++i;
      return i;
    }
    function setPlaying(on) { playing = on; playButton.textContent = on ? 'Pause' : 'Play'; lastTime = null; }
    playButton.addEventListener('click', function () { setPlaying(!playing); });
    speedSelect.addEventListener('change', function () { speed = Number(speedSelect.value); });
    slider.addEventListener('input', function () {
      setPlaying(false); index = Number(slider.value); simFrame = data.frames[index]; draw();
    });
    function tick(time) {
      if (playing) {
        if (lastTime !== null) {
          simFrame += (time - lastTime) / 1000 * FRAMES_PER_SECOND * speed;
          if (simFrame > lastFrame) simFrame = 0;
          var next = indexOfFrame(simFrame);
          if (next !== index) { index = next; draw(); }
        }
        lastTime = time;
      }
      requestAnimationFrame(tick);
    }
    if (stopAt !== null) { index = indexOfFrame(stopAt); simFrame = data.frames[index]; }
    setPlaying(playing);
    draw();
    root.setAttribute('data-ready', '1');
    requestAnimationFrame(tick);
  }

  var players = document.querySelectorAll('.soda-player');
  for (var p = 0; p < players.length; ++p) {
    try { new Player(players[p]); } catch (e) { sodaReportError('player ' + p + ': ' + e); }
  }
})();
)js";

} // namespace

std::string html_escape(const std::string& text) { return svg_escape(text); }

std::string motion_json(const Motion& m, long long scored_from) {
  nlohmann::json j;
  j["name"] = m.name;
  j["masses"] = m.masses;
  j["width"] = m.width;
  j["height"] = m.height;
  j["every"] = m.every;
  j["scored_from"] = scored_from;
  std::vector<long long> fixed, links, cx;
  for (double v : m.fixed_xy) fixed.push_back(tenths(v));
  for (const MotionLink& l : m.links) {
    links.insert(links.end(), {l.a, l.b, l.kind == soda::LinkKind::Muscle ? 1 : l.kind == soda::LinkKind::FixedBar ? 2 : 0,
                               tenths(l.rest)});
  }
  for (double v : m.centroid_x) cx.push_back(tenths(v));
  j["fixed"] = fixed;
  j["links"] = links;
  j["frames"] = m.sample_frames;
  nlohmann::json xy = nlohmann::json::array();
  for (const std::vector<double>& sample : m.mass_xy) {
    std::vector<long long> row;
    row.reserve(sample.size());
    for (double v : sample) row.push_back(tenths(v));
    xy.push_back(std::move(row));
  }
  j["xy"] = std::move(xy);
  j["cx"] = cx;
  j["diverged"] = m.diverged;
  nlohmann::json marks = nlohmann::json::array();
  for (const MotionMark& mark : m.marks) marks.push_back({{"x", tenths(mark.x)}, {"label", mark.label}});
  j["marks"] = std::move(marks);
  return script_safe(j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
}

std::string player_head() {
  return std::string("<style>") + kCss + "</style>\n<script>" + kErrorCatcher + "</script>\n";
}

std::string player_element(const Motion& motion, const PlayerView& view) {
  const std::string json = motion_json(motion, view.scored_from);
  std::ostringstream o;
  // As wide as the canvas (and its border) at most: a long name wraps instead of
  // stretching the controls.
  o << "<div class=\"soda-player\" id=\"" << html_escape(view.id) << "\" data-motion=\"" << html_escape(view.id)
    << "-motion\" style=\"max-width: " << view.width + 2 << "px\">\n"
    << "<div class=\"caption\">" << html_escape(view.caption) << "</div>\n"
    << "<canvas width=\"" << view.width << "\" height=\"" << view.height << "\"></canvas>\n"
    << "<div class=\"controls\"><button class=\"play\" type=\"button\">Pause</button>"
    << "<label>speed <select class=\"speed\">"
    << "<option value=\"0.25\">0.25&#215;</option><option value=\"0.5\">0.5&#215;</option>"
    << "<option value=\"1\" selected>1&#215;</option><option value=\"2\">2&#215;</option>"
    << "<option value=\"4\">4&#215;</option><option value=\"8\">8&#215;</option></select></label>"
    << "<input class=\"slider\" type=\"range\" min=\"0\" max=\"0\" value=\"0\" aria-label=\"frame\"></div>\n"
    << "<div class=\"info\"></div>\n"
    << "<script type=\"application/json\" id=\"" << html_escape(view.id) << "-motion\">" << json << "</script>\n"
    << "</div>\n";
  return o.str();
}

std::string player_script() {
  return "<script type=\"application/json\" id=\"soda-style\">" + creature_style_json() + "</script>\n<script>" +
         kPlayerScript + "</script>\n";
}

std::string render_player_page(const Motion& motion, const std::string& title, const std::string& subtitle) {
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" << html_escape(title)
    << "</title>\n"
    << "<style>body { font-family: Helvetica, Arial, sans-serif; margin: 20px; color: #222; }</style>\n"
    << player_head() << "</head>\n<body>\n<pre id=\"page-errors\" hidden></pre>\n"
    << "<h1>" << html_escape(title) << "</h1>\n<p>" << html_escape(subtitle) << "</p>\n";
  PlayerView view;
  view.id = "player";
  view.caption = motion.name.empty() ? "creature" : motion.name;
  o << player_element(motion, view) << player_script() << "</body>\n</html>\n";
  return o.str();
}

} // namespace sodaevo::app
