// SodaReplicaWorker: the designer's replica figure (the exact run and 8 jittered
// replicas of 1,000 frames) in a Web Worker with its own engine. On a big creature
// those 9,000 frames take seconds (13 s for 5,000 masses), which on the page's own
// thread would freeze it after every edit. The worker is made from a Blob URL
// holding the engine's text (the page's <script id="soda-engine">), the API of
// soda_engine.js (<script data-src="soda_engine.js">) and workerMain below; the
// design travels as the designer's own XML, which reads back to the same bits.
//
// run(xmlBytes, replicas, frames, jitter) resolves with SodaEngine.replicas' result,
// or rejects with the engine's message; a newer run() ends an older one (its
// worker is terminated, its promise never settles), so a stale figure never shows
// and an abandoned one costs nothing.
(function (root) {
  'use strict';

  // Runs inside the worker, after the engine's text and the API's.
  function workerMain() {
    var ready = SodaEngine.create(createSodaEngine);
    self.onmessage = function (e) {
      ready.then(function (engine) {
        var job = e.data;
        try {
          engine.loadXml(new Uint8Array(job.xml), 'design.xml');
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

  ReplicaWorker.prototype.run = function (xmlBytes, replicas, frames, jitter) {
    var self = this;
    if (this.busy) { this.worker.terminate(); this.worker = null; } // an older run, now stale
    if (!this.worker) this.worker = new Worker(this.url);
    this.busy = true;
    var worker = this.worker, bytes = new Uint8Array(xmlBytes).buffer;
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
        reject(new Error('the replica worker failed: ' + e.message));
      };
      worker.postMessage({ xml: bytes, replicas: replicas, frames: frames, jitter: jitter }, [bytes]);
    });
  };

  root.SodaReplicaWorker = ReplicaWorker;
})(this);
