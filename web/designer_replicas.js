// SodaReplicaWorker: an engine of its own in a Web Worker, for the designer's heavy
// work. The replica figure (the exact run and 8 jittered replicas of 1,000 frames)
// takes seconds on a big creature (13 s for 5,000 masses), and reading a big file's
// XML takes 0.3 s for 5,000 masses, seconds for 100,000: on the page's own thread
// either would freeze it. The worker is made from a Blob URL holding the engine's
// text (the page's <script id="soda-engine">), the API of soda_engine.js
// (<script data-src="soda_engine.js">) and workerMain below. Designs travel as
// SodaEngine.exportDesign's bytes (doubles as their bits: the same design at
// both ends), which an engine takes in milliseconds.
//
// open(xmlBytes, name) resolves with {design: bytes, object: its design(),
// warnings} of the file, or
// rejects with the reader's message; run(designBytes, replicas, frames, jitter)
// resolves with SodaEngine.replicas' result, or rejects with the engine's message.
// A newer job ends an older one (its worker is terminated, its promise never
// settles), so a stale result never shows and an abandoned one costs nothing: the
// designer keeps one worker for opening files and one for the figure.
(function (root) {
  'use strict';

  // Runs inside the worker, after the engine's text and the API's.
  function workerMain() {
    var ready = SodaEngine.create(createSodaEngine);
    self.onmessage = function (e) {
      ready.then(function (engine) {
        var job = e.data;
        try {
          if (job.open) {
            var warnings = engine.loadXml(new Uint8Array(job.open), job.name);
            var design = engine.exportDesign().buffer;
            self.postMessage({ result: { design: design, object: engine.design(), warnings: warnings } }, [design]);
            return;
          }
          engine.importDesign(new Uint8Array(job.design));
          self.postMessage({ result: engine.replicas(job.replicas, job.frames, job.jitter) });
        } catch (err) {
          self.postMessage({ error: String(err && err.message || err) });
        }
      });
    };
  }

  function ReplicaWorker(engineText, apiText) {
    this.url = URL.createObjectURL(new Blob([engineText, '\n', apiText, '\n(', workerMain.toString(), ')();\n'],
                                            { type: 'text/javascript' }));
    this.worker = null;
    this.busy = false;
  }

  /// From the designer page's own scripts.
  ReplicaWorker.fromPage = function (doc) {
    return new ReplicaWorker(doc.getElementById('soda-engine').textContent,
                             doc.querySelector('script[data-src="soda_engine.js"]').textContent);
  };

  /// Posts `job` (its `buffer` transferred) to the worker; the promise of its answer.
  ReplicaWorker.prototype.job = function (job, buffer) {
    var self = this;
    if (this.busy) { this.worker.terminate(); this.worker = null; } // an older job, now stale
    if (!this.worker) this.worker = new Worker(this.url);
    this.busy = true;
    var worker = this.worker;
    return new Promise(function (resolve, reject) {
      worker.onmessage = function (e) {
        self.busy = false;
        if (e.data.error !== undefined) reject(new Error(e.data.error)); else resolve(e.data.result);
      };
      worker.onerror = function (e) {
        e.preventDefault();
        self.busy = false;
        self.worker = null;
        worker.terminate();
        reject(new Error('the worker failed: ' + e.message));
      };
      worker.postMessage(job, [buffer]);
    });
  };

  ReplicaWorker.prototype.open = function (xmlBytes, name) {
    var bytes = new Uint8Array(xmlBytes).slice().buffer; // a copy: the caller keeps its bytes
    return this.job({ open: bytes, name: name }, bytes).then(function (r) {
      return { design: new Uint8Array(r.design), object: r.object, warnings: r.warnings };
    });
  };

  ReplicaWorker.prototype.run = function (designBytes, replicas, frames, jitter) {
    var bytes = new Uint8Array(designBytes).slice().buffer;
    return this.job({ design: bytes, replicas: replicas, frames: frames, jitter: jitter }, bytes);
  };

  root.SodaReplicaWorker = ReplicaWorker;
})(this);
