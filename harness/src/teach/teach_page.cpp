// teach_page.cpp: the self-contained HTML page of a `refraster teach` run (teach_page.hpp).
//
// Implements: the page's static text (title, scene, GL source, summary, the list of
// differences, the notes, the mask legend, the command that reproduces the page), written
// HTML-escaped; the run's document embedded as JSON; and the inline script that draws the three
// images on canvases (algorithm, GL, difference mask) with the pixel grid and the input geometry,
// follows the pointer, outlines a chosen pixel in every image, and steps through the algorithm.
// Stepping keeps the weights decided so far in one array and walks forward from the last state
// it saved (every few dozen steps, saved lazily as it passes): a step forward costs that step's
// pixels plus one repaint of the image, a step back one saved state copied and a few steps
// replayed.
//
// Deliberately does not: compute anything about the algorithm or the differences (the mask's
// classes come from the document's differences), load anything (no network, no other file,
// no web font), or use any script library.
#include "harness/teach_page.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string_view>

#include "harness/encode.hpp"
#include "harness/markup.hpp"

namespace harness {

namespace {

using nlohmann::json;

// A field's text: a string as it is, a number or a boolean as JSON writes it, a whole float
// without its ".0"; anything else (absent, null, an array) as "".
std::string text_of(const json& v) {
    if (v.is_string()) return v.get<std::string>();
    if (v.is_number_float()) {
        const double d = v.get<double>();
        if (std::isfinite(d) && d == std::floor(d) && std::fabs(d) < 1e15) {
            return std::to_string(static_cast<long long>(d));
        }
    }
    if (v.is_number() || v.is_boolean()) return v.dump();
    return "";
}

std::string field(const json& d, const char* key) {
    const auto it = d.find(key);
    return it == d.end() ? std::string() : text_of(*it);
}

long long int_field(const json& d, const char* key) {
    const auto it = d.find(key);
    if (it == d.end() || !it->is_number()) return 0;
    const double v = it->get<double>();
    return std::isfinite(v) ? static_cast<long long>(std::clamp(v, -1e9, 1e9)) : 0;
}

const json& array_field(const json& d, const char* key) {
    static const json empty = json::array();
    const auto it = d.find(key);
    return it != d.end() && it->is_array() ? *it : empty;
}

// The document as JSON text safe inside a <script> element (encode.hpp, script_safe_json).
std::string embedded_json(const json& data) {
    return encode::script_safe_json(data.dump(-1, ' ', false, json::error_handler_t::replace));
}

bool lit(const json& v) {
    if (v.is_boolean()) return v.get<bool>();
    if (v.is_number()) return v.get<double>() > 0;
    return false;
}

const char* kStyle = R"CSS(<style>
:root{color-scheme:light}
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;margin:1.2em 1.5em;color:#222;
  line-height:1.4;max-width:1600px}
h1{font-size:1.45em;margin:0 0 .2em}h2{font-size:1.12em;margin:1.2em 0 .4em}
h1 .algo{font-weight:400;color:#666;font-size:.75em}
code{background:#f1f1f1;padding:1px 4px;border-radius:3px;font-size:.92em}
.muted{color:#777}
#meta,#summary{margin:.2em 0}
#summary{font-weight:600}
#controls{margin:.7em 0;display:flex;gap:1.5em;align-items:center;flex-wrap:wrap}
#zoom{vertical-align:middle;width:10em}
#views{display:flex;gap:18px;flex-wrap:wrap;align-items:flex-start}
figure{margin:0}
figcaption{font-size:.9em;margin-top:4px;max-width:32em}
.frame{position:relative;display:inline-block;line-height:0;border:1px solid #888;background:#000}
.frame canvas{display:block}
.frame canvas.base{cursor:crosshair}
.frame canvas.top{position:absolute;left:0;top:0;pointer-events:none}
#stepper{min-width:18em;max-width:26em;flex:1 1 18em;border:1px solid #ddd;border-radius:6px;
  padding:.3em .9em .8em;background:#fafafa}
#stepper h2{margin-top:.4em}
#step-position{margin:.2em 0}
.buttons{display:flex;gap:.3em;flex-wrap:wrap}
.buttons button{font:inherit;font-size:.95em;padding:.2em .55em}
#step-title{font-weight:600;margin:.5em 0;min-height:1.4em;word-break:break-word}
table{border-collapse:collapse;font-size:14px}
td,th{border:1px solid #ccc;padding:2px 8px;text-align:left;vertical-align:top}
th{background:#f0f0f0}
td.num{text-align:right;font-variant-numeric:tabular-nums}
#step-state td:last-child{font-family:ui-monospace,"DejaVu Sans Mono",monospace}
#step-pixels{font-size:.88em;color:#444;word-break:break-word}
#pixel-readout{font-variant-numeric:tabular-nums;margin:.8em 0 .2em;min-height:1.4em}
#pixel-reason{margin:0 0 .6em;color:#b00020;min-height:1.4em}
#legends{display:flex;gap:2em;flex-wrap:wrap;font-size:14px}
#legends ul{list-style:none;padding:0;margin:.3em 0}
#legends li{margin:.15em 0}
.swatch{display:inline-block;width:1.1em;height:1.1em;border:1px solid #999;vertical-align:middle;
  margin-right:.4em;box-sizing:border-box}
.line{display:inline-block;width:1.6em;height:0;border-top:3px solid;vertical-align:middle;
  margin-right:.4em}
tr.diff{cursor:pointer}tr.diff:hover{background:#eef8ff}
tr.diff.selected{background:#c9f3ff}
#differences td.reason{max-width:50em}
#command{user-select:all}
#step-slider{width:100%;margin:.5em 0 .2em}
[hidden]{display:none !important}
#pseudo-code{margin:.4em 0 .6em;padding-left:2.2em;font-size:.86em}
#pseudo-code li{padding:1px 4px;border-radius:3px;white-space:pre-wrap}
#pseudo-code li code{background:none;padding:0;font-size:1em}
#pseudo-code li.current{background:#ffe082;font-weight:600}
#step-part{margin:.3em 0 0;font-size:.92em}
/* On paper (a handout, a PDF for slides): the images and the current step, no controls. */
@media print{
  body{margin:0;max-width:none;font-size:10.5pt}
  #controls,.buttons,#step-slider,#step-keys{display:none}
  .frame,.swatch,.line{-webkit-print-color-adjust:exact;print-color-adjust:exact}
  #views{gap:10px}
  #stepper{border:none;background:none;padding:0;max-width:none}
  figure,#stepper,#legends,table{break-inside:avoid}
  tr.diff.selected{background:none}
}
</style>
)CSS";

const char* kScript = R"JS(<script>
(function () {
  'use strict';
  function $(id) { return document.getElementById(id); }
  var data = JSON.parse($('teach-data').textContent);
  var W = Math.max(0, Math.floor(+data.width || 0)), H = Math.max(0, Math.floor(+data.height || 0));
  var N = W * H;
  var steps = Array.isArray(data.steps) ? data.steps : [];
  var diffs = Array.isArray(data.differences) ? data.differences : [];
  var input = Array.isArray(data.input) ? data.input : [];
  var dpr = window.devicePixelRatio || 1;

  function bytes(a) {
    var out = new Uint8ClampedArray(N * 4);
    if (Array.isArray(a)) for (var i = 0; i < out.length && i < a.length; ++i) out[i] = +a[i] || 0;
    return out;
  }
  var algRgba = bytes(data.algorithm_rgba), glRgba = bytes(data.gl_rgba);
  function inside(x, y) {
    return x >= 0 && y >= 0 && x < W && y < H && x === Math.floor(x) && y === Math.floor(y);
  }
  function isLit(g) { return g === true || (typeof g === 'number' && g > 0); }
  function num(v) {
    var n = +v;
    return isFinite(n) ? String(Math.round(n * 10000) / 10000) : String(v);
  }

  // The differences by pixel, and each one's class in the mask.
  var diffAt = new Int32Array(N).fill(-1);
  diffs.forEach(function (d, i) {
    var x = +d.x, y = +d.y;
    if (inside(x, y) && diffAt[y * W + x] < 0) diffAt[y * W + x] = i;
  });
  var MASK = { alg: [255, 109, 0], gl: [41, 121, 255], partial: [255, 214, 0] };
  function diffClass(d) {
    var a = +d.algorithm || 0, g = isLit(d.gl);
    if (a >= 1 && !g) return 'alg';
    if (a <= 0 && g) return 'gl';
    return 'partial';
  }
  // An equal pixel is a dark grey from GL's luminance: never a hue, so that no scene colour can
  // look like one of the mask's three.
  var maskRgba = new Uint8ClampedArray(N * 4);
  for (var i = 0; i < N; ++i) {
    var c = diffAt[i] >= 0 ? MASK[diffClass(diffs[diffAt[i]])] : null;
    var lum = 0.2126 * glRgba[4 * i] + 0.7152 * glRgba[4 * i + 1] + 0.0722 * glRgba[4 * i + 2];
    for (var k = 0; k < 3; ++k) maskRgba[4 * i + k] = c ? c[k] : 40 + 0.25 * lum;
    maskRgba[4 * i + 3] = 255;
  }

  // Images: a W x H canvas each, rows flipped (row 0 of the data is the bottom row).
  function sourceCanvas(rgba) {
    var c = document.createElement('canvas');
    c.width = Math.max(1, W); c.height = Math.max(1, H);
    if (N > 0) {
      var img = new ImageData(W, H);
      for (var y = 0; y < H; ++y) {
        img.data.set(rgba.subarray(y * W * 4, (y + 1) * W * 4), (H - 1 - y) * W * 4);
      }
      c.getContext('2d').putImageData(img, 0, 0);
    }
    return c;
  }
  var algFinal = sourceCanvas(algRgba);
  var algSteps = sourceCanvas(new Uint8ClampedArray(N * 4));
  var panels = ['algorithm', 'gl', 'mask'].map(function (name) {
    var base = $('img-' + name);
    return { name: name, base: base, top: base.parentNode.querySelector('canvas.top') };
  });
  panels[1].src = sourceCanvas(glRgba);
  panels[2].src = sourceCanvas(maskRgba);

  var zoomInput = $('zoom'), modeInput = $('step-mode');
  var z = +zoomInput.value || 8;
  var hover = null, selected = null, at = 0;
  function stepMode() { return steps.length > 0 && modeInput.checked; }

  // The steps: state[i] is the weight the steps up to `cur` decided at pixel i (-1: none yet;
  // a later step overrides an earlier one). States are saved every `every` steps as the walk
  // passes them, so that a step back replays at most `every` steps.
  var every = Math.max(32, Math.ceil(steps.length * N / 4e6));
  var state = new Float32Array(N).fill(-1), cur = -1, saved = {};
  function stepPixels(k) {
    var px = steps[k] && steps[k].pixels;
    return Array.isArray(px) ? px : [];
  }
  function advance() {
    ++cur;
    stepPixels(cur).forEach(function (p) {
      if (Array.isArray(p) && inside(+p[0], +p[1])) state[+p[1] * W + +p[0]] = +p[2] || 0;
    });
    if ((cur + 1) % every === 0 && !saved[cur]) saved[cur] = state.slice();
  }
  function seek(k) {
    if (k < cur || k - cur > every) {
      var c = Math.floor((k + 1) / every) * every - 1;
      while (c >= 0 && !saved[c]) c -= every;
      if (k < cur || c > cur) {
        if (c >= 0) state.set(saved[c]); else state.fill(-1);
        cur = c;
      }
    }
    while (cur < k) advance();
  }
  var stepImage = N > 0 ? new ImageData(W, H) : null;
  function paintSteps() {
    if (!stepImage) return;
    var d = stepImage.data;
    for (var y = 0; y < H; ++y) {
      for (var x = 0; x < W; ++x) {
        var w = state[y * W + x], o = ((H - 1 - y) * W + x) * 4, r, g, b;
        if (w < 0) { r = g = b = 24; }
        else if (w === 0) { r = 112; g = 30; b = 30; }
        else { r = g = b = 24 + 231 * Math.min(1, w); }
        d[o] = r; d[o + 1] = g; d[o + 2] = b; d[o + 3] = 255;
      }
    }
    algSteps.getContext('2d').putImageData(stepImage, 0, 0);
  }

  // Drawing: pixels, grid (zoom 4 and more), the input geometry, and in step mode the current
  // step's pixels outlined and its overlay; the pointer and the chosen pixel on a canvas above.
  var ROLE_COLOURS = ['#00e676', '#40c4ff', '#eeff41', '#ea80fc', '#ffab40', '#a7ffeb'];
  var roles = [];
  input.forEach(function (s) {
    var r = String(s && s.role !== undefined ? s.role : '');
    if (roles.indexOf(r) < 0) roles.push(r);
  });
  function roleColour(s) {
    var r = roles.indexOf(String(s && s.role !== undefined ? s.role : ''));
    return ROLE_COLOURS[Math.max(0, r) % ROLE_COLOURS.length];
  }
  function sx(x) { return x * z; }
  function sy(y) { return (H - y) * z; }
  function resize(c) {
    var w = Math.round(W * z * dpr), h = Math.round(H * z * dpr);
    if (c.width !== w || c.height !== h) { c.width = w; c.height = h; }
    c.style.width = (W * z) + 'px'; c.style.height = (H * z) + 'px';
    var ctx = c.getContext('2d');
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    return ctx;
  }
  function grid(ctx) {
    [[1, 'rgba(128,128,128,0.45)'], [8, 'rgba(170,170,170,0.9)']].forEach(function (g) {
      ctx.beginPath();
      for (var i = 0; i <= W; i += g[0]) {
        var x = Math.min(i * z, W * z - 1) + 0.5;
        ctx.moveTo(x, 0); ctx.lineTo(x, H * z);
      }
      for (var j = 0; j <= H; j += g[0]) {
        var y = Math.min(sy(j), H * z - 1) + 0.5;
        ctx.moveTo(0, y); ctx.lineTo(W * z, y);
      }
      ctx.strokeStyle = g[1]; ctx.lineWidth = 1; ctx.stroke();
    });
  }
  function segments(ctx, list, colour, width, dots) {
    ctx.lineCap = 'round';
    list.forEach(function (s) {
      if (!s) return;
      var x0 = +s.x0, y0 = +s.y0, x1 = +s.x1, y1 = +s.y1;
      if (![x0, y0, x1, y1].every(isFinite)) return;
      var col = typeof colour === 'function' ? colour(s) : colour;
      ctx.strokeStyle = col; ctx.fillStyle = col; ctx.lineWidth = width;
      ctx.beginPath(); ctx.moveTo(sx(x0), sy(y0)); ctx.lineTo(sx(x1), sy(y1)); ctx.stroke();
      if (dots || (x0 === x1 && y0 === y1)) {
        [[x0, y0], [x1, y1]].forEach(function (p) {
          ctx.beginPath(); ctx.arc(sx(p[0]), sy(p[1]), width + 1, 0, 2 * Math.PI); ctx.fill();
        });
      }
    });
  }
  function outline(ctx, x, y, colour, width, inset, dash) {
    ctx.setLineDash(dash || []);
    ctx.strokeStyle = colour; ctx.lineWidth = width;
    ctx.strokeRect(sx(x) + inset, sy(y + 1) + inset, z - 2 * inset, z - 2 * inset);
    ctx.setLineDash([]);
  }
  function drawBase(p) {
    if (N === 0) return;
    var ctx = resize(p.base);
    ctx.imageSmoothingEnabled = false;
    ctx.fillStyle = '#000'; ctx.fillRect(0, 0, W * z, H * z);
    var src = p.name === 'algorithm' ? (stepMode() ? algSteps : algFinal) : p.src;
    ctx.drawImage(src, 0, 0, W * z, H * z);
    if (z >= 4) grid(ctx);
    segments(ctx, input, roleColour, 1.5, true);
    if (p.name === 'algorithm' && stepMode()) {
      var inset = z >= 6 ? 1.5 : 0.5, lw = z >= 6 ? 2 : 1;
      stepPixels(at).forEach(function (q) {
        if (!Array.isArray(q) || !inside(+q[0], +q[1])) return;
        if (+q[2] > 0) outline(ctx, +q[0], +q[1], '#ffd600', lw, inset);
        else outline(ctx, +q[0], +q[1], '#ff1744', lw, inset, [3, 2]);
      });
      var ov = steps[at] && Array.isArray(steps[at].overlay) ? steps[at].overlay : [];
      segments(ctx, ov, '#ff4081', 2.5, false);
    }
    var r = p.base.getBoundingClientRect();
    p.base.dataset.rect = [r.left + window.scrollX, r.top + window.scrollY, r.width, r.height]
        .map(Math.round).join(',');
  }
  function drawTop() {
    if (N === 0) return;
    panels.forEach(function (p) {
      var ctx = resize(p.top);
      ctx.clearRect(0, 0, W * z, H * z);
      if (selected) {
        outline(ctx, selected.x, selected.y, '#000', 5, -2.5);
        outline(ctx, selected.x, selected.y, '#00e5ff', 3, -2.5);
      }
      if (hover) outline(ctx, hover.x, hover.y, '#00e5ff', 1, -0.5);
    });
  }
  function drawAll() { panels.forEach(drawBase); drawTop(); }

  // The pixel under the pointer (or the chosen one): coordinates, both values, the reason.
  var readoutEl = $('pixel-readout'), reasonEl = $('pixel-reason');
  var readoutHint = readoutEl.textContent;
  function rgbaText(a, i) {
    return 'rgba(' + a[4 * i] + ', ' + a[4 * i + 1] + ', ' + a[4 * i + 2] + ', ' + a[4 * i + 3] + ')';
  }
  function readout() {
    var px = hover || selected;
    if (!px) { readoutEl.textContent = readoutHint; reasonEl.textContent = ''; return; }
    var i = px.y * W + px.x, k = diffAt[i], d = k >= 0 ? diffs[k] : null;
    var s = 'pixel (' + px.x + ', ' + px.y + '): algorithm ' + rgbaText(algRgba, i);
    if (d) s += ', weight ' + num(d.algorithm);
    s += '; ' + (data.beside ? String(data.beside) : 'GL') + ' ' + rgbaText(glRgba, i);
    if (d) s += isLit(d.gl) ? ', lit' : ', not lit';
    if (steps.length) {
      var w = state[i];
      s += '; after step ' + (at + 1) + ': ' + (w < 0 ? 'not decided yet' :
          w === 0 ? 'considered and rejected' : 'weight ' + num(w));
    }
    readoutEl.textContent = s + (d ? '. They differ:' : '. The same in both.');
    reasonEl.textContent = d ? String(d.reason === undefined ? '' : d.reason) : '';
  }
  function keepHash() {
    var h = '#step=' + (at + 1) + (selected ? '&pixel=' + selected.x + ',' + selected.y : '');
    try { history.replaceState(null, '', h); } catch (e) { /* a page without history */ }
  }
  var rows = Array.prototype.slice.call(document.querySelectorAll('#differences tr.diff'));
  function select(px) {
    selected = px;
    rows.forEach(function (r) {
      r.classList.toggle('selected', !!px && +r.dataset.x === px.x && +r.dataset.y === px.y);
    });
    readout(); drawTop(); keepHash();
  }
  rows.forEach(function (r) {
    function pick() { select({ x: +r.dataset.x, y: +r.dataset.y }); }
    r.addEventListener('click', pick);
    r.addEventListener('keydown', function (e) {
      if (e.key === 'Enter' || e.key === ' ') { e.preventDefault(); pick(); }
    });
  });
  panels.forEach(function (p) {
    function at_pointer(e) {
      var r = p.base.getBoundingClientRect();
      if (!r.width || !r.height) return null;
      var x = Math.floor((e.clientX - r.left) / r.width * W);
      var row = Math.floor((e.clientY - r.top) / r.height * H);
      return { x: Math.max(0, Math.min(W - 1, x)), y: H - 1 - Math.max(0, Math.min(H - 1, row)) };
    }
    p.base.addEventListener('mousemove', function (e) {
      var px = at_pointer(e);
      if (px && (!hover || hover.x !== px.x || hover.y !== px.y)) { hover = px; readout(); drawTop(); }
    });
    p.base.addEventListener('mouseleave', function () { hover = null; readout(); drawTop(); });
    p.base.addEventListener('click', function (e) {
      var px = at_pointer(e);
      if (px) select(selected && selected.x === px.x && selected.y === px.y ? null : px);
    });
  });

  // The step-through.
  var buttons = { first: $('step-first'), prev: $('step-prev'), next: $('step-next'), last: $('step-last') };
  function cell(tr, tag, text) {
    var c = document.createElement(tag); c.textContent = text; tr.appendChild(c);
  }
  function show(k) {
    if (!steps.length) return;
    at = Math.max(0, Math.min(steps.length - 1, Math.floor(+k) || 0));
    seek(at); paintSteps();
    var s = steps[at] || {};
    $('step-index').textContent = String(at);
    $('step-number').textContent = String(at + 1);
    $('step-title').textContent = String(s.title === undefined ? '' : s.title);
    var code = $('pseudo-code');
    if (code) {
      var line = Math.floor(+s.line) || 0;
      Array.prototype.forEach.call(code.children, function (li, k) {
        li.classList.toggle('current', k + 1 === line);
      });
    }
    var body = $('step-state').tBodies[0];
    while (body.firstChild) body.removeChild(body.firstChild);
    (Array.isArray(s.state) ? s.state : []).forEach(function (pair) {
      var tr = document.createElement('tr');
      cell(tr, 'td', String(Array.isArray(pair) ? pair[0] : pair));
      cell(tr, 'td', Array.isArray(pair) && pair.length > 1 ? String(pair[1]) : '');
      body.appendChild(tr);
    });
    var px = stepPixels(at), shown = px.slice(0, 24).map(function (q) {
      return Array.isArray(q) ? '(' + q[0] + ', ' + q[1] + ') ' +
          (+q[2] > 0 ? 'weight ' + num(q[2]) : 'rejected') : '';
    });
    $('step-pixels').textContent = px.length === 0 ? 'This step decides no pixel.' :
        'This step decides ' + (px.length === 1 ? '1 pixel' : px.length + ' pixels') + ': ' +
        shown.join(', ') + (px.length > shown.length ? ', ...' : '') + '.';
    buttons.first.disabled = buttons.prev.disabled = at === 0;
    buttons.next.disabled = buttons.last.disabled = at === steps.length - 1;
    if (slider) slider.value = String(at + 1);
    if (typeof showPart === 'function') showPart();
    drawBase(panels[0]); readout(); keepHash();
  }
  // The slider, playing, and stepping a part (a segment, a polygon) at a time.
  var slider = $('step-slider'), playButton = $('step-play'), speedInput = $('step-speed');
  var parts = [];  // runs of consecutive steps of one group: {name, first, last}
  steps.forEach(function (st, k) {
    var g = st && typeof st.group === 'string' ? st.group : '';
    if (parts.length && parts[parts.length - 1].name === g) parts[parts.length - 1].last = k;
    else parts.push({ name: g, first: k, last: k });
  });
  function partOf(k) {
    for (var i = 0; i < parts.length; ++i) if (k <= parts[i].last) return i;
    return parts.length - 1;
  }
  var hasParts = parts.length > 1;
  if (!hasParts) $('part-buttons').hidden = true;
  function showPart() {
    if (!hasParts || !steps.length) return;
    var i = partOf(at), p = parts[i];
    $('step-part').textContent = (p.name || 'before the first part') + ': steps ' +
        (p.first + 1) + ' to ' + (p.last + 1) + ' (part ' + (i + 1) + ' of ' + parts.length + ')';
    $('part-prev').disabled = at === 0;
    $('part-next').disabled = i === parts.length - 1;
  }
  function previousPart() {
    var i = partOf(at);
    show(at > parts[i].first ? parts[i].first : parts[Math.max(0, i - 1)].first);
  }
  function nextPart() {
    var i = partOf(at);
    if (i + 1 < parts.length) show(parts[i + 1].first);
  }
  var timer = null;
  function stop() {
    if (timer !== null) clearInterval(timer);
    timer = null;
    playButton.textContent = 'Play';
  }
  function play() {
    if (timer !== null) { stop(); return; }
    if (at === steps.length - 1) show(0);
    var rate = Math.max(1, Math.min(100, +speedInput.value || 4));
    playButton.textContent = 'Pause';
    timer = setInterval(function () {
      if (at >= steps.length - 1) { stop(); return; }
      show(at + 1);
    }, 1000 / rate);
  }
  slider.addEventListener('input', function () { show(+slider.value - 1); });
  playButton.addEventListener('click', play);
  speedInput.addEventListener('change', function () { if (timer !== null) { stop(); play(); } });
  $('part-prev').addEventListener('click', previousPart);
  $('part-next').addEventListener('click', nextPart);
  buttons.first.addEventListener('click', function () { show(0); });
  buttons.prev.addEventListener('click', function () { show(at - 1); });
  buttons.next.addEventListener('click', function () { show(at + 1); });
  buttons.last.addEventListener('click', function () { show(steps.length - 1); });
  document.addEventListener('keydown', function (e) {
    if (e.ctrlKey || e.altKey || e.metaKey || !steps.length) return;
    var t = e.target;
    if (t && t.closest && t.closest('input, select, textarea')) return;
    if (e.key === 'p') { e.preventDefault(); play(); return; }
    if (e.key === 'PageUp' && hasParts) { e.preventDefault(); previousPart(); return; }
    if (e.key === 'PageDown' && hasParts) { e.preventDefault(); nextPart(); return; }
    var to = { ArrowRight: at + 1, ArrowLeft: at - 1, Home: 0, End: steps.length - 1 }[e.key];
    if (to === undefined) return;
    e.preventDefault(); show(to);
  });

  // Zoom, the algorithm image's mode, the geometry's legend, the command's directory.
  function applyZoom() {
    z = Math.max(1, Math.min(32, Math.floor(+zoomInput.value) || 1));
    $('zoom-value').textContent = String(z);
    drawAll();
  }
  zoomInput.addEventListener('input', applyZoom);
  modeInput.addEventListener('change', function () { drawBase(panels[0]); });
  if (!steps.length) { modeInput.checked = false; modeInput.disabled = true; }
  var legend = $('geometry-legend');
  roles.forEach(function (r) {
    var li = document.createElement('li'), line = document.createElement('span');
    line.className = 'line'; line.style.borderColor = roleColour({ role: r });
    li.appendChild(line); li.appendChild(document.createTextNode('input: ' + (r || 'geometry')));
    legend.appendChild(li);
  });
  if (location.protocol === 'file:') {
    var dir = decodeURIComponent(location.pathname.replace(/\/[^\/]*$/, '')) || '/';
    $('command-dir').textContent = /^[A-Za-z0-9_.\/=,:+@%-]+$/.test(dir) ? dir :
        "'" + dir.replace(/'/g, "'\\''") + "'";
  }

  // The view a link asks for: #step=K (1-based), #pixel=X,Y, #view=final, #speed=N (steps a
  // second when playing), then #press=a,b,... (buttons clicked: first, prev, next, last, play,
  // part-prev, part-next; and keys pressed, in order, as a reader would).
  var hash = {};
  location.hash.replace(/^#/, '').split('&').forEach(function (kv) {
    var e = kv.indexOf('=');
    if (e > 0) {
      try { hash[kv.slice(0, e)] = decodeURIComponent(kv.slice(e + 1)); } catch (err) { /* bad */ }
    }
  });
  if (hash.view === 'final') modeInput.checked = false;
  applyZoom();
  // #step=K is the page's Step K, counted from 1 as the page counts them.
  if (hash.speed !== undefined) speedInput.value = String(hash.speed);
  show(hash.step !== undefined ? +hash.step - 1 : 0);
  var pm = /^(\d+),(\d+)$/.exec(hash.pixel || '');
  if (pm && inside(+pm[1], +pm[2])) select({ x: +pm[1], y: +pm[2] });
  (hash.press ? hash.press.split(',') : []).forEach(function (a) {
    a = a.trim();
    var more = { play: playButton, 'part-prev': $('part-prev'), 'part-next': $('part-next') };
    if (buttons[a]) buttons[a].click();
    else if (more[a]) more[a].click();
    else if (['ArrowRight', 'ArrowLeft', 'Home', 'End', 'PageUp', 'PageDown', 'p'].indexOf(a) >= 0) {
      document.dispatchEvent(new KeyboardEvent('keydown', { key: a, bubbles: true, cancelable: true }));
    }
  });
  window.addEventListener('resize', drawAll);
  document.body.dataset.ready = '1';
})();
</script>
)JS";

}  // namespace

std::string teach_page_html(const nlohmann::json& data) {
    static const json empty = json::object();
    const json& d = data.is_object() ? data : empty;
    const std::string title = field(d, "title");
    const std::string algorithm = field(d, "algorithm");
    const std::string scene = field(d, "scene");
    const std::string scene_file = field(d, "scene_file");
    const std::string beside = field(d, "beside");  // another algorithm where GL's image is
    const long long width = std::max(0LL, int_field(d, "width"));
    const long long height = std::max(0LL, int_field(d, "height"));
    const long long zoom = std::clamp(
        std::llround(256.0 / static_cast<double>(std::max({width, height, 1LL}))), 1LL, 32LL);
    const json& steps = array_field(d, "steps");
    const json& differences = array_field(d, "differences");
    const json& notes = array_field(d, "notes");

    std::ostringstream h;
    h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
         "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>"
      << markup::escape(title.empty() ? algorithm : title) << " &middot; " << markup::escape(scene)
      << "</title>\n"
      << kStyle << "</head>\n<body>\n";

    // What this page is.
    h << "<header><h1>" << markup::escape(title) << " <span class=\"algo\">("
      << markup::escape(algorithm) << ") "
      << (beside.empty() ? std::string("against GL's rules") : "beside " + markup::escape(beside))
      << "</span></h1>\n<p id=\"meta\">Scene <code id=\"scene\">" << markup::escape(scene)
      << "</code> from <code>" << markup::escape(scene_file) << "</code>, a " << width << "&times;"
      << height
      << " target (pixel (x, y), y up from the bottom row as GL counts it). GL's rules: <span "
         "id=\"gl-source\">"
      << markup::escape(field(d, "gl_source")) << "</span>.</p>\n<p id=\"summary\">"
      << markup::escape(field(d, "summary")) << "</p></header>\n";

    // Controls, the three images and the step-through beside them.
    h << "<div id=\"controls\"><label>Zoom <input id=\"zoom\" type=\"range\" min=\"1\" "
         "max=\"32\" value=\""
      << zoom << "\"></label> <span><span id=\"zoom-value\">" << zoom
      << "</span>&times;</span><label><input type=\"checkbox\" id=\"step-mode\" checked> the "
         "algorithm's image as the steps so far have drawn it (unchecked: its final "
         "image)</label></div>\n<div id=\"views\">\n";
    const auto panel = [&](const char* id, const std::string& caption) {
        h << "<figure><div class=\"frame\"><canvas id=\"img-" << id
          << "\" class=\"base\" width=\"0\" height=\"0\"></canvas><canvas class=\"top\" "
             "width=\"0\" height=\"0\"></canvas></div><figcaption>"
          << caption << "</figcaption></figure>\n";
    };
    panel("algorithm", "<b>" + markup::escape(title.empty() ? algorithm : title) + "</b>");
    panel("gl", beside.empty() ? std::string("<b>GL's rules</b>")
                               : "<b>" + markup::escape(beside) + "</b>");
    panel("mask", "<b>difference mask</b> (" + std::to_string(differences.size()) +
                      (differences.size() == 1 ? " pixel differs" : " pixels differ") + ")");
    h << "<section id=\"stepper\"><h2>Step-through</h2><p id=\"step-position\">Step <b "
         "id=\"step-number\">"
      << (steps.empty() ? 0 : 1) << "</b> of <b id=\"step-count\">" << steps.size()
      << "</b> <span class=\"muted\">(index <span id=\"step-index\">0</span>)</span></p>"
         "<div class=\"buttons\"><button id=\"step-first\" type=\"button\">First</button>"
         "<button id=\"step-prev\" type=\"button\">Previous</button>"
         "<button id=\"step-next\" type=\"button\">Next</button>"
         "<button id=\"step-last\" type=\"button\">Last</button>"
         "<button id=\"step-play\" type=\"button\">Play</button><label>at <select "
         "id=\"step-speed\"><option value=\"1\">1</option><option value=\"4\" "
         "selected>4</option><option value=\"15\">15</option><option "
         "value=\"60\">60</option></select> steps a second</label></div>"
         "<input id=\"step-slider\" type=\"range\" min=\"1\" max=\""
      << std::max<std::size_t>(steps.size(), 1) << "\" value=\"1\" aria-label=\"step\""
      << (steps.empty() ? " disabled" : "")
      << "><div class=\"buttons\" id=\"part-buttons\"><button id=\"part-prev\" "
         "type=\"button\">&larr; Part</button><button id=\"part-next\" "
         "type=\"button\">Part &rarr;</button><p id=\"step-part\"></p></div>"
         "<p class=\"muted\" id=\"step-keys\">Keys: &larr; &rarr; Home End, PageUp PageDown "
         "by part (a segment, a polygon), p to play. A link to a step: "
         "<code>#step=K</code> opens step K.</p><p id=\"step-title\">";
    if (steps.empty()) {
        h << "This algorithm recorded no steps.";
    } else {
        h << markup::escape(
            text_of(steps[0].is_object() ? steps[0].value("title", json()) : json()));
    }
    h << "</p>";
    // The algorithm's pseudo-code, the current step's line highlighted (by the script).
    {
        const json& code = array_field(d, "pseudo_code");
        if (!code.empty()) {
            h << "<ol id=\"pseudo-code\">";
            for (const json& line : code)
                h << "<li><code>" << markup::escape(text_of(line)) << "</code></li>";
            h << "</ol>";
        }
    }
    h << "<table id=\"step-state\"><thead><tr><th>variable</th><th>value</th></tr></thead>"
         "<tbody></tbody></table><p id=\"step-pixels\"></p></section>\n</div>\n";

    // The pixel under the pointer, and what the colours mean.
    h << "<p id=\"pixel-readout\">Move the pointer over an image: its pixel (x, y), both values "
         "and, where they differ, why. Click a pixel, or a row of the list below, to outline it "
         "in all three images.</p><p id=\"pixel-reason\"></p>\n"
         "<div id=\"legends\"><div><b>difference mask</b><ul id=\"mask-legend\">"
         "<li><span class=\"swatch\" style=\"background:#ff6d00\"></span>lit by the algorithm "
         "only</li>"
         "<li><span class=\"swatch\" style=\"background:#2979ff\"></span>lit by "
      << (beside.empty() ? std::string("GL") : markup::escape(beside))
      << " only</li>"
         "<li><span class=\"swatch\" style=\"background:#ffd600\"></span>partial weights that "
         "differ (or both lit, differently)</li>"
         "<li><span class=\"swatch\" style=\"background:#333\"></span>equal (dark greys: GL's "
         "image by its brightness alone)</li></ul></div>"
         "<div><b>the algorithm's image, step by step</b><ul id=\"step-legend\">"
         "<li><span class=\"swatch\" style=\"background:#fff\"></span>decided: brightness is "
         "the weight</li>"
         "<li><span class=\"swatch\" style=\"background:#701e1e\"></span>considered and "
         "rejected</li>"
         "<li><span class=\"swatch\" style=\"background:#181818;border:2px solid "
         "#ffd600\"></span>this step's pixels (dashed red: rejected)</li>"
         "<li><span class=\"line\" style=\"border-color:#ff4081\"></span>this step's "
         "construction</li></ul></div>"
         "<div><b>geometry and pixels</b><ul id=\"geometry-legend\">"
         "<li><span class=\"swatch\" style=\"background:#000;border:2px solid "
         "#00e5ff\"></span>the chosen pixel</li></ul></div></div>\n";

    // Where they differ.
    h << "<h2>Where they differ</h2>\n";
    if (differences.empty()) {
        h << "<p id=\"no-differences\">No pixel differs: the algorithm and "
          << (beside.empty() ? std::string("GL's rules") : markup::escape(beside))
          << " light the same pixels here.</p>\n";
    } else {
        h << "<table id=\"differences\"><thead><tr><th>x</th><th>y</th><th>algorithm's "
             "weight</th><th>"
          << (beside.empty() ? std::string("GL") : markup::escape(beside))
          << "</th><th>reason</th></tr></thead><tbody>\n";
        std::size_t i = 0;
        for (const auto& e : differences) {
            const json& diff = e.is_object() ? e : empty;
            const std::string x = field(diff, "x"), y = field(diff, "y");
            h << "<tr class=\"diff\" tabindex=\"0\" data-index=\"" << i++ << "\" data-x=\""
              << markup::escape(x) << "\" data-y=\"" << markup::escape(y) << "\"><td class=\"num\">"
              << markup::escape(x) << "</td><td class=\"num\">" << markup::escape(y)
              << "</td><td class=\"num\">" << markup::escape(field(diff, "algorithm"))
              << "</td><td>" << (lit(diff.value("gl", json())) ? "lit" : "not lit")
              << "</td><td class=\"reason\">" << markup::escape(field(diff, "reason"))
              << "</td></tr>\n";
        }
        h << "</tbody></table>\n";
    }

    h << "<h2>Notes</h2>\n";
    if (notes.empty()) {
        h << "<p id=\"notes\" class=\"muted\">No notes.</p>\n";
    } else {
        h << "<ul id=\"notes\">";
        for (const auto& n : notes) h << "<li>" << markup::escape(text_of(n)) << "</li>";
        h << "</ul>\n";
    }

    h << "<h2>Reproduce this page</h2>\n<p><code id=\"command\">refraster teach "
      << markup::escape(encode::shell_word(scene_file)) << " --algorithm "
      << markup::escape(encode::shell_word(algorithm))
      << markup::escape(d.contains("command_options") && d["command_options"].is_string()
                            ? d["command_options"].get<std::string>()
                            : std::string())
      << " --output <span id=\"command-dir\">DIR</span></code> <span class=\"muted\">(DIR: "
         "this page's directory)</span></p>\n";

    h << "<script type=\"application/json\" id=\"teach-data\">" << embedded_json(d) << "</script>\n"
      << kScript << "</body></html>\n";
    return h.str();
}

}  // namespace harness
