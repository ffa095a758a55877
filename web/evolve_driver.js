// SodaEvolve: a run of `sodaevo evolve` in WebAssembly (web/evolve_api.cpp), for
// the designer's Evolve mode, the browser tests and Node.
//
// One instance (the driver) holds the run folder in its memory file system and
// runs the library's loop; when it asks for evaluations, the request is cut into
// chunks that a pool evaluates (Web Workers in a page, each with its own instance;
// instances in this thread in Node) and the answers are told back by index, so
// the pool's size never changes a result.
//
//   var run = new SodaEvolve(driverModule, pool);
//   run.writeFile('/in/configs/config.json', text);
//   var info = run.start('/in/configs/config.json', '/run');   // throws Error(the CLI's message)
//   run.advance().then(function (r) { r.kind: 'generation' | 'done', r.progress });
(function (root) {
  'use strict';

  function SodaEvolve(module, pool) {
    this.module = module;
    this.pool = pool;
    this.evaluations = 0;     // creatures evaluated by the pool
    this.evaluateSeconds = 0; // wall time spent waiting for the pool
  }

  SodaEvolve.prototype.outBytes = function () {
    var m = this.module, p = m._sev_out(), n = m._sev_out_size();
    return m.HEAPU8.slice(p, p + n);
  };
  SodaEvolve.prototype.outText = function () {
    return new TextDecoder('utf-8').decode(this.outBytes());
  };
  SodaEvolve.prototype.check = function (code) {
    if (code < 0) throw new Error(this.outText());
    return code;
  };
  /// Calls fn(pointer, length) with `data` (a string as UTF-8, or bytes) in wasm memory, 0-terminated.
  SodaEvolve.withBytes = function (m, data, fn) {
    var bytes = typeof data === 'string' ? new TextEncoder().encode(data) : new Uint8Array(data);
    var p = m._malloc(bytes.length + 1);
    try {
      m.HEAPU8.set(bytes, p);
      m.HEAPU8[p + bytes.length] = 0;
      return fn(p, bytes.length);
    } finally {
      m._free(p);
    }
  };

  SodaEvolve.prototype.writeFile = function (path, data) {
    var m = this.module, self = this;
    SodaEvolve.withBytes(m, path, function (p) {
      SodaEvolve.withBytes(m, data, function (q, n) { self.check(m._sev_write_file(p, q, n)); });
    });
  };
  SodaEvolve.prototype.readFile = function (path) {
    var m = this.module, self = this;
    SodaEvolve.withBytes(m, path, function (p) { self.check(m._sev_read_file(p)); });
    return this.outBytes();
  };
  SodaEvolve.prototype.listFiles = function (dir) {
    var m = this.module, self = this;
    SodaEvolve.withBytes(m, dir, function (p) { self.check(m._sev_list_files(p)); });
    return this.outText().split('\n').filter(Boolean);
  };

  /// Puts a run's inputs into the memory file system: every bundled model file
  /// (`models`: {relative path under models/: bytes}) under /in/models/, the config
  /// as /in/configs/config.json, and, wherever a seed model of the config points,
  /// the bundled file of that file name (so "../models/x.xml", "x.xml" beside the
  /// config or "/home/me/x.xml" all find x.xml). Returns the config's path.
  SodaEvolve.prototype.placeInputs = function (configText, models) {
    var self = this, byName = {};
    Object.keys(models).forEach(function (rel) {
      self.writeFile('/in/models/' + rel, models[rel]);
      var name = rel.split('/').pop();
      if (!(name in byName)) byName[name] = models[rel];
    });
    var configPath = '/in/configs/config.json';
    this.writeFile(configPath, configText);
    var seeds = [];
    try {
      var parsed = JSON.parse(configText);
      if (parsed && parsed.population && Array.isArray(parsed.population.seed_models)) seeds = parsed.population.seed_models;
    } catch (e) { /* the reader says what is wrong with it */ }
    seeds.forEach(function (s) {
      if (typeof s !== 'string' || s === '') return;
      var path = SodaEvolve.normalize(s.charAt(0) === '/' ? s : '/in/configs/' + s);
      var name = path.split('/').pop(), dir = path.slice(0, path.length - name.length);
      if (/[*?\[]/.test(name)) {
        Object.keys(byName).forEach(function (n) { self.writeFile(dir + n, byName[n]); });
      } else if (name in byName && path.indexOf('/in/models/') !== 0) {
        self.writeFile(path, byName[name]);
      }
    });
    return configPath;
  };
  SodaEvolve.normalize = function (path) {
    var out = [];
    path.split('/').forEach(function (part) {
      if (part === '..') out.pop();
      else if (part !== '' && part !== '.') out.push(part);
    });
    return '/' + out.join('/');
  };

  /// Reads the config (the command line's checks and messages) and creates the run
  /// folder; returns what the run is (name, algorithm, generations...).
  SodaEvolve.prototype.start = function (configPath, runDir) {
    var m = this.module, self = this;
    SodaEvolve.withBytes(m, configPath, function (p) {
      SodaEvolve.withBytes(m, runDir, function (q) { self.check(m._sev_start(p, q)); });
    });
    this.runDir = runDir;
    return JSON.parse(this.outText());
  };

  /// Chunks of a request of n creatures: a few per worker, so that the workers even
  /// out (creatures differ in cost); contiguous, answered by their first index.
  SodaEvolve.chunkBounds = function (n, workers) {
    var count = Math.max(1, Math.min(n, workers * 3));
    var bounds = [];
    for (var k = 0; k < count; ++k) bounds.push([Math.floor(k * n / count), Math.floor((k + 1) * n / count)]);
    return bounds.filter(function (b) { return b[1] > b[0]; });
  };

  /// Runs the loop to the end of the next generation (iteration): a promise of
  /// {kind: 'generation' | 'done', progress}. Rejects with the loop's error or the
  /// pool's (a worker that failed): nothing of the generation is kept, and the
  /// run goes on from its last finished generation when advance() is called again.
  SodaEvolve.prototype.advance = function () {
    var self = this, m = this.module;
    return new Promise(function (resolve, reject) {
      function loop() {
        var code;
        try {
          code = self.check(m._sev_advance());
        } catch (e) { reject(e); return; }
        if (code === 2 || code === 3) {
          resolve({ kind: code === 2 ? 'generation' : 'done', progress: JSON.parse(self.outText()) });
          return;
        }
        var n = parseInt(self.outText(), 10);
        var bounds = SodaEvolve.chunkBounds(n, self.pool.size());
        var chunks = bounds.map(function (b) {
          self.check(m._sev_request_chunk(b[0], b[1]));
          return self.outBytes();
        });
        var t0 = Date.now();
        self.pool.evaluate(chunks).then(function (answers) {
          self.evaluateSeconds += (Date.now() - t0) / 1000;
          self.evaluations += n;
          try {
            answers.forEach(function (bytes, k) {
              SodaEvolve.withBytes(m, bytes, function (p, len) { self.check(m._sev_tell(bounds[k][0], p, len)); });
            });
          } catch (e) { reject(e); return; }
          loop();
        }, reject);
      }
      loop();
    });
  };

  /// After the run: champions checked and exported as `sodaevo export RUN --best N
  /// --out DIR` writes them; returns {champion: {id, fitness_bits, file}, files}.
  SodaEvolve.prototype.exportChampions = function (outDir, best) {
    var m = this.module, self = this;
    SodaEvolve.withBytes(m, outDir, function (p) { self.check(m._sev_export(p, best || 5)); });
    return JSON.parse(this.outText());
  };

  /// A worker's part: evaluates a chunk (bytes) in `module`; the answer's bytes.
  SodaEvolve.evaluateChunk = function (module, bytes) {
    var code = SodaEvolve.withBytes(module, bytes, function (p, n) { return module._sev_evaluate(p, n); });
    var p = module._sev_out(), n = module._sev_out_size();
    var out = module.HEAPU8.slice(p, p + n);
    if (code < 0) throw new Error(new TextDecoder('utf-8').decode(out));
    return out;
  };

  /// A pool of instances in this thread (Node, tests): evaluates chunks one by one.
  SodaEvolve.LocalPool = function (modules) {
    this.modules = modules;
  };
  SodaEvolve.LocalPool.prototype.size = function () { return this.modules.length; };
  SodaEvolve.LocalPool.prototype.evaluate = function (chunks) {
    var modules = this.modules;
    try {
      return Promise.resolve(chunks.map(function (c, k) { return SodaEvolve.evaluateChunk(modules[k % modules.length], c); }));
    } catch (e) {
      return Promise.reject(e);
    }
  };

  if (typeof module === 'object' && module.exports) module.exports = SodaEvolve;
  else root.SodaEvolve = SodaEvolve;
})(typeof self !== 'undefined' ? self : this);
