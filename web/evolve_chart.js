// Drawing and packing for Evolve mode (designer_evolve.js): the fitness chart, the
// MAP-Elites heat map and a zip of the run folder (stored, no compression: a zip
// any unzip reads, written by hand since a page has no zip library).
(function (root) {
  'use strict';

  var COLORS = { best: '#1f4e8c', mean: '#c0762b', median: '#3d8b4f', band: 'rgba(31,78,140,0.15)', axis: '#6b5a45' };

  /// Ticks at round values (1, 2 or 5 times a power of ten apart, about five of
  /// them, at most seven, never closer than `minStep`) from lo to hi, as the run
  /// report's charts have (charts::round_ticks).
  function roundTicks(lo, hi, minStep) {
    var raw = Math.max((hi - lo) / 6, minStep || 0), mag = Math.pow(10, Math.floor(Math.log10(raw)));
    var step = [1, 2, 5, 10].map(function (m) { return m * mag; }).find(function (s) { return s >= raw * (1 - 1e-9); });
    var digits = Math.max(0, -Math.floor(Math.log10(step) + 1e-9));
    var ticks = [];
    for (var v = Math.ceil(lo / step - 1e-9) * step; v <= hi + step * 1e-9; v += step) {
      var value = Math.abs(v) < step * 1e-9 ? 0 : v;
      ticks.push({ value: value, label: value.toFixed(digits) });
    }
    return { step: step, ticks: ticks };
  }

  /// rows: [{generation, best, mean, median, best_sd}] (generation from 0, shown from
  /// 1 as the page and the CLI count); `shown(v)` turns a fitness into what is plotted
  /// (px, or frames for races). Draws best, mean, median and the best's interval (best
  /// +- 1.96 sd of its replicas) inside the axes, which end on round ticks, so nothing
  /// is clipped; the legend and the axis titles sit outside the data.
  function drawFitnessChart(canvas, rows, unit, shown) {
    var g = canvas.getContext('2d'), w = canvas.width, h = canvas.height;
    g.clearRect(0, 0, w, h);
    var pad = { l: 64, r: 18, t: 26, b: 40 };
    var finite = function (v) { return typeof v === 'number' && isFinite(v); };
    var values = [];
    rows.forEach(function (r) {
      ['best', 'mean', 'median'].forEach(function (k) { if (finite(r[k])) values.push(shown(r[k])); });
      if (finite(r.best) && finite(r.best_sd)) values.push(shown(r.best - 1.96 * r.best_sd), shown(r.best + 1.96 * r.best_sd));
    });
    g.fillStyle = COLORS.axis;
    g.font = '12px system-ui, sans-serif';
    g.textBaseline = 'alphabetic';
    if (values.length === 0) { g.textAlign = 'left'; g.fillText('the chart fills in as generations finish', pad.l, h / 2); return; }
    var lo = Math.min.apply(null, values), hi = Math.max.apply(null, values);
    if (hi - lo < 1e-9) { hi += 1; lo -= 1; }
    var yTicks = roundTicks(lo, hi);
    lo = Math.floor(lo / yTicks.step + 1e-9) * yTicks.step; // the axis ends on round ticks
    hi = Math.ceil(hi / yTicks.step - 1e-9) * yTicks.step;
    yTicks = roundTicks(lo, hi);
    var first = 1, last = Math.max(2, rows[rows.length - 1].generation + 1);
    var X = function (gen) { return pad.l + (w - pad.l - pad.r) * (gen + 1 - first) / (last - first); };
    var Y = function (v) { return h - pad.b - (h - pad.t - pad.b) * (v - lo) / (hi - lo); };
    g.strokeStyle = '#d8d0c2';
    g.lineWidth = 1;
    g.textAlign = 'right';
    yTicks.ticks.forEach(function (t) {
      g.beginPath(); g.moveTo(pad.l, Y(t.value)); g.lineTo(w - pad.r, Y(t.value)); g.stroke();
      g.fillText(t.label, pad.l - 6, Y(t.value) + 4);
    });
    g.textAlign = 'center';
    roundTicks(first, last, 1).ticks.forEach(function (t) {
      var x = X(t.value - 1);
      g.beginPath(); g.moveTo(x, h - pad.b); g.lineTo(x, h - pad.b + 5); g.stroke();
      g.fillText(t.label, x, h - pad.b + 17);
    });
    g.fillText('generation', pad.l + (w - pad.l - pad.r) / 2, h - 6);
    g.save();
    g.translate(13, pad.t + (h - pad.t - pad.b) / 2);
    g.rotate(-Math.PI / 2);
    g.fillText(unit === 'px' ? 'fitness (px)' : 'race result (' + unit + ')', 0, 0);
    g.restore();
    // The best's interval, a band.
    var band = rows.filter(function (r) { return finite(r.best) && finite(r.best_sd); });
    if (band.length > 0) {
      g.fillStyle = COLORS.band;
      g.beginPath();
      band.forEach(function (r, i) { g[i ? 'lineTo' : 'moveTo'](X(r.generation), Y(shown(r.best + 1.96 * r.best_sd))); });
      band.slice().reverse().forEach(function (r) { g.lineTo(X(r.generation), Y(shown(r.best - 1.96 * r.best_sd))); });
      g.closePath();
      g.fill();
    }
    ['median', 'mean', 'best'].forEach(function (key) {
      g.strokeStyle = COLORS[key];
      g.lineWidth = key === 'best' ? 2.5 : 1.5;
      g.beginPath();
      var started = false;
      rows.forEach(function (r) {
        if (!finite(r[key])) return;
        g[started ? 'lineTo' : 'moveTo'](X(r.generation), Y(shown(r[key])));
        started = true;
      });
      g.stroke();
    });
    // The legend above the plot.
    var x = pad.l, y = pad.t - 10;
    g.textAlign = 'left';
    ['best', 'mean', 'median'].forEach(function (key) {
      g.fillStyle = COLORS[key];
      g.fillRect(x, y - 4, 14, 4);
      g.fillText(key, x + 18, y);
      x += 70;
    });
    g.fillStyle = COLORS.band;
    g.fillRect(x, y - 8, 14, 8);
    g.fillStyle = COLORS.axis;
    g.fillText("best's 95 % interval", x + 18, y);
  }

  /// The archive (archive.json of a MAP-Elites run): its first two axes as a grid,
  /// each cell coloured by its best elite's fitness (over the third axis, if any).
  function drawHeatMap(canvas, archive, shown) {
    var g = canvas.getContext('2d'), w = canvas.width, h = canvas.height;
    g.clearRect(0, 0, w, h);
    g.font = '12px system-ui, sans-serif';
    g.fillStyle = '#6b5a45';
    if (!archive || !archive.axes || !archive.cells) { g.fillText('the archive fills in as iterations finish', 10, h / 2); return; }
    var axes = archive.axes, bx = axes[0].bins, by = axes[1].bins;
    var best = {}, lo = Infinity, hi = -Infinity;
    archive.cells.forEach(function (e) {
      var key = e.bins[0] + ',' + e.bins[1];
      var f = shown(e.fitness.mean);
      if (!isFinite(f)) return;
      if (!(key in best) || f > best[key]) best[key] = f;
    });
    Object.keys(best).forEach(function (k) { lo = Math.min(lo, best[k]); hi = Math.max(hi, best[k]); });
    var pad = { l: 40, r: 10, t: 10, b: 34 };
    var cw = (w - pad.l - pad.r) / bx, ch = (h - pad.t - pad.b) / by;
    for (var ix = 0; ix < bx; ++ix) {
      for (var iy = 0; iy < by; ++iy) {
        var key = ix + ',' + iy;
        var x = pad.l + ix * cw, y = h - pad.b - (iy + 1) * ch;
        if (key in best) {
          var t = hi > lo ? (best[key] - lo) / (hi - lo) : 1;
          g.fillStyle = 'hsl(' + (220 - 200 * t).toFixed(0) + ',70%,' + (70 - 25 * t).toFixed(0) + '%)';
        } else {
          g.fillStyle = '#ece6da';
        }
        g.fillRect(x + 0.5, y + 0.5, cw - 1, ch - 1);
      }
    }
    g.fillStyle = '#6b5a45';
    g.fillText(axes[0].descriptor + ' \u2192', pad.l, h - 12);
    g.save(); g.translate(14, h - pad.b); g.rotate(-Math.PI / 2); g.fillText(axes[1].descriptor + ' \u2192', 0, 0); g.restore();
    g.fillText(Object.keys(best).length + ' of ' + bx * by + ' cells (' + archive.cells.length + ' elites); colour: best, blue ' +
               lo.toFixed(0) + ' to red ' + hi.toFixed(0), pad.l + 90, h - 12);
  }

  // --- zip, stored ---
  var CRC_TABLE = (function () {
    var t = new Uint32Array(256);
    for (var n = 0; n < 256; ++n) {
      var c = n;
      for (var k = 0; k < 8; ++k) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
      t[n] = c >>> 0;
    }
    return t;
  })();
  function crc32(bytes) {
    var c = 0xffffffff;
    for (var i = 0; i < bytes.length; ++i) c = CRC_TABLE[(c ^ bytes[i]) & 0xff] ^ (c >>> 8);
    return (c ^ 0xffffffff) >>> 0;
  }

  /// files: [{name, bytes}] -> the zip's bytes (every entry stored).
  function zipStored(files) {
    var parts = [], central = [], offset = 0, enc = new TextEncoder();
    function header(size) { return { buf: new Uint8Array(size), view: null }; }
    files.forEach(function (f) {
      var name = enc.encode(f.name), crc = crc32(f.bytes), h = header(30 + name.length), v = new DataView(h.buf.buffer);
      v.setUint32(0, 0x04034b50, true); v.setUint16(4, 20, true); v.setUint16(6, 0x0800, true);
      v.setUint32(14, crc, true); v.setUint32(18, f.bytes.length, true); v.setUint32(22, f.bytes.length, true);
      v.setUint16(26, name.length, true);
      h.buf.set(name, 30);
      parts.push(h.buf, f.bytes);
      var c = header(46 + name.length), cv = new DataView(c.buf.buffer);
      cv.setUint32(0, 0x02014b50, true); cv.setUint16(4, 20, true); cv.setUint16(6, 20, true); cv.setUint16(8, 0x0800, true);
      cv.setUint32(16, crc, true); cv.setUint32(20, f.bytes.length, true); cv.setUint32(24, f.bytes.length, true);
      cv.setUint16(28, name.length, true); cv.setUint32(42, offset, true);
      c.buf.set(name, 46);
      central.push(c.buf);
      offset += h.buf.length + f.bytes.length;
    });
    var size = central.reduce(function (s, b) { return s + b.length; }, 0);
    var end = new Uint8Array(22), ev = new DataView(end.buffer);
    ev.setUint32(0, 0x06054b50, true); ev.setUint16(8, files.length, true); ev.setUint16(10, files.length, true);
    ev.setUint32(12, size, true); ev.setUint32(16, offset, true);
    var all = parts.concat(central, [end]), total = all.reduce(function (s, b) { return s + b.length; }, 0);
    var out = new Uint8Array(total), at = 0;
    all.forEach(function (b) { out.set(b, at); at += b.length; });
    return out;
  }

  root.SodaEvolveView = { drawFitnessChart: drawFitnessChart, drawHeatMap: drawHeatMap, zipStored: zipStored, crc32: crc32 };
})(typeof self !== 'undefined' ? self : this);
