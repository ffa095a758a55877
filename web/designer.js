// The designer: modes, pointer gestures, the world's sliders, files, sharing and
// the live figures, over the engine of soda_engine.js. window.sodaDesigner is the
// app (for tests); the page sets data-ready="1" on <html> once a design is shown,
// and collects script errors in data-errors and #page-errors.
(function () {
  'use strict';

  window.sodaErrors = [];
  function reportError(text) {
    window.sodaErrors.push(String(text));
    document.documentElement.setAttribute('data-errors', String(window.sodaErrors.length));
    var box = document.getElementById('page-errors');
    box.hidden = false;
    box.textContent += text + '\n';
  }
  window.addEventListener('error', function (e) { reportError('error: ' + e.message + ' at ' + e.filename + ':' + e.lineno); });
  window.addEventListener('unhandledrejection', function (e) { reportError('unhandled rejection: ' + e.reason); });

  var $ = function (id) { return document.getElementById(id); };
  var STYLE = JSON.parse($('soda-style').textContent);
  var REPLICAS = 8, REPLICA_FRAMES = 1000, JITTER = 0.002;
  // Files bigger than this are read by a worker: the page's engine takes 0.2-0.3 s
  // for the 740 kB of 5,000 masses on its first call, so some 40 ms for 100 kB.
  var BIG_FILE = 100000;
  var SLIDERS = [
    { key: 'waveSpeed', label: 'wave speed', min: 0, max: 0.1, step: 0.0005, digits: 4 },
    { key: 'waveAmplitude', label: 'wave amplitude', min: 0, max: 1, step: 0.01, digits: 2 },
    { key: 'gravity', label: 'gravity', min: 0, max: 4, step: 0.01, digits: 2 },
    { key: 'friction', label: 'friction', min: 0, max: 1, step: 0.001, digits: 3 },
    { key: 'springyness', label: 'springyness', min: 0, max: 0.5, step: 0.005, digits: 3 },
    { key: 'surfaceFriction', label: 'surface friction', min: 0, max: 1, step: 0.01, digits: 2 },
    { key: 'surfaceReflection', label: 'surface bounce', min: -1, max: 0, step: 0.01, digits: 2 }
  ];

  var app = {
    engine: null, design: null, name: 'creature', mode: 'construct', tool: 'mass', selectedLink: -1,
    playing: true, speed: 1, gesture: null, replicaTimer: 0, replicaWorker: null, openWorker: null, opening: 0
  };
  window.sodaDesigner = app;

  /// v to `digits` decimals, never "-0.00".
  function decimals(v, digits) {
    var text = v.toFixed(digits);
    return /^-0\.?0*$/.test(text) ? text.slice(1) : text;
  }

  function message(text, isError) {
    var box = $('message');
    box.textContent = text || '';
    box.className = isError ? 'error' : '';
  }

  // --- the design ---
  function refresh() {
    app.design = app.engine.design();
    if (app.selectedLink >= app.design.links.length) app.selectedLink = -1;
    SLIDERS.forEach(function (s) {
      var v = app.design[s.key];
      s.input.value = String(v);
      s.output.textContent = v.toFixed(s.digits);
    });
    $('autoreverse').checked = app.design.autoreverse;
    // The name follows the design (Open, New, a shared link, Construct from Evolve
    // mode), except while being typed in.
    if (document.activeElement !== $('design-name')) $('design-name').value = app.design.name;
    var masses = 0, count = { spring: 0, muscle: 0, bar: 0 }, nodes = app.design.nodes, links = app.design.links;
    for (var i = 0; i < nodes.length; ++i) if (!nodes[i].fixed) ++masses;
    for (i = 0; i < links.length; ++i) ++count[links[i].kind];
    $('fig-design').textContent = masses + ' masses, ' + (nodes.length - masses) + ' fixed, ' +
      count.spring + ' springs, ' + count.muscle + ' muscles, ' + count.bar + ' bars';
    draw();
  }

  function edited() {
    $('share-url').value = '';
    refresh();
    scheduleReplicas();
  }

  /// Runs an engine edit; a refused one shows the engine's message.
  function edit(fn) {
    try {
      fn();
      message('');
    } catch (e) {
      message(e.message, true);
    }
    edited();
  }

  /// Opens model XML: true, or false (the message shown, the design kept). A big
  /// file is read by a worker: then a promise of true or false, and "opening…"
  /// until it is in (the old design stays meanwhile).
  function loadBytes(bytes, name) {
    var opening = ++app.opening; // a later open wins over an earlier one still in the worker
    var reading = null;
    if (bytes.length > BIG_FILE && window.Worker) {
      try {
        app.openWorker = app.openWorker || SodaReplicaWorker.fromPage(document);
        reading = app.openWorker.open(bytes, name);
      } catch (e) {
        reading = null; // no worker here (a browser's rule for file pages, say): read it on the page
      }
    }
    if (reading) {
      message('opening ' + name + ' (' + Math.round(bytes.length / 1000) + ' kB)\u2026');
      return reading.then(function (r) {
        if (opening !== app.opening) return false;
        var warnings;
        try {
          warnings = app.engine.importDesign(r.design, r.object);
          // Its objects now (what the pointer meets), its picture in the next task:
          // two shorter blocks of the page's thread.
          app.design = app.engine.design();
          app.selectedLink = -1;
        } catch (e) {
          return refused(e);
        }
        return new Promise(function (resolve) { setTimeout(resolve, 0); }).then(function () {
          return opening === app.opening && opened(name, function () { return warnings; });
        });
      }, function (e) {
        return opening === app.opening && refused(e);
      });
    }
    return opened(name, function () { return app.engine.loadXml(bytes, name); });
  }

  /// Shows the design `load` (which returns the warnings) makes; true, or false.
  function opened(name, load) {
    try {
      var warnings = load();
      app.name = (app.engine.design().name || name.replace(/\.xml$/i, '') || 'creature');
      app.selectedLink = -1;
      message('opened ' + name + (warnings.length ? '\n' + warnings.join('\n') : ''));
      setMode('construct'); // draws it
      $('share-url').value = '';
      scheduleReplicas();
      return true;
    } catch (e) {
      return refused(e);
    }
  }

  function refused(e) {
    app.lastError = e.message;
    message(e.message + '\n(the design was kept)', true);
    return false;
  }

  function centreCamera() {
    var design = app.engine.design(), c = SodaView.centroid(design, app.engine.positions());
    var w = design.width;
    app.stage.cameraX = c ? c[0] : Math.min(w, app.stage.canvas.width) / 2 - 20;
  }

  // --- drawing and figures ---
  function draw() {
    var xy = app.engine.positions();
    if (app.mode === 'simulate') {
      var c = SodaView.centroid(app.design, xy);
      if (c) app.stage.cameraX = c[0];
    }
    app.stage.draw(app.design, xy, { selectedLink: app.selectedLink, pending: app.gesture && app.gesture.pending });
    app.waveBar.draw(app.design, app.engine.wavePhase(), app.selectedLink);
    var frame = app.mode === 'simulate' ? app.engine.frame() : 0, d = app.mode === 'simulate' ? app.engine.distance() : 0;
    $('fig-frame').textContent = String(frame);
    $('fig-distance').textContent = decimals(d, 1) + ' px';
    $('fig-speed').textContent = decimals(frame > 0 ? d / frame : 0, 2) + ' px/frame';
  }

  /// The replica figure, in a worker (designer_replicas.js) so that a big creature
  /// does not block the page; "working…" until it is in.
  function scheduleReplicas() {
    clearTimeout(app.replicaTimer);
    $('fig-replicas').textContent = 'working\u2026';
    $('fig-replicas').title = '';
    app.replicaTimer = setTimeout(function () {
      var masses = app.design.nodes.some(function (n) { return !n.fixed; });
      if (!masses) { $('fig-replicas').textContent = '\u2013'; return; }
      var shown = function (r) {
        $('fig-replicas').textContent = decimals(r.mean, 2) + ' \u00b1 ' + decimals(r.sd, 2) + ' px/frame';
        $('fig-replicas').title = REPLICAS + ' replicas of ' + REPLICA_FRAMES + ' frames, each with ' + (r.jitter ?
          'its sines moved by 1 ulp for ' + JITTER * 100 + ' % of arguments (another libm)' : 'the exact sine (no jitter in this engine)') +
          '; exact engine: ' + r.exact.toFixed(3) + ' px/frame';
      };
      var failed = function (e) {
        $('fig-replicas').textContent = '\u2013';
        $('fig-replicas').title = e.message;
      };
      try {
        app.replicaWorker = app.replicaWorker || SodaReplicaWorker.fromPage(document);
        app.replicaWorker.run(app.engine.exportDesign(), REPLICAS, REPLICA_FRAMES, JITTER).then(shown, failed);
      } catch (e) {
        failed(e);
      }
    }, 300);
  }

  // --- modes ---
  function setMode(mode) {
    if (mode === 'simulate') {
      try {
        app.engine.reset();
      } catch (e) {
        message('cannot simulate: ' + e.message, true);
        mode = 'construct';
      }
    }
    app.mode = mode;
    app.gesture = null;
    document.body.className = 'mode-' + mode;
    Array.prototype.forEach.call(document.querySelectorAll('#modes button'), function (b) {
      b.classList.toggle('active', b.getAttribute('data-mode') === mode);
    });
    if (mode !== 'simulate') centreCamera();
    refresh();
  }

  function tick() {
    if (app.mode === 'simulate' && app.playing) {
      try {
        if (app.speed === 'fast') {
          var until = performance.now() + 30;
          while (performance.now() < until) app.engine.step(200);
        } else {
          app.engine.step(app.speed);
        }
      } catch (e) {
        message(e.message, true);
        app.playing = false;
      }
      draw();
    }
    requestAnimationFrame(tick);
  }

  // --- pointer gestures on the stage ---
  /// The world point under a canvas point, to 0.1 px (a pointer's position in a
  /// scaled canvas has a long fraction that would only clutter the saved file).
  function worldAt(point) {
    var w = app.stage.toWorld(point[0], point[1]);
    return [Math.round(w[0] * 10) / 10, Math.round(w[1] * 10) / 10];
  }

  function onStageDown(event) {
    if (app.mode === 'simulate') return;
    var point = app.stage.eventPoint(event), xy = app.engine.positions();
    var node = app.stage.nodeAt(xy, point[0], point[1]);
    if (app.mode === 'delete') {
      var link = node < 0 ? app.stage.linkAt(app.design, xy, point[0], point[1]) : -1;
      if (node >= 0) edit(function () { app.engine.removeNode(node); });
      else if (link >= 0) edit(function () { app.engine.removeLink(link); });
      app.selectedLink = -1;
      return;
    }
    if (node < 0) {
      var hit = app.stage.linkAt(app.design, xy, point[0], point[1]);
      if (hit >= 0 && app.tool !== 'bar') {
        app.selectedLink = hit;
        draw();
        return;
      }
    }
    app.stage.canvas.setPointerCapture(event.pointerId);
    var from = node >= 0 ? app.stage.toScreen(xy[2 * node], xy[2 * node + 1]) : point;
    app.gesture = { node: node, start: point, moved: false, pending: null, from: from };
    event.preventDefault();
  }

  function onStageMove(event) {
    var g = app.gesture;
    if (!g) return;
    var point = app.stage.eventPoint(event);
    if (Math.hypot(point[0] - g.start[0], point[1] - g.start[1]) > 4) g.moved = true;
    if (!g.moved) return;
    if (app.tool === 'move' && g.node >= 0) {
      var w = worldAt(point);
      app.engine.moveNode(g.node, w[0], Math.max(0, w[1]));
      refresh();
      return;
    }
    g.pending = { from: g.from, to: point };
    draw();
  }

  function onStageUp(event) {
    var g = app.gesture;
    if (!g) return;
    app.gesture = null;
    var point = app.stage.eventPoint(event);
    var fixedEnds = app.tool === 'fixed' || app.tool === 'bar';
    if (app.tool === 'move') {
      edited();
      return;
    }
    if (!g.moved) {
      if (g.node >= 0) { // a click on a node: free <-> fixed
        var fixed = !app.design.nodes[g.node].fixed;
        edit(function () { app.engine.setFixed(g.node, fixed); });
      } else if (app.tool !== 'bar') {
        var w = worldAt(point);
        edit(function () { app.engine.addNode(w[0], Math.max(0, w[1]), fixedEnds); });
      } else {
        draw();
      }
      return;
    }
    edit(function () {
      var a = g.node;
      if (a < 0) {
        var ws = worldAt(g.start);
        a = app.engine.addNode(ws[0], Math.max(0, ws[1]), fixedEnds);
      }
      var b = app.stage.nodeAt(app.engine.positions(), point[0], point[1]);
      if (b < 0) {
        var we = worldAt(point);
        b = app.engine.addNode(we[0], Math.max(0, we[1]), fixedEnds);
      }
      if (a === b) return;
      var exists = app.engine.design().links.some(function (l) { return (l.a === a && l.b === b) || (l.a === b && l.b === a); });
      if (!exists) app.selectedLink = app.engine.addLink(a, b, app.tool === 'bar' ? 'bar' : 'spring');
    });
  }

  // --- the wave bar ---
  function onBarDown(event) {
    var point = app.stage.eventPoint.call(app.waveBar, event);
    var i = app.waveBar.markerAt(app.design, point[0], point[1], app.selectedLink);
    if (i < 0) return;
    app.selectedLink = i;
    app.barDrag = i;
    app.waveBar.canvas.setPointerCapture(event.pointerId);
    draw();
    event.preventDefault();
  }
  function onBarMove(event) {
    if (app.barDrag === undefined || app.barDrag < 0) return;
    var point = app.stage.eventPoint.call(app.waveBar, event), v = app.waveBar.valueAt(point[0], point[1]);
    var i = app.barDrag;
    try {
      app.engine.setMuscle(i, v.muscle, v.amplitude, v.phase);
    } catch (e) {
      message(e.message, true);
    }
    refresh();
  }
  function onBarUp() {
    if (app.barDrag === undefined || app.barDrag < 0) return;
    app.barDrag = -1;
    edited();
  }

  // --- panel, files, sharing ---
  function buildSliders() {
    var box = $('sliders');
    SLIDERS.forEach(function (s) {
      var row = document.createElement('label');
      row.className = 'slider';
      row.innerHTML = '<span></span><input type="range"><output></output>';
      row.firstChild.textContent = s.label;
      s.input = row.querySelector('input');
      s.output = row.querySelector('output');
      s.input.min = s.min;
      s.input.max = s.max;
      s.input.step = s.step;
      s.input.id = 'slider-' + s.key;
      s.input.addEventListener('input', function () {
        edit(function () { app.engine.setWorld(s.key, Number(s.input.value)); });
      });
      box.appendChild(row);
    });
  }

  function baseName() {
    return (app.engine.design().name || app.name || 'creature').replace(/[^A-Za-z0-9_.-]+/g, '_').replace(/^[._]+/, '').slice(0, 60) || 'creature';
  }

  function save() {
    try {
      SodaShare.download(baseName() + '.xml', app.engine.saveXmlBytes(), 'application/xml');
      message('saved ' + baseName() + '.xml');
    } catch (e) {
      message(e.message, true);
    }
  }

  function share() {
    var bytes;
    try {
      bytes = app.engine.saveXmlBytes();
    } catch (e) {
      message(e.message, true);
      return Promise.resolve();
    }
    return SodaShare.encode(bytes).then(function (fragment) {
      history.replaceState(null, '', '#' + fragment);
      $('share-url').value = location.href;
      message('the address now holds this design (' + location.href.length + ' characters): copy it to share');
    });
  }

  function copyLink() {
    (($('share-url').value) ? Promise.resolve() : share()).then(function () {
      var url = $('share-url').value;
      if (navigator.clipboard && navigator.clipboard.writeText) {
        return navigator.clipboard.writeText(url).then(function () { message('link copied'); }, function () {
          $('share-url').select();
          message('select the link and copy it (the browser refused the clipboard)');
        });
      }
      $('share-url').select();
      message('select the link and copy it');
    });
  }

  function evolve() {
    try {
      var name = baseName();
      SodaShare.download(name + '.xml', app.engine.saveXmlBytes(), 'application/xml');
      var config = {
        name: name,
        comment: 'Seeded with ' + name + '.xml from the sodaevo designer. Run: sodaevo evolve ' + name + '-evolve.json',
        population: { seed_models: [name + '.xml'], random_fraction: 0.2 }
      };
      SodaShare.download(name + '-evolve.json', new TextEncoder().encode(JSON.stringify(config, null, 2) + '\n'), 'application/json');
      message('downloaded ' + name + '.xml and ' + name + '-evolve.json: put them in one folder and run\n  sodaevo evolve ' + name + '-evolve.json');
    } catch (e) {
      message(e.message, true);
    }
  }

  function openFile(file) {
    var reader = new FileReader();
    reader.onload = function () { loadBytes(new Uint8Array(reader.result), file.name); };
    reader.onerror = function () { message('cannot read ' + file.name + ': ' + reader.error, true); };
    reader.readAsArrayBuffer(file);
  }

  function wire() {
    Array.prototype.forEach.call(document.querySelectorAll('#modes button'), function (b) {
      b.addEventListener('click', function () { setMode(b.getAttribute('data-mode')); });
    });
    Array.prototype.forEach.call(document.querySelectorAll('input[name=tool]'), function (r) {
      r.addEventListener('change', function () { app.tool = r.value; setHint(); });
    });
    var st = app.stage.canvas, wb = app.waveBar.canvas;
    st.addEventListener('pointerdown', onStageDown);
    st.addEventListener('pointermove', onStageMove);
    st.addEventListener('pointerup', onStageUp);
    wb.addEventListener('pointerdown', onBarDown);
    wb.addEventListener('pointermove', onBarMove);
    wb.addEventListener('pointerup', onBarUp);
    $('play').addEventListener('click', function () {
      app.playing = !app.playing;
      $('play').textContent = app.playing ? 'Pause' : 'Play';
    });
    $('step-frame').addEventListener('click', function () { app.engine.step(1); draw(); });
    $('restart').addEventListener('click', function () { setMode('simulate'); });
    $('speed').addEventListener('change', function () {
      var v = $('speed').value;
      app.speed = v === 'fast' ? 'fast' : Number(v);
    });
    $('autoreverse').addEventListener('change', function () {
      edit(function () { app.engine.setWorld('autoreverse', $('autoreverse').checked ? 1 : 0); });
    });
    $('design-name').addEventListener('change', function () {
      edit(function () { app.engine.setName($('design-name').value); });
    });
    $('new-design').addEventListener('click', function () {
      app.engine.clear();
      app.selectedLink = -1;
      setMode('construct');
      edited();
    });
    $('open-file').addEventListener('change', function () {
      if (this.files.length) openFile(this.files[0]);
      this.value = '';
    });
    $('save-xml').addEventListener('click', save);
    $('share').addEventListener('click', share);
    $('copy-link').addEventListener('click', copyLink);
    $('evolve').addEventListener('click', evolve);
    document.addEventListener('keydown', function (e) {
      if (e.target.tagName === 'INPUT' || e.ctrlKey || e.metaKey || e.altKey) return;
      var modes = { c: 'construct', s: 'simulate', d: 'delete' };
      if (modes[e.key]) setMode(modes[e.key]);
      if (e.key === ' ' && app.mode === 'simulate') { $('play').click(); e.preventDefault(); }
    });
  }

  function setHint() {
    var hints = {
      mass: 'click: add a mass; drag from a mass: link it to another or to a new mass; click a mass: fix or free it',
      fixed: 'click: add a fixed node; drag: link to a new fixed node',
      bar: 'drag: a fixed bar (terrain) between two fixed nodes',
      move: 'drag a node to move it (its links keep their new lengths as rest lengths)'
    };
    $('tool-hint').textContent = hints[app.tool];
  }

  /// The first design: the address's model, else the one the page was written with.
  function firstDesign() {
    var inAddress = SodaShare.modelInAddress(location.hash);
    var initial = $('initial-model'), initialText = initial.textContent.trim();
    var fallback = function () {
      if (initialText) return Promise.resolve(loadBytes(SodaShare.fromBase64url(initialText), initial.getAttribute('data-name') || 'model.xml'));
      setMode('construct');
      edited();
      return Promise.resolve();
    };
    if (inAddress === null) return fallback();
    return SodaShare.decode(inAddress).then(function (bytes) {
      return loadBytes(bytes, 'the shared link');
    }).then(function (ok) {
      if (!ok) throw new Error(app.lastError);
    }).catch(function (e) {
      return fallback().then(function () {
        message('cannot open the model in this page\'s address: ' + e.message + '\n(' + (initialText ? 'opened the page\'s own design instead' : 'started an empty design') + ')', true);
      });
    });
  }

  function start(engine) {
    app.engine = engine;
    // For Evolve mode (designer_evolve.js): open a creature, switch modes, name files.
    app.loadBytes = loadBytes;
    app.setMode = setMode;
    app.baseName = baseName;
    app.message = message;
    app.stage = new SodaView.Stage($('stage'), STYLE);
    app.waveBar = new SodaWaveBar.WaveBar($('wave-bar'), STYLE);
    buildSliders();
    wire();
    setHint();
    app.stage.drawGround(app.engine.design()); // the empty stage while a big file opens
    return firstDesign().then(function () {
      // "#mode=simulate&frame=N" (with or without a model): simulate, paused at frame N.
      var params = new URLSearchParams(location.hash.slice(1));
      if (params.get('mode') === 'simulate') {
        setMode('simulate');
        if (params.has('frame')) {
          app.engine.step(Math.max(0, Number(params.get('frame')) || 0));
          app.playing = false;
          $('play').textContent = 'Play';
          draw();
        }
      }
      document.documentElement.setAttribute('data-ready', '1');
      requestAnimationFrame(tick);
    });
  }

  SodaEngine.create(createSodaEngine).then(start).catch(function (e) { reportError('the engine did not start: ' + e); });
})();
