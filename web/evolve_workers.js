// SodaWorkerPool: the Web Workers that evaluate a run's creatures in the page, one
// per core (navigator.hardwareConcurrency), each with its own instance of the
// evolution's WebAssembly (web/evolve_api.cpp, sev_evaluate). The page is one file
// that opens from disk, so each worker is made from a Blob URL holding the
// engine's text (the page's <script id="soda-evolve-engine">) and workerMain below;
// without SharedArrayBuffer (not given to a page opened from a file) everything
// travels as messages, the chunks' bytes transferred, not copied.
//
// evaluate(chunks) gives chunks to idle workers in order and resolves with the
// answers in the chunks' order. A worker that fails or dies rejects the whole call
// (the driver keeps nothing of the generation) and is replaced by a fresh one.
(function (root) {
  'use strict';

  // Runs inside each worker, after the engine's text (createSodaEvolve).
  function workerMain() {
    var module = null, queue = [];
    function evaluate(message) {
      var m = module, bytes = new Uint8Array(message.bytes);
      var p = m._malloc(bytes.length + 1);
      try {
        m.HEAPU8.set(bytes, p);
        var code = m._sev_evaluate(p, bytes.length);
        var q = m._sev_out(), n = m._sev_out_size();
        var out = m.HEAPU8.slice(q, q + n);
        if (code < 0) self.postMessage({ id: message.id, error: new TextDecoder('utf-8').decode(out) });
        else self.postMessage({ id: message.id, bytes: out.buffer }, [out.buffer]);
      } catch (e) {
        self.postMessage({ id: message.id, error: String(e && e.message || e) });
      } finally {
        m._free(p);
      }
    }
    self.onmessage = function (e) {
      // The test hook's crash (designer_evolve.js, "&crash=N"): an uncaught error, as a bug would throw.
      if (e.data.crash) throw new Error('this worker crashed on purpose (test hook)');
      if (module) evaluate(e.data);
      else queue.push(e.data);
    };
    createSodaEvolve().then(function (m) {
      module = m;
      queue.forEach(evaluate);
      queue = [];
    }, function (e) { self.postMessage({ id: -1, error: 'the engine did not start: ' + e }); });
  }

  function SodaWorkerPool(count) {
    var engine = document.getElementById('soda-evolve-engine');
    if (!engine) throw new Error('this page has no evolution engine (sodaevo was built without it)');
    var text = engine.textContent + '\n;(' + workerMain.toString() + ')();\n';
    this.url = URL.createObjectURL(new Blob([text], { type: 'text/javascript' }));
    this.count = Math.max(1, count || navigator.hardwareConcurrency || 2);
    this.workers = [];
    for (var k = 0; k < this.count; ++k) this.workers.push(this.spawn());
    this.nextId = 0;
    this.chunksGiven = 0;
    this.crashAt = 0; // > 0: that chunk's worker crashes (tests: a crash loses no finished generation)
  }

  SodaWorkerPool.prototype.spawn = function () {
    return { worker: new Worker(this.url), busy: false };
  };
  SodaWorkerPool.prototype.size = function () { return this.count; };

  /// Replaces worker k (it died, or failed mid-chunk).
  SodaWorkerPool.prototype.replace = function (k) {
    try { this.workers[k].worker.terminate(); } catch (e) { /* already gone */ }
    this.workers[k] = this.spawn();
  };

  SodaWorkerPool.prototype.evaluate = function (chunks) {
    var self = this;
    return new Promise(function (resolve, reject) {
      var answers = new Array(chunks.length), next = 0, done = 0, failed = false;
      function give(k) {
        var slot = self.workers[k];
        if (failed || next >= chunks.length) { slot.busy = false; return; }
        var index = next++, id = self.nextId++;
        slot.busy = true;
        slot.worker.onmessage = function (e) {
          if (e.data.id !== id) return;
          if (e.data.error !== undefined) return fail(k, 'a worker failed: ' + e.data.error);
          answers[index] = new Uint8Array(e.data.bytes);
          if (++done === chunks.length) { slot.busy = false; resolve(answers); return; }
          give(k);
        };
        slot.worker.onerror = function (e) { e.preventDefault(); fail(k, 'a worker crashed: ' + (e.message || 'unknown error')); };
        var bytes = chunks[index].slice(); // transferred: the caller keeps its copy
        var crash = ++self.chunksGiven === self.crashAt;
        slot.worker.postMessage({ id: id, bytes: bytes.buffer, crash: crash }, [bytes.buffer]);
      }
      function fail(k, why) {
        if (failed) return;
        failed = true;
        // Every worker still busy is replaced: its answer would belong to nothing.
        self.workers.forEach(function (w, j) { if (w.busy || j === k) self.replace(j); });
        reject(new Error(why));
      }
      if (chunks.length === 0) { resolve([]); return; }
      for (var k = 0; k < self.workers.length; ++k) give(k);
    });
  };

  SodaWorkerPool.prototype.close = function () {
    this.workers.forEach(function (w) { w.worker.terminate(); });
    URL.revokeObjectURL(this.url);
  };

  root.SodaWorkerPool = SodaWorkerPool;
})(typeof self !== 'undefined' ? self : this);
