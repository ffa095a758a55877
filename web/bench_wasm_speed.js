// The WebAssembly engine's speed in Node: frames per second of one creature, the
// reference step (what the designer runs), CPU time, best of 5 x 20,000 frames.
// web/README.md ("Speed") quotes it against the native reference step, measured by
// `sodaevo simulate MODEL --reference --frames 20000 --json` in the same sitting.
//
//   node web/bench_wasm_speed.js build/web/soda_engine_wasm.js models/dainty_walker.xml [more.xml ...]
'use strict';
const fs = require('fs');
const path = require('path');
const SodaEngine = require(path.join(__dirname, 'soda_engine.js'));

const [wasmPath, ...models] = process.argv.slice(2);
if (!wasmPath || models.length === 0) {
  console.error('usage: node web/bench_wasm_speed.js SODA_ENGINE_WASM_JS MODEL.xml [MODEL.xml ...]');
  process.exit(2);
}
const createSodaEngine = require(path.resolve(wasmPath));
const kFrames = 20000, kRuns = 5;

SodaEngine.create(createSodaEngine).then((engine) => {
  for (const model of models) {
    engine.loadXml(fs.readFileSync(model), path.basename(model));
    let best = Infinity;
    for (let run = 0; run < kRuns; ++run) {
      engine.reset();
      const t0 = process.cpuUsage();
      engine.step(kFrames);
      const t = process.cpuUsage(t0);
      best = Math.min(best, (t.user + t.system) / 1e6);
    }
    console.log(JSON.stringify({ model: path.basename(model), frames: kFrames, seconds: best,
                                 frames_per_second: kFrames / best }));
  }
}).catch((e) => { console.error(e); process.exit(1); });
