// SodaEngine: the exact SodaConstructor engine (compiled to WebAssembly by
// web/build_wasm.sh) behind a small API for the designer page, the browser tests
// and Node. One engine holds one design and one simulation of it; see
// web/engine_api.cpp for what each call does.
//
//   SodaEngine.create(createSodaEngine).then(function (engine) {
//     engine.loadXml(bytesOrText, 'walker.xml');   // throws Error(message) on bad input
//     engine.reset(); engine.step(100);
//     var xy = engine.positions();                  // Float64Array [x0, y0, x1, y1, ...]
//   });
(function (root) {
  'use strict';

  var LINK_KINDS = ['spring', 'muscle', 'bar'];

  function SodaEngine(module) {
    this.module = module;
    this.session = module._soda_new();
    this.designCache = null; // design()'s object until the design changes
  }

  /// A promise of an engine; `factory` is createSodaEngine from soda_engine_wasm.js.
  SodaEngine.create = function (factory) {
    return factory().then(function (module) { return new SodaEngine(module); });
  };
  SodaEngine.LINK_KINDS = LINK_KINDS;

  SodaEngine.prototype.check = function (ok) {
    if (!ok) throw new Error(this.module.UTF8ToString(this.module._soda_message(this.session)));
  };
  SodaEngine.prototype.outputBytes = function () {
    var m = this.module, p = m._soda_output(this.session), n = m._soda_output_length(this.session);
    return m.HEAPU8.slice(p, p + n);
  };
  SodaEngine.prototype.outputText = function () {
    return new TextDecoder('utf-8').decode(this.outputBytes());
  };
  /// Calls fn(pointer) with `text` (a string, as UTF-8, or bytes) copied into wasm memory.
  SodaEngine.prototype.withBytes = function (data, fn) {
    var m = this.module;
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

  // --- files ---
  /// Reads model XML (v1 or v2; the file's bytes, or a string). Returns the reader's
  /// warnings; throws Error with the command line's message, keeping the design.
  SodaEngine.prototype.loadXml = function (data, name) {
    var self = this;
    this.designCache = null;
    this.withBytes(data, function (p, n) {
      self.withBytes(name || 'model.xml', function (q) { self.check(self.module._soda_load_xml(self.session, p, n, q)); });
    });
    var warnings = this.outputText();
    return warnings ? warnings.replace(/\n$/, '').split('\n') : [];
  };
  /// The design as canonical v1 XML: bytes of an ISO-8859-1 file.
  SodaEngine.prototype.saveXmlBytes = function () {
    this.check(this.module._soda_save_xml(this.session));
    return this.outputBytes();
  };
  SodaEngine.prototype.saveXml = function () {
    return new TextDecoder('iso-8859-1').decode(this.saveXmlBytes());
  };
  /// The design and the last load's warnings as bytes, for another engine's importDesign
  /// (the designer's worker reads big files; web/design_bytes.hpp).
  SodaEngine.prototype.exportDesign = function () {
    this.check(this.module._soda_export_design(this.session));
    return this.outputBytes();
  };
  /// Takes exportDesign's bytes as loadXml takes a file: returns the warnings.
  /// `design`: the exporting engine's design() of them, if at hand (a worker's
  /// comes as a copy made natively, cheaper than making it again on a page).
  SodaEngine.prototype.importDesign = function (bytes, design) {
    var self = this;
    this.designCache = null;
    this.withBytes(bytes, function (p, n) { self.check(self.module._soda_import_design(self.session, p, n)); });
    this.designCache = design || null;
    var warnings = this.outputText();
    return warnings ? warnings.replace(/\n$/, '').split('\n') : [];
  };
  /// The design: {name, width, height, gravity, ..., nodes: [{x, y, fixed}], links: [{kind, a, b, rest, amplitude, phase}]}.
  /// One object until the design changes (read it, do not change it): a page asks often,
  /// and a big design's nodes and links take milliseconds to make.
  SodaEngine.prototype.design = function () {
    if (this.designCache) return this.designCache;
    var m = this.module;
    this.check(m._soda_design_json(this.session));
    var d = JSON.parse(this.outputText());
    var nodeCount = m._soda_node_count(this.session), linkCount = m._soda_link_count(this.session);
    var p = m._soda_design_numbers(this.session) / 8, v = m.HEAPF64; // after the call: memory may grow
    d.nodes = new Array(nodeCount);
    for (var i = 0; i < nodeCount; ++i, p += 3) d.nodes[i] = { x: v[p], y: v[p + 1], fixed: v[p + 2] === 1 };
    d.links = new Array(linkCount);
    for (i = 0; i < linkCount; ++i, p += 6) {
      d.links[i] = { kind: LINK_KINDS[v[p]], a: v[p + 1], b: v[p + 2], rest: v[p + 3], amplitude: v[p + 4], phase: v[p + 5] };
    }
    this.designCache = d;
    return d;
  };

  // --- editing ---
  // Each edit drops design()'s object first (even one the engine refuses: no harm).
  SodaEngine.prototype.clear = function () { this.designCache = null; this.module._soda_clear(this.session); };
  SodaEngine.prototype.addNode = function (x, y, fixed) {
    this.designCache = null;
    return this.module._soda_add_node(this.session, x, y, fixed ? 1 : 0);
  };
  SodaEngine.prototype.moveNode = function (i, x, y) {
    this.designCache = null;
    this.check(this.module._soda_move_node(this.session, i, x, y));
  };
  SodaEngine.prototype.setFixed = function (i, fixed) {
    this.designCache = null;
    this.check(this.module._soda_set_fixed(this.session, i, fixed ? 1 : 0));
  };
  SodaEngine.prototype.removeNode = function (i) { this.designCache = null; this.check(this.module._soda_remove_node(this.session, i)); };
  SodaEngine.prototype.addLink = function (a, b, kind) {
    this.designCache = null;
    var i = this.module._soda_add_link(this.session, a, b, LINK_KINDS.indexOf(kind || 'spring'));
    this.check(i >= 0);
    return i;
  };
  SodaEngine.prototype.removeLink = function (i) { this.designCache = null; this.check(this.module._soda_remove_link(this.session, i)); };
  /// Makes link i a muscle of amplitude and phase (cycles), or a spring (muscle false).
  SodaEngine.prototype.setMuscle = function (i, muscle, amplitude, phase) {
    this.designCache = null;
    this.check(this.module._soda_set_link(this.session, i, muscle ? 1 : 0, amplitude || 0, phase || 0));
  };
  /// One world value by its name in design(): gravity, friction, springyness, surfaceFriction,
  /// surfaceReflection, waveAmplitude, wavePhase, waveSpeed, width, height,
  /// gravityDirection, waveDirection, autoreverse.
  SodaEngine.prototype.setWorld = function (key, value) {
    var self = this;
    this.designCache = null;
    this.withBytes(key, function (p) { self.check(self.module._soda_set_world(self.session, p, Number(value))); });
  };
  SodaEngine.prototype.setName = function (name) {
    var self = this;
    this.designCache = null;
    this.withBytes(name, function (p) { self.module._soda_set_name(self.session, p); });
  };

  // --- simulating ---
  SodaEngine.prototype.reset = function () { this.check(this.module._soda_reset(this.session)); };
  SodaEngine.prototype.step = function (frames) { this.check(this.module._soda_step(this.session, frames)); };
  SodaEngine.prototype.frame = function () { return this.module._soda_frame(this.session); };
  SodaEngine.prototype.wavePhase = function () { return this.module._soda_wave_phase(this.session); };
  SodaEngine.prototype.distance = function () { return this.module._soda_distance(this.session); };
  /// Float64Array [x0, y0, x1, y1, ...] by design node (a copy).
  SodaEngine.prototype.positions = function () {
    var m = this.module, count = 2 * this.nodeCount();
    var p = m._soda_positions(this.session) / 8;
    return m.HEAPF64.slice(p, p + count);
  };
  SodaEngine.prototype.nodeCount = function () { return this.module._soda_node_count(this.session); };
  /// The state's bits as text (web/engine_api.cpp, soda_state_bits).
  SodaEngine.prototype.stateBits = function () {
    this.check(this.module._soda_state_bits(this.session));
    return this.outputText();
  };
  /// Replica statistics: {exact, values, mean, sd} in px/frame over `replicas` runs of
  /// `frames` frames with sine jitter of `probability` (seeds 1..replicas).
  SodaEngine.prototype.replicas = function (replicas, frames, probability) {
    this.check(this.module._soda_replicas(this.session, replicas, frames, probability));
    var r = JSON.parse(this.outputText()), n = r.values.length, sum = 0, squares = 0;
    r.values.forEach(function (v) { sum += v; });
    r.mean = n ? sum / n : r.exact;
    r.values.forEach(function (v) { squares += (v - r.mean) * (v - r.mean); });
    r.sd = n > 1 ? Math.sqrt(squares / (n - 1)) : 0;
    r.jitter = this.module._soda_has_jitter() === 1;
    return r;
  };

  if (typeof module === 'object' && module.exports) module.exports = SodaEngine;
  else root.SodaEngine = SodaEngine;
})(this);
