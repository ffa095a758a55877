// The wave bar, as in SodaConstructor: the wave's phase runs left to right over
// one cycle; each muscle sits at its own phase (x) and amplitude (height above the
// baseline). Dragging a marker sets both; dragging it into the strip under the
// baseline makes the link a spring again. A selected spring shows in that strip,
// ready to be dragged up into a muscle.
var SodaWaveBar = (function () {
  'use strict';
  var PAD = 14, SPRING_STRIP = 18, MARKER = 6;

  function WaveBar(canvas, style) {
    this.canvas = canvas;
    this.ctx = canvas.getContext('2d');
    this.style = style;
  }

  WaveBar.prototype.baseline = function () { return this.canvas.height - SPRING_STRIP; };
  WaveBar.prototype.phaseX = function (phase) { return PAD + phase * (this.canvas.width - 2 * PAD); };
  WaveBar.prototype.amplitudeY = function (a) { return this.baseline() - a * (this.baseline() - PAD); };

  /// Where a muscle dragged to canvas point (sx, sy) goes: {muscle, phase, amplitude}.
  WaveBar.prototype.valueAt = function (sx, sy) {
    var phase = (sx - PAD) / (this.canvas.width - 2 * PAD);
    phase = phase - Math.floor(phase);
    if (sy > this.baseline() + 4) return { muscle: false, phase: 0, amplitude: 0 };
    var amplitude = (this.baseline() - sy) / (this.baseline() - PAD);
    // To 0.001, as a person sets them (pixel positions have long fractions).
    var round = function (v) { return Math.round(v * 1000) / 1000; };
    return { muscle: true, phase: round(phase) % 1, amplitude: round(Math.max(0, Math.min(1, amplitude))) };
  };

  /// Canvas position of link i's marker (springs: only the selected one, in the strip).
  WaveBar.prototype.markerPosition = function (design, i, selected) {
    var l = design.links[i];
    if (l.kind === 'muscle') return [this.phaseX(l.phase), this.amplitudeY(l.amplitude)];
    if (l.kind === 'spring' && i === selected) return [PAD + 20, this.baseline() + SPRING_STRIP / 2];
    return null;
  };

  /// The link whose marker is under canvas point (sx, sy), the selected one first; -1 if none.
  WaveBar.prototype.markerAt = function (design, sx, sy, selected) {
    var order = [];
    if (selected >= 0 && selected < design.links.length) order.push(selected);
    for (var i = 0; i < design.links.length; ++i) if (i !== selected) order.push(i);
    for (var k = 0; k < order.length; ++k) {
      var p = this.markerPosition(design, order[k], selected);
      if (p && Math.abs(p[0] - sx) <= MARKER + 3 && Math.abs(p[1] - sy) <= MARKER + 3) return order[k];
    }
    return -1;
  };

  WaveBar.prototype.draw = function (design, wavePhase, selected) {
    var ctx = this.ctx, W = this.canvas.width, H = this.canvas.height, S = this.style, base = this.baseline();
    ctx.fillStyle = S.background;
    ctx.fillRect(0, 0, W, H);
    ctx.fillStyle = S.ground;
    ctx.fillRect(0, base, W, H - base);
    ctx.fillStyle = S.tick;
    ctx.font = '10px sans-serif';
    ctx.fillText('springs', W - PAD - 40, H - 5);
    ctx.fillText('amplitude 1', 2, PAD - 3);
    // The muscles' sine: a muscle at phase p pulls to rest * (1 + A * sin(2 pi (p - wave))).
    ctx.strokeStyle = 'rgba(31, 78, 140, 0.35)';
    ctx.lineWidth = 1.5;
    ctx.beginPath();
    for (var sx = PAD; sx <= W - PAD; sx += 2) {
      var p = (sx - PAD) / (W - 2 * PAD), v = Math.sin(2 * Math.PI * (p - wavePhase)) * design.waveAmplitude;
      var y = (base + PAD) / 2 - v * (base - PAD) / 2;
      if (sx === PAD) ctx.moveTo(sx, y); else ctx.lineTo(sx, y);
    }
    ctx.stroke();
    // Phase grid: quarters of a cycle.
    ctx.strokeStyle = S.tick;
    ctx.lineWidth = 0.5;
    for (var q = 0; q <= 4; ++q) {
      var gx = this.phaseX(q / 4);
      ctx.beginPath();
      ctx.moveTo(gx, PAD);
      ctx.lineTo(gx, base);
      ctx.stroke();
    }
    // The wave's own phase now: the muscle under this line is at its rest length.
    var now = this.phaseX(wavePhase - Math.floor(wavePhase));
    ctx.strokeStyle = 'rgba(31, 78, 140, 0.8)';
    ctx.lineWidth = 1.5;
    ctx.beginPath();
    ctx.moveTo(now, PAD);
    ctx.lineTo(now, base);
    ctx.stroke();
    for (var i = 0; i < design.links.length; ++i) {
      var m = this.markerPosition(design, i, selected);
      if (!m) continue;
      var muscle = design.links[i].kind === 'muscle';
      ctx.fillStyle = muscle ? 'rgb(' + S.muscleContracted.join(',') + ')' : S.spring;
      ctx.beginPath();
      ctx.arc(m[0], m[1], MARKER, 0, 2 * Math.PI);
      ctx.fill();
      if (i === selected) {
        ctx.strokeStyle = 'rgb(230, 170, 0)';
        ctx.lineWidth = 3;
        ctx.stroke();
      }
    }
  };

  return { WaveBar: WaveBar };
})();
