// The fast stepper's speed in WebAssembly in Chromium (headless), one thread: frames
// per second of one creature from its start, best of 5 runs of FRAMES frames, and
// its centroid_dx, which equals `sodaevo simulate MODEL --frames FRAMES --json`'s
// when the run is the native one bit for bit. web/README.md ("Speed") quotes it.
//
//   node web/bench_fast_chromium.js CHROMIUM DESIGNER.html FRAMES MODEL.xml [MODEL.xml ...]
'use strict';
const fs = require('fs');
const path = require('path');
const { execFileSync } = require('child_process');

const [chromium, page, framesArg, ...models] = process.argv.slice(2);
if (!chromium || !page || !framesArg || models.length === 0) {
  console.error('usage: node web/bench_fast_chromium.js CHROMIUM DESIGNER.html FRAMES MODEL.xml [MODEL.xml ...]');
  process.exit(2);
}
const xmls = models.map((m) => fs.readFileSync(m).toString('base64'));
const expression = `(async function () {
  const m = await createSodaEvolve();
  const out = [];
  for (const b64 of ${JSON.stringify(xmls)}) {
    const bytes = Uint8Array.from(atob(b64), (c) => c.charCodeAt(0));
    const p = m._malloc(bytes.length);
    m.HEAPU8.set(bytes, p);
    let best = null;
    for (let run = 0; run < 5; ++run) {
      if (m._sev_fast_run(p, bytes.length, ${Number(framesArg)}) < 0) throw new Error(m.UTF8ToString(m._sev_out()));
      const r = JSON.parse(m.UTF8ToString(m._sev_out()));
      if (!best || r.frames_per_second > best.frames_per_second) best = r;
    }
    m._free(p);
    out.push(best);
  }
  return out;
})()`;
const result = JSON.parse(execFileSync('node', [path.join(__dirname, 'chromium_wait.js'), chromium,
  'file://' + path.resolve(page), "typeof createSodaEvolve === 'function'", expression, '600'], { encoding: 'utf8' }));
result.forEach((r, k) => console.log(JSON.stringify(Object.assign({ model: path.basename(models[k]) }, r))));
