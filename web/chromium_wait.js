// Opens a page in headless Chromium, waits until a JavaScript condition holds
// there, then prints the value of an expression (JSON) and optionally saves a
// screenshot. For the Evolve-mode tests and screenshots: --dump-dom's virtual time
// does not wait for Web Workers, this waits for the page itself. Talks to Chromium
// over the DevTools protocol on a pipe (--remote-debugging-pipe: file descriptors
// 3 and 4, messages ended by a NUL byte), so it needs no network port.
//
//   node web/chromium_wait.js [--run-links] CHROMIUM URL CONDITION EXPRESSION [TIMEOUT_S] [SCREENSHOT.png] [WIDTHxHEIGHT]
//
// --run-links: the page starts with window.sodaDesignerHooks.runEvolveLink set, so
// an "#evolve=...&run" link runs at once instead of asking (designer_evolve.js).
//
// Exit status 0 with the expression's JSON on stdout; 1 on a timeout (the
// expression is still printed) or an error; the page's console goes to stderr.
'use strict';
const { spawn } = require('child_process');
const fs = require('fs');
const os = require('os');
const path = require('path');

const args = process.argv.slice(2);
const runLinks = args[0] === '--run-links';
if (runLinks) args.shift();
const [chromium, url, condition, expression, timeoutArg, screenshot, sizeArg] = args;
if (!chromium || !url || !condition || !expression) {
  console.error('usage: node web/chromium_wait.js [--run-links] CHROMIUM URL CONDITION EXPRESSION [TIMEOUT_S] [SCREENSHOT.png] [WxH]');
  process.exit(2);
}
const timeout = 1000 * Number(timeoutArg || 120);
const [width, height] = (sizeArg || '1300x900').split('x').map(Number);
const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'soda-chromium-'));
const child = spawn(chromium, ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking',
  '--no-first-run', '--disable-extensions', '--disable-component-update', '--disable-sync', '--hide-scrollbars',
  '--remote-debugging-pipe', '--user-data-dir=' + profile, '--window-size=' + width + ',' + height, 'about:blank'],
  { stdio: ['ignore', 'ignore', 'pipe', 'pipe', 'pipe'] });
child.stderr.on('data', () => {}); // Chromium's own log
const toChrome = child.stdio[3], fromChrome = child.stdio[4];

let nextId = 1, buffer = Buffer.alloc(0);
const pending = new Map();
fromChrome.on('data', (chunk) => {
  buffer = Buffer.concat([buffer, chunk]);
  for (let end; (end = buffer.indexOf(0)) >= 0; buffer = buffer.subarray(end + 1)) {
    const message = JSON.parse(buffer.subarray(0, end).toString('utf8'));
    if (message.id && pending.has(message.id)) {
      const { resolve, reject } = pending.get(message.id);
      pending.delete(message.id);
      if (message.error) reject(new Error(JSON.stringify(message.error)));
      else resolve(message.result);
    } else if (message.method === 'Runtime.consoleAPICalled') {
      console.error('console.' + message.params.type + ': ' + message.params.args.map((a) => a.value).join(' '));
    } else if (message.method === 'Runtime.exceptionThrown') {
      console.error('exception: ' + JSON.stringify(message.params.exceptionDetails.exception || message.params.exceptionDetails.text));
    }
  }
});
function send(method, params, sessionId) {
  const id = nextId++;
  toChrome.write(JSON.stringify({ id, method, params: params || {}, sessionId }) + '\0');
  return new Promise((resolve, reject) => pending.set(id, { resolve, reject }));
}
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

(async () => {
  const { targetId } = await send('Target.createTarget', { url: 'about:blank' });
  const { sessionId } = await send('Target.attachToTarget', { targetId, flatten: true });
  await send('Runtime.enable', {}, sessionId);
  await send('Page.enable', {}, sessionId);
  await send('Emulation.setDeviceMetricsOverride', { width, height, deviceScaleFactor: 1, mobile: false }, sessionId);
  if (runLinks) {
    await send('Page.addScriptToEvaluateOnNewDocument', {
      source: 'window.sodaDesignerHooks = Object.assign(window.sodaDesignerHooks || {}, { runEvolveLink: true });'
    }, sessionId);
  }
  await send('Page.navigate', { url }, sessionId);
  const evaluate = async (expr) => {
    const r = await send('Runtime.evaluate', { expression: expr, returnByValue: true, awaitPromise: true }, sessionId);
    return r.result ? r.result.value : undefined;
  };
  const started = Date.now();
  let ok = false;
  while (Date.now() - started < timeout) {
    try {
      if (await evaluate(condition)) { ok = true; break; }
    } catch (e) { /* the page is still loading */ }
    await sleep(100);
  }
  const value = await evaluate(expression);
  if (screenshot) {
    const shot = await send('Page.captureScreenshot', { format: 'png' }, sessionId);
    fs.writeFileSync(screenshot, Buffer.from(shot.data, 'base64'));
  }
  process.stdout.write(JSON.stringify(value === undefined ? null : value) + '\n');
  await send('Browser.close').catch(() => {});
  return ok ? 0 : 1;
})().then((code) => finish(code), (e) => {
  console.error(String(e && e.stack || e));
  finish(1);
});

// Chromium is gone before its profile folder is removed (it writes there to the end).
function finish(code) {
  const done = () => {
    try { fs.rmSync(profile, { recursive: true, force: true, maxRetries: 5 }); } catch (e) { /* a temporary folder */ }
    process.exit(code);
  };
  if (child.exitCode !== null) return done();
  child.on('exit', done);
  child.kill();
}
