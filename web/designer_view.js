// The stage: the design or the running creature on a canvas, and what is under
// the pointer. World: px, y up, floor at y = 0; one world px is one canvas px.
// Drawn as the player of `sodaevo render` draws (colours of creature_style.hpp):
// masses round, fixed nodes square, springs grey, fixed bars black, muscles red,
// dark and thick when contracted, pale and thin when stretched.
var SodaView = (function () {
  'use strict';
  var FLOOR_MARGIN = 24, PICK_RADIUS = 9, LINK_PICK = 6;

  function Stage(canvas, style) {
    this.canvas = canvas;
    this.ctx = canvas.getContext('2d');
    this.style = style;
    this.cameraX = canvas.width / 2 - 20; // world x at the canvas's centre
  }

  Stage.prototype.toScreen = function (x, y) {
    return [x - this.cameraX + this.canvas.width / 2, this.canvas.height - FLOOR_MARGIN - y];
  };
  Stage.prototype.toWorld = function (sx, sy) {
    return [sx + this.cameraX - this.canvas.width / 2, this.canvas.height - FLOOR_MARGIN - sy];
  };
  /// Canvas coordinates of a pointer event (the canvas may be shown scaled).
  Stage.prototype.eventPoint = function (event) {
    var r = this.canvas.getBoundingClientRect();
    return [(event.clientX - r.left) * this.canvas.width / r.width, (event.clientY - r.top) * this.canvas.height / r.height];
  };

  /// Index of the node nearest canvas point (sx, sy) within reach, or -1.
  Stage.prototype.nodeAt = function (xy, sx, sy) {
    var best = -1, bestD = PICK_RADIUS * PICK_RADIUS;
    for (var i = 0; 2 * i < xy.length; ++i) {
      var p = this.toScreen(xy[2 * i], xy[2 * i + 1]), dx = p[0] - sx, dy = p[1] - sy, d = dx * dx + dy * dy;
      if (d <= bestD) { best = i; bestD = d; }
    }
    return best;
  };

  /// Index of the link nearest canvas point (sx, sy) within reach, or -1.
  Stage.prototype.linkAt = function (design, xy, sx, sy) {
    var best = -1, bestD = LINK_PICK;
    for (var i = 0; i < design.links.length; ++i) {
      var l = design.links[i];
      var a = this.toScreen(xy[2 * l.a], xy[2 * l.a + 1]), b = this.toScreen(xy[2 * l.b], xy[2 * l.b + 1]);
      var dx = b[0] - a[0], dy = b[1] - a[1], len2 = dx * dx + dy * dy;
      var t = len2 > 0 ? Math.max(0, Math.min(1, ((sx - a[0]) * dx + (sy - a[1]) * dy) / len2)) : 0;
      var d = Math.hypot(a[0] + t * dx - sx, a[1] + t * dy - sy);
      if (d < bestD) { best = i; bestD = d; }
    }
    return best;
  };

  function muscleStyle(S, stretch) {
    var to = stretch < 0 ? S.muscleContracted : S.muscleStretched, t = Math.abs(stretch), c = [];
    for (var i = 0; i < 3; ++i) c.push(Math.round(S.muscleRest[i] + (to[i] - S.muscleRest[i]) * t));
    var mid = (S.muscleWidthContracted + S.muscleWidthStretched) / 2;
    return { color: 'rgb(' + c.join(',') + ')', width: mid + (S.muscleWidthStretched - S.muscleWidthContracted) / 2 * stretch };
  }

  Stage.prototype.drawGround = function (design) {
    var ctx = this.ctx, S = this.style, W = this.canvas.width, H = this.canvas.height, floorY = H - FLOOR_MARGIN;
    ctx.fillStyle = S.background;
    ctx.fillRect(0, 0, W, H);
    ctx.fillStyle = S.ground;
    ctx.fillRect(0, floorY, W, FLOOR_MARGIN);
    ctx.strokeStyle = S.floor;
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.moveTo(0, floorY);
    ctx.lineTo(W, floorY);
    ctx.stroke();
    // Ticks every 100 px of world x, labelled.
    ctx.fillStyle = S.tick;
    ctx.font = '10px sans-serif';
    var left = this.toWorld(0, 0)[0], right = this.toWorld(W, 0)[0];
    for (var x = Math.ceil(left / 100) * 100; x <= right; x += 100) {
      var sx = this.toScreen(x, 0)[0];
      ctx.fillRect(sx, floorY, 1, 5);
      // Only whole labels: one cut at the canvas's edge ("2230" as "223") misleads.
      if (sx + 2 + ctx.measureText(String(x)).width <= W) ctx.fillText(String(x), sx + 2, floorY + 15);
    }
    // The container's side walls (the engine bounces masses off them).
    ctx.strokeStyle = S.tick;
    ctx.setLineDash([4, 4]);
    ctx.lineWidth = 1;
    [0, design.width].forEach(function (wx) {
      var sx = this.toScreen(wx, 0)[0];
      if (sx < 0 || sx > W) return;
      ctx.beginPath();
      ctx.moveTo(sx, 0);
      ctx.lineTo(sx, floorY);
      ctx.stroke();
    }, this);
    ctx.setLineDash([]);
  };

  /// Draws the design at positions xy; options: selectedLink, pending {from: [sx, sy], to: [sx, sy]}.
  /// Springs, bars and masses go out as one path each (thousands of strokes would
  /// take a big creature's page tens of milliseconds per picture); muscles, whose
  /// colour and width follow their stretch, one by one, above them.
  Stage.prototype.draw = function (design, xy, options) {
    options = options || {};
    var ctx = this.ctx, S = this.style, links = design.links, nodes = design.nodes;
    this.drawGround(design);
    // Screen coordinates of every node, once (as toScreen gives them).
    var n = nodes.length, sx = new Float64Array(n), sy = new Float64Array(n);
    var cameraX = this.cameraX, half = this.canvas.width / 2, top = this.canvas.height - FLOOR_MARGIN;
    for (var i = 0; i < n; ++i) {
      sx[i] = xy[2 * i] - cameraX + half;
      sy[i] = top - xy[2 * i + 1];
    }
    var segment = function (l) { ctx.moveTo(sx[l.a], sy[l.a]); ctx.lineTo(sx[l.b], sy[l.b]); };
    ctx.lineCap = 'round';
    var selected = links[options.selectedLink];
    if (selected) {
      ctx.strokeStyle = 'rgba(255, 200, 0, 0.8)';
      ctx.lineWidth = 10;
      ctx.beginPath();
      segment(selected);
      ctx.stroke();
    }
    // Square ends: a link ends under its nodes' marks, and round ends cost the
    // picture of a big creature twice the time.
    ctx.lineCap = 'butt';
    [['spring', S.spring, S.springWidth], ['bar', S.bar, S.barWidth]].forEach(function (kind) {
      ctx.beginPath();
      for (var k = 0; k < links.length; ++k) if (links[k].kind === kind[0]) segment(links[k]);
      ctx.strokeStyle = kind[1];
      ctx.lineWidth = kind[2];
      ctx.stroke();
    });
    ctx.lineCap = 'round';
    links.forEach(function (l) {
      if (l.kind !== 'muscle') return;
      var length = Math.hypot(sx[l.b] - sx[l.a], sy[l.b] - sy[l.a]);
      var stretch = l.rest > 0 ? Math.max(-1, Math.min(1, (length / l.rest - 1) / S.muscleRange)) : 0;
      var m = muscleStyle(S, stretch);
      ctx.strokeStyle = m.color;
      ctx.lineWidth = m.width;
      ctx.beginPath();
      segment(l);
      ctx.stroke();
    });
    if (options.pending) {
      ctx.strokeStyle = '#1f4e8c';
      ctx.setLineDash([5, 4]);
      ctx.lineWidth = 1.5;
      ctx.beginPath();
      ctx.moveTo(options.pending.from[0], options.pending.from[1]);
      ctx.lineTo(options.pending.to[0], options.pending.to[1]);
      ctx.stroke();
      ctx.setLineDash([]);
    }
    if (!design.nodes.length) {
      ctx.fillStyle = S.tick;
      ctx.font = '16px sans-serif';
      ctx.textAlign = 'center';
      ctx.fillText('An empty design: click to add a mass, drag from it to add a spring, or open a model.', this.canvas.width / 2, this.canvas.height / 2);
      ctx.textAlign = 'start';
    }
    ctx.fillStyle = S.fixed;
    for (i = 0; i < n; ++i) {
      if (nodes[i].fixed) ctx.fillRect(sx[i] - S.fixedSide / 2, sy[i] - S.fixedSide / 2, S.fixedSide, S.fixedSide);
    }
    ctx.fillStyle = S.mass;
    ctx.beginPath();
    for (i = 0; i < n; ++i) {
      if (nodes[i].fixed) continue;
      ctx.moveTo(sx[i] + S.massRadius, sy[i]);
      ctx.arc(sx[i], sy[i], S.massRadius, 0, 2 * Math.PI);
    }
    ctx.fill();
  };

  /// Mean position of the free masses (null without any).
  function centroid(design, xy) {
    var sx = 0, sy = 0, n = 0;
    design.nodes.forEach(function (node, i) {
      if (node.fixed) return;
      sx += xy[2 * i];
      sy += xy[2 * i + 1];
      ++n;
    });
    return n ? [sx / n, sy / n] : null;
  }

  return { Stage: Stage, centroid: centroid };
})();
