// Evolve mode: `sodaevo evolve` in the page (evolve_driver.js over the Web Workers
// of evolve_workers.js), the same run as the command line for the same config, bit
// for bit. Starts from the current design (it seeds the population, as "Evolve
// from this" does) or a bundled config; shows per generation the fitness chart, the
// champion walking, a strip of the generation's best few, and for MAP-Elites the
// archive's heat map; pauses and resumes between generations; downloads the
// champion, the config, champions.json and the run folder (a zip that `sodaevo
// report`, `replay` and `evolve --resume` take once unpacked).
//
// A link "designer.html#evolve=<base64url of a config JSON>&run" opens Evolve mode
// with that config ("start from: the link's config") and asks before running it.
// Hook for tests and automation: with window.sodaDesignerHooks.runEvolveLink set
// (web/chromium_wait.js --run-links) it runs at once; at the end #evolve-result
// has data-id, data-fitness-bits and data-xml-sha256 of the champion (as `sodaevo export` writes it; MAP-Elites:
// data-archive-sha256 of archive.json), or data-error with the reader's message,
// and <html data-evolve-done="1">.
(function () {
  'use strict';

  var $ = function (id) { return document.getElementById(id); };
  var BUNDLED_CONFIGS = ['quick', 'default', 'map_elites', 'sodarace_flat'];
  var ev = { run: null, pool: null, rows: [], state: 'idle', info: null, champion: null, config: null };

  function bundledFiles() {
    var el = $('soda-bundled');
    var all = el ? JSON.parse(el.textContent) : {};
    var files = {};
    Object.keys(all).forEach(function (path) { files[path] = SodaShare.fromBase64url(all[path]); });
    return files;
  }

  function buildPanel() {
    var nav = $('modes');
    var button = document.createElement('button');
    button.type = 'button';
    button.setAttribute('data-mode', 'evolve');
    button.title = 'Evolve creatures in this page: the same run as sodaevo evolve (E)';
    button.textContent = 'Evolve';
    nav.appendChild(button);
    var panel = document.createElement('section');
    panel.id = 'evolve-panel';
    panel.innerHTML =
      '<div class="evolve-controls">' +
      '<label>start from <select id="ev-source"><option value="design">this design</option>' +
      BUNDLED_CONFIGS.map(function (c) { return '<option value="' + c + '">configs/' + c + '.json</option>'; }).join('') +
      '</select></label>' +
      '<label>population <input id="ev-population" type="number" min="2" max="100000"></label>' +
      '<label>generations <input id="ev-generations" type="number" min="1" max="1000000"></label>' +
      '<label>replicas <input id="ev-replicas" type="number" min="1" max="4096"></label>' +
      '<label>frames <input id="ev-frames" type="number" min="1"></label>' +
      '<label>fitness <select id="ev-kind"><option value="walk">walk</option><option value="race">race</option></select></label>' +
      '<label>terrain <select id="ev-terrain"></select></label>' +
      '<button type="button" id="ev-start">Start</button> <button type="button" id="ev-pause" disabled>Pause</button>' +
      '</div>' +
      '<p id="ev-progress" class="hint">Choose a start and press Start: the run is the one `sodaevo evolve` makes of the same config.</p>' +
      '<div class="evolve-views"><canvas id="ev-chart" width="620" height="260" aria-label="Fitness per generation"></canvas>' +
      '<canvas id="ev-champion" width="420" height="260" aria-label="The champion walking"></canvas>' +
      '<canvas id="ev-heatmap" width="620" height="420" aria-label="MAP-Elites archive" hidden></canvas></div>' +
      '<div id="ev-strip-box"><h2>The generation\'s best <span class="hint">(click one to watch it; Construct opens it in the designer)</span></h2><div id="ev-strip"></div></div>' +
      '<div class="evolve-downloads"><button type="button" id="ev-dl-champion" disabled>Champion XML</button> ' +
      '<button type="button" id="ev-dl-config" disabled>Config</button> ' +
      '<button type="button" id="ev-dl-champions" disabled>champions.json</button> ' +
      '<button type="button" id="ev-dl-run" disabled>Run folder (.zip)</button></div>' +
      '<div id="evolve-result" hidden></div>';
    document.querySelector('main').appendChild(panel);
    var files = ev.files;
    Object.keys(files).filter(function (p) { return /^models\/terrains\/.*\.xml$/.test(p); }).forEach(function (p) {
      var name = p.split('/').pop().replace(/\.xml$/, '');
      var o = document.createElement('option');
      o.value = name; o.textContent = name;
      $('ev-terrain').appendChild(o);
    });
    $('ev-terrain').value = 'TerrainFlat';
    button.addEventListener('click', function () { window.sodaDesigner.setMode('evolve'); });
    $('ev-source').addEventListener('change', fillFields);
    $('ev-start').addEventListener('click', function () { startRun(configFromFields()); });
    $('ev-pause').addEventListener('click', togglePause);
    $('ev-dl-champion').addEventListener('click', function () { download(ev.champion.name, ev.champion.bytes, 'application/xml'); });
    $('ev-dl-config').addEventListener('click', function () { download((ev.info.name || 'run') + '.json', new TextEncoder().encode(ev.configText), 'application/json'); });
    $('ev-dl-champions').addEventListener('click', function () { download('champions.json', ev.run.readFile('/export/champions.json'), 'application/json'); });
    $('ev-dl-run').addEventListener('click', downloadRun);
    document.addEventListener('keydown', function (e) {
      if (e.key === 'e' && e.target.tagName !== 'INPUT' && !e.ctrlKey && !e.metaKey && !e.altKey) window.sodaDesigner.setMode('evolve');
    });
    fillFields();
  }

  function download(name, bytes, type) { SodaShare.download(name, bytes, type); }

  /// The config the source names (a bundled one, or one seeded with the design).
  function sourceConfig() {
    var source = $('ev-source').value;
    if (source === 'link') return JSON.parse(ev.linkConfig);
    if (source !== 'design') {
      return JSON.parse(new TextDecoder('utf-8').decode(ev.files['configs/' + source + '.json']));
    }
    var name = window.sodaDesigner.baseName();
    return { name: name, seed: 1, generations: 20, population: { size: 40, seed_models: [name + '.xml'], random_fraction: 0.2 },
             fitness: { frames: 1000, settle_frames: 100 } };
  }

  function fillFields(given) {
    var c = given && given.population ? given : sourceConfig(), f = c.fitness || {}, p = c.population || {};
    $('ev-population').value = p.size || 100;
    $('ev-generations').value = c.generations || (c.map_elites && c.map_elites.iterations) || 100;
    $('ev-replicas').value = f.replicas || 1;
    $('ev-frames').value = f.frames || 2000;
    $('ev-kind').value = f.kind === 'race' ? 'race' : 'walk';
    if (f.race && f.race.terrains) $('ev-terrain').value = f.race.terrains[0];
  }

  function configFromFields() {
    var c = sourceConfig();
    c.population = c.population || {};
    c.fitness = c.fitness || {};
    c.population.size = Number($('ev-population').value);
    if (c.algorithm === 'map-elites') c.map_elites.iterations = Number($('ev-generations').value);
    else c.generations = Number($('ev-generations').value);
    var replicas = Number($('ev-replicas').value);
    if (replicas > 1 || c.fitness.replicas) c.fitness.replicas = replicas;
    if (c.fitness.replicas_max && c.fitness.replicas_max < replicas) c.fitness.replicas_max = replicas;
    if ($('ev-kind').value === 'race') {
      c.fitness.kind = 'race';
      c.fitness.race = c.fitness.race || {};
      c.fitness.race.terrains = [$('ev-terrain').value];
      delete c.fitness.frames;
    } else {
      c.fitness.frames = Number($('ev-frames').value);
    }
    return JSON.stringify(c, null, 2) + '\n';
  }

  function setProgress(text, isError) {
    $('ev-progress').textContent = text;
    $('ev-progress').classList.toggle('error', !!isError);
  }

  function shownFitness(v) { return ev.info && ev.info.lower_is_better ? -v : v; }

  /// Starts a run of `configText`; resolves when it ends (or stops on an error).
  function startRun(configText) {
    if (ev.state === 'running') return Promise.resolve();
    var models = {};
    var design = window.sodaDesigner.engine;
    // The current design first, so a seed named after it is the design.
    if (design.design().nodes.length > 0) models['design/' + window.sodaDesigner.baseName() + '.xml'] = design.saveXmlBytes();
    Object.keys(ev.files).forEach(function (p) { if (p.indexOf('models/') === 0) models[p.slice(7)] = ev.files[p]; });
    ev.rows = [];
    ev.champion = null;
    ev.pinned = null;
    ev.configText = configText;
    ['ev-dl-champion', 'ev-dl-champions', 'ev-dl-run'].forEach(function (id) { $(id).disabled = true; });
    return createSodaEvolve().then(function (module) {
      if (!ev.pool) ev.pool = new SodaWorkerPool(navigator.hardwareConcurrency || 2);
      if (ev.crashAt) ev.pool.crashAt = ev.crashAt;
      ev.run = new SodaEvolve(module, ev.pool);
      var path = ev.run.placeInputs(configText, models);
      ev.info = ev.run.start(path, '/run');
      $('ev-dl-config').disabled = false;
      $('ev-heatmap').hidden = ev.info.algorithm !== 'map-elites';
      $('ev-chart').hidden = ev.info.algorithm === 'map-elites';
      $('ev-champion').hidden = ev.info.algorithm === 'map-elites';
      $('ev-strip-box').hidden = ev.info.algorithm === 'map-elites';
      $('ev-strip').textContent = '';
      ev.started = performance.now();
      ev.state = 'running';
      $('ev-pause').disabled = false;
      $('ev-pause').textContent = 'Pause';
      setProgress('running ' + ev.info.name + ' on ' + ev.pool.size() + ' worker(s)\u2026');
      return loop();
    }).catch(function (e) {
      ev.state = 'idle';
      setProgress(e.message, true);
      throw e;
    });
  }

  function loop() {
    if (ev.state !== 'running') return Promise.resolve();
    return ev.run.advance().then(function (r) {
      show(r.progress);
      if (r.kind === 'done') return finish(r.progress);
      // Yield to the page between generations, by a message rather than a timer: a
      // background tab's timers are throttled (to once a second, then a minute), its
      // messages not, so the run goes on there at full speed.
      return new Promise(function (resolve) {
        var channel = new MessageChannel();
        channel.port1.onmessage = function () { channel.port1.close(); resolve(); };
        channel.port2.postMessage(0);
      }).then(loop);
    }, function (e) {
      // Nothing of the generation was kept: the run folder is at its last finished one.
      ev.state = 'paused';
      $('ev-pause').textContent = 'Resume';
      setProgress('paused: ' + e.message + '\nResume continues from the last finished generation.', true);
    });
  }

  function togglePause() {
    if (ev.state === 'running') {
      ev.state = 'paused'; // stops after the current generation
      $('ev-pause').textContent = 'Resume';
    } else if (ev.state === 'paused') {
      ev.state = 'running';
      $('ev-pause').textContent = 'Pause';
      loop();
    }
  }

  function show(p) {
    var seconds = (performance.now() - ev.started) / 1000;
    var rate = ev.run.evaluateSeconds > 0 ? ev.run.evaluations / ev.run.evaluateSeconds : 0;
    var unit = ev.info.unit;
    if (p.algorithm === 'map-elites') {
      setProgress('iteration ' + p.iteration + ' of ' + p.iterations + ': ' + p.filled + ' of ' + p.cells + ' cells filled, QD-score ' +
                  Math.round(p.qd_score) + ', best ' + shownFitness(p.best).toFixed(1) + ' ' + unit + '; ' + p.evaluations +
                  ' evaluations, ' + rate.toFixed(0) + ' evaluations/s, ' + seconds.toFixed(1) + ' s');
      SodaEvolveView.drawHeatMap($('ev-heatmap'), p.archive, shownFitness);
      return;
    }
    ev.rows.push({ generation: p.generation, best: p.best, mean: p.mean, median: p.median, best_sd: p.best_sd });
    var text = 'generation ' + (p.generation + 1) + ' of ' + p.generations + ': best ' + // counted from 1, as the CLI
               (p.best === null ? '-' : shownFitness(p.best).toFixed(2)) + ' ' + unit + ', mean ' +
               (p.mean === null ? '-' : shownFitness(p.mean).toFixed(2)) + '; ' + p.evaluations + ' evaluations, ' +
               rate.toFixed(0) + ' evaluations/s, ' + seconds.toFixed(1) + ' s';
    if (p.invalid || p.diverged) text += '; ' + p.invalid + ' invalid, ' + p.diverged + ' diverged';
    setProgress(text);
    SodaEvolveView.drawFitnessChart($('ev-chart'), ev.rows, unit, shownFitness);
    if (p.strip) showStrip(p.strip);
  }

  function showStrip(strip) {
    var box = $('ev-strip');
    box.textContent = '';
    strip.forEach(function (c, k) {
      var card = document.createElement('figure');
      card.className = 'ev-card' + (c.status !== 'ok' ? ' ev-bad' : '');
      var canvas = document.createElement('canvas');
      canvas.width = 300; canvas.height = 220; // shown at half size: whole creatures
      card.appendChild(canvas);
      var caption = document.createElement('figcaption');
      caption.textContent = c.id + ': ' + (c.status === 'ok' ? shownFitness(c.fitness).toFixed(1) : c.status);
      if (c.status !== 'ok') card.title = c.status + ': ' + c.reason;
      card.appendChild(caption);
      box.appendChild(card);
      if (c.xml) {
        drawStill(canvas, c.xml);
        canvas.title = 'watch it walk (above)';
        canvas.addEventListener('click', function () { ev.pinned = c; watch(c); });
        var open = document.createElement('button');
        open.type = 'button';
        open.textContent = 'Construct';
        open.title = 'open it in Construct mode';
        open.addEventListener('click', function () { openInDesigner(c); });
        card.appendChild(open);
      }
      if (k === 0 && c.xml && !ev.pinned) watch(c);
    });
  }

  /// A second session of the designer's engine, for the pictures (the design stays).
  function viewer() {
    if (!ev.viewer) ev.viewer = new SodaEngine(window.sodaDesigner.engine.module);
    return ev.viewer;
  }

  function drawStill(canvas, xml) {
    try {
      var v = viewer();
      v.loadXml(xml, 'creature.xml');
      v.reset();
      var stage = new SodaView.Stage(canvas, window.sodaDesigner.stage.style);
      fitCamera(stage, v.positions());
      stage.draw(v.design(), v.positions(), {});
    } catch (e) { /* a creature the viewer refuses is only not drawn */ }
  }

  /// The stage's camera on the creature's centre (one world px is one canvas px).
  function fitCamera(stage, xy) {
    var sum = 0, n = 0;
    for (var i = 0; i < xy.length; i += 2) { sum += xy[i]; ++n; }
    if (n > 0 && isFinite(sum)) stage.cameraX = sum / n;
  }

  /// The champion walking (racing) in its own canvas, restarted every few seconds.
  function watch(c) {
    var xml = c.xml;
    if (ev.watching && ev.watching.xml === xml) return;
    ev.watching = { xml: xml, engine: new SodaEngine(window.sodaDesigner.engine.module), frames: 0 };
    var w = ev.watching;
    try { w.engine.loadXml(xml, c.id + '.xml'); w.engine.reset(); } catch (e) { return; }
    var canvas = $('ev-champion');
    var stage = new SodaView.Stage(canvas, window.sodaDesigner.stage.style);
    function frame() {
      if (ev.watching !== w) return;
      try {
        if (w.engine.frame() >= 3000) w.engine.reset();
        w.engine.step(4);
        fitCamera(stage, w.engine.positions());
        stage.draw(w.engine.design(), w.engine.positions(), {});
        var g = canvas.getContext('2d');
        g.fillStyle = '#6b5a45';
        g.font = '12px system-ui, sans-serif';
        g.fillText((ev.pinned === c ? '' : 'the best: ') + c.id + ', frame ' + w.engine.frame(), 10, 18);
      } catch (e) {
        var g = canvas.getContext('2d');
        g.fillStyle = '#b00';
        g.fillText(c.id + ': ' + e.message + ' (diverged)', 10, 20);
        return;
      }
      requestAnimationFrame(frame);
    }
    requestAnimationFrame(frame);
  }

  function openInDesigner(c) {
    window.sodaDesigner.loadBytes(new TextEncoder().encode(c.xml), c.id + '.xml');
  }

  /// The end: champions checked and exported as `sodaevo export` writes them.
  function finish(p) {
    ev.state = 'done';
    $('ev-pause').disabled = true;
    var result = $('evolve-result');
    if (ev.info.algorithm === 'map-elites') {
      result.setAttribute('data-stopped', p.stopped_because);
      ev.run.exportChampions('/export', 5); // every elite checked, as `sodaevo export --archive`
      $('ev-dl-run').disabled = false;
      $('ev-dl-champions').disabled = false;
      setProgress($('ev-progress').textContent + '\nfinished (' + p.stopped_because + ')');
      // The archive is the result: archive.json, byte for byte the command line's.
      return sha256Hex(ev.run.readFile('/run/archive.json')).then(function (hex) { result.setAttribute('data-archive-sha256', hex); });
    }
    var exported = ev.run.exportChampions('/export', 5);
    var file = exported.champion.file;
    var bytes = ev.run.readFile(file);
    ev.champion = { name: file.split('/').pop(), bytes: bytes };
    ['ev-dl-champion', 'ev-dl-champions', 'ev-dl-run'].forEach(function (id) { $(id).disabled = false; });
    // "champion": the best of the last generation, in the CLI's and the report's words.
    setProgress($('ev-progress').textContent + '\nfinished (' + p.stopped_because + '): champion ' + exported.champion.id +
                ' (best of the last generation), ' + ev.champion.name);
    return sha256Hex(bytes).then(function (hex) {
      result.setAttribute('data-id', exported.champion.id);
      result.setAttribute('data-fitness-bits', exported.champion.fitness_bits);
      result.setAttribute('data-xml-sha256', hex);
      result.setAttribute('data-seconds', ((performance.now() - ev.started) / 1000).toFixed(2));
    });
  }

  function sha256Hex(bytes) {
    return crypto.subtle.digest('SHA-256', bytes).then(function (digest) {
      return Array.prototype.map.call(new Uint8Array(digest), function (b) { return (b < 16 ? '0' : '') + b.toString(16); }).join('');
    });
  }

  function downloadRun() {
    var files = [];
    ev.run.listFiles('/run').forEach(function (path) {
      files.push({ name: (ev.info.name || 'run') + path.slice(4), bytes: ev.run.readFile(path) });
    });
    download((ev.info.name || 'run') + '-run.zip', SodaEvolveView.zipStored(files), 'application/zip');
  }

  /// "#evolve=<base64url config>[&run]": its config in the fields, to run on Start
  /// (a link is not trusted to start a heavy run); the test hook runs it and reports.
  function hook() {
    var params = new URLSearchParams(location.hash.slice(1));
    if (!params.has('evolve')) return;
    var text = new TextDecoder('utf-8').decode(SodaShare.fromBase64url(params.get('evolve')));
    window.sodaDesigner.setMode('evolve');
    var name = 'the link\'s config', unread = '';
    ev.linkConfig = null;
    try {
      var given = JSON.parse(text);
      ev.linkConfig = text;
      if (typeof given.name === 'string') name += ' (' + given.name + ')';
    } catch (e) { unread = e.message; /* the hook's run gets the reader's message */ }
    if (ev.linkConfig !== null) {
      var option = document.createElement('option');
      option.value = 'link';
      option.textContent = name;
      $('ev-source').insertBefore(option, $('ev-source').firstChild);
      $('ev-source').value = 'link';
      fillFields();
    }
    if (!params.has('run')) return;
    var hooks = window.sodaDesignerHooks || {};
    if (!hooks.runEvolveLink) {
      if (unread) setProgress('The link\'s config cannot be read: ' + unread, true);
      else setProgress('This link asks to run ' + name + ': check the fields and press Start to run it.');
      $('ev-start').focus();
      return;
    }
    var done = function () { document.documentElement.setAttribute('data-evolve-done', '1'); };
    // "&crash=N": the worker given the N-th chunk crashes; "&resume": a paused run is
    // resumed (once per pause), as a user would press Resume.
    if (params.has('crash')) ev.crashAt = Number(params.get('crash'));
    var resumeOnPause = params.has('resume');
    var settle = function () {
      if (ev.state === 'paused' && resumeOnPause) {
        ev.resumed = (ev.resumed || 0) + 1;
        $('evolve-result').setAttribute('data-resumed', String(ev.resumed));
        ev.state = 'running';
        return loop().then(settle);
      }
      // A run that stopped on an error (a worker failed) pauses; the hook reports it.
      if (ev.state !== 'done') $('evolve-result').setAttribute('data-error', $('ev-progress').textContent);
      done();
    };
    startRun(text).then(settle, function (e) {
      $('evolve-result').setAttribute('data-error', e.message);
      done();
    });
  }

  function init() {
    if (!$('soda-evolve-engine') || typeof createSodaEvolve !== 'function') return; // built without it
    ev.files = bundledFiles();
    buildPanel();
    hook();
  }

  // After the designer has its design (designer.js sets data-ready).
  var wait = setInterval(function () {
    if (document.documentElement.getAttribute('data-ready') !== '1') return;
    clearInterval(wait);
    try { init(); } catch (e) { window.sodaErrors && window.sodaErrors.push(String(e)); throw e; }
  }, 20);
  window.sodaEvolve = ev;
})();
