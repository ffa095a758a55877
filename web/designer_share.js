// Sharing a design: the model file's bytes in the page's address, downloads.
//
// The address holds "#model=z:<base64url>" (the XML compressed with the browser's
// CompressionStream, raw deflate) or "#model=b:<base64url>" (the bytes as they are:
// what `sodaevo report` writes, and what a browser without CompressionStream
// makes). base64url: RFC 4648 section 5, no padding.
var SodaShare = (function () {
  'use strict';
  var ALPHABET = 'ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_';
  var VALUE = new Uint8Array(128); // of each letter's code (a page holds megabytes of it: no indexOf)
  for (var k = 0; k < 64; ++k) VALUE[ALPHABET.charCodeAt(k)] = k;

  function toBase64url(bytes) {
    var out = '', i = 0;
    for (; i + 2 < bytes.length; i += 3) {
      var v = bytes[i] << 16 | bytes[i + 1] << 8 | bytes[i + 2];
      out += ALPHABET[v >> 18 & 63] + ALPHABET[v >> 12 & 63] + ALPHABET[v >> 6 & 63] + ALPHABET[v & 63];
    }
    if (i < bytes.length) {
      var w = bytes[i] << 16 | (i + 1 < bytes.length ? bytes[i + 1] << 8 : 0);
      out += ALPHABET[w >> 18 & 63] + ALPHABET[w >> 12 & 63] + (i + 1 < bytes.length ? ALPHABET[w >> 6 & 63] : '');
    }
    return out;
  }

  /// Bytes of base64url text (padding and '+', '/' of plain base64 accepted too).
  function fromBase64url(text) {
    text = text.replace(/=+$/, '').replace(/\+/g, '-').replace(/\//g, '_');
    if (/[^A-Za-z0-9_-]/.test(text) || text.length % 4 === 1) throw new Error('not base64url text');
    // Natively where the browser can (a big creature's page holds a megabyte of it).
    if (Uint8Array.fromBase64) return Uint8Array.fromBase64(text, { alphabet: 'base64url' });
    var bytes = new Uint8Array(Math.floor(text.length * 3 / 4)), n = 0, bits = 0, value = 0;
    for (var i = 0; i < text.length; ++i) {
      value = value << 6 | VALUE[text.charCodeAt(i)];
      bits += 6;
      if (bits >= 8) {
        bits -= 8;
        bytes[n++] = value >> bits & 255;
      }
    }
    return bytes.subarray(0, n);
  }

  function through(bytes, stream) {
    var piped = new Blob([bytes]).stream().pipeThrough(stream);
    return new Response(piped).arrayBuffer().then(function (b) { return new Uint8Array(b); });
  }

  var canCompress = typeof CompressionStream === 'function' && typeof DecompressionStream === 'function';

  /// A promise of the fragment ("model=...") for a model file's bytes.
  function encode(bytes) {
    if (!canCompress) return Promise.resolve('model=b:' + toBase64url(bytes));
    return through(bytes, new CompressionStream('deflate-raw')).then(function (z) { return 'model=z:' + toBase64url(z); });
  }

  /// A promise of the model file's bytes in a fragment's value ("b:..." or "z:...").
  function decode(value) {
    return Promise.resolve().then(function () {
      var kind = value.slice(0, 2), bytes = fromBase64url(value.slice(2));
      if (kind === 'b:') return bytes;
      if (kind === 'z:') {
        if (!canCompress) throw new Error('this browser cannot decompress it (no DecompressionStream)');
        return through(bytes, new DecompressionStream('deflate-raw')).catch(function () {
          throw new Error('its compressed data is damaged');
        });
      }
      throw new Error('expected "b:" or "z:" after model=, got "' + value.slice(0, 8) + '"');
    });
  }

  /// The value of "model" in the address's fragment, or null.
  function modelInAddress(hash) {
    var m = /(?:^#|&)model=([^&]*)/.exec(hash || '');
    return m ? decodeURIComponent(m[1]) : null;
  }

  /// Hooks for tests: window.sodaDesignerHooks.download(name, bytes) replaces a download.
  function download(name, bytes, type) {
    var hooks = window.sodaDesignerHooks;
    if (hooks && hooks.download) return hooks.download(name, bytes, type);
    var url = URL.createObjectURL(new Blob([bytes], { type: type || 'application/octet-stream' }));
    var a = document.createElement('a');
    a.href = url;
    a.download = name;
    document.body.appendChild(a);
    a.click();
    a.remove();
    setTimeout(function () { URL.revokeObjectURL(url); }, 1000);
  }

  return { toBase64url: toBase64url, fromBase64url: fromBase64url, encode: encode, decode: decode,
           modelInAddress: modelInAddress, download: download, canCompress: canCompress };
})();
