// A run of the evolution in WebAssembly under Node, as the designer's Evolve mode
// runs it (web/evolve_driver.js), with `workers` instances evaluating in turn:
//
//   node web/evolve_node.js build/web/soda_evolve_wasm.js configs/quick.json [WORKERS] [OUT_DIR]
//
// Prints one JSON line: the champion (id, fitness bits, SHA-256 of its exported
// XML), evaluations and seconds. With OUT_DIR, writes the run folder and the
// exported champions there (what `sodaevo report` and `export` read).
'use strict';
const fs = require('fs');
const path = require('path');
const crypto = require('crypto');
const SodaEvolve = require(path.join(__dirname, 'evolve_driver.js'));

const [wasmPath, configPath, workersArg, outDir] = process.argv.slice(2);
if (!wasmPath || !configPath) {
  console.error('usage: node web/evolve_node.js SODA_EVOLVE_WASM_JS CONFIG.json [WORKERS] [OUT_DIR]');
  process.exit(2);
}
const createSodaEvolve = require(path.resolve(wasmPath));
const workers = Math.max(1, parseInt(workersArg || '1', 10));

function bundledModels(dir, prefix, out) {
  for (const entry of fs.readdirSync(dir, { withFileTypes: true })) {
    const rel = prefix + entry.name;
    if (entry.isDirectory()) bundledModels(path.join(dir, entry.name), rel + '/', out);
    else out[rel] = fs.readFileSync(path.join(dir, entry.name));
  }
  return out;
}

(async () => {
  const modules = [];
  for (let k = 0; k <= workers; ++k) modules.push(await createSodaEvolve());
  const run = new SodaEvolve(modules[0], new SodaEvolve.LocalPool(modules.slice(1)));
  const models = bundledModels(path.join(__dirname, '..', 'models'), '', {});
  const t0 = Date.now();
  const config = run.placeInputs(fs.readFileSync(configPath, 'utf8'), models);
  try {
    run.start(config, '/run');
  } catch (e) {
    console.log(JSON.stringify({ refused: e.message }));
    return;
  }
  let r;
  do {
    r = await run.advance();
  } while (r.kind !== 'done');
  const exported = run.exportChampions('/export', 5);
  const seconds = (Date.now() - t0) / 1000;
  const c = exported.champion || {}; // MAP-Elites: the archive is the result (OUT_DIR/run/archive.json)
  const xml = exported.champion ? run.readFile(exported.champion.file) : new Uint8Array(0);
  if (outDir) {
    for (const dir of ['/run', '/export']) {
      for (const file of run.listFiles(dir)) {
        const target = path.join(outDir, file);
        fs.mkdirSync(path.dirname(target), { recursive: true });
        fs.writeFileSync(target, run.readFile(file));
      }
    }
  }
  console.log(JSON.stringify({ id: c.id, fitness_bits: c.fitness_bits, qd_score: r.progress.qd_score,
    xml_sha256: crypto.createHash('sha256').update(xml).digest('hex'), evaluations: run.evaluations,
    seconds, evaluate_seconds: run.evaluateSeconds, stopped_because: r.progress.stopped_because }));
})().catch((e) => { console.error(e); process.exit(1); });
