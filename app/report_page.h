// lockstep verify --report DIR: the template of DIR/index.html (app/report_page.cpp).
//
// One self-contained page: no network, no CDN; the CSS and JS are here, the
// run's data (DIR/report.json, schema lockstep-report/1) replaces
// @LOCKSTEP_DATA@ inside a <script type="application/json"> block, and the
// pictures are the report's own PNGs, by path relative to DIR. Pages opened from
// file:// cannot read the pixels of file:// images (they taint a canvas), so
// each case folder also has pixels.js: the same PNGs as data: URIs, loaded with
// a <script> tag when the case is opened (a script from file:// is allowed),
// for the readout under the cursor.
//
// Kept as a raw string so the page stays readable HTML/CSS/JS and needs no
// build step; `lockstep merge-reports` fills the same template from merged data.
#pragma once

#include <string_view>

namespace lockstep::cli {

inline constexpr std::string_view kReportPage = R"lockstep_page(<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>lockstep verify report</title>
<style>
  :root { --pass: #1a7f37; --fail: #cf222e; --muted: #656d76; --line: #d0d7de; --bg2: #f6f8fa; }
  body { font: 14px/1.4 system-ui, sans-serif; margin: 0 1.2em 2em; color: #1f2328; }
  h1 { font-size: 1.5em; margin: .6em 0 .2em; }
  h2 { font-size: 1.2em; margin: 1em 0 .4em; }
  h3 { font-size: 1em; margin: .8em 0 .3em; }
  .muted { color: var(--muted); }
  #summary b.pass { color: var(--pass); } #summary b.fail { color: var(--fail); }
  #charts { display: flex; flex-wrap: wrap; gap: 1em; align-items: flex-start; }
  #charts figure { margin: 0; border: 1px solid var(--line); border-radius: 6px; padding: .4em; background: #fff; }
  #charts figcaption { font-weight: 600; margin-bottom: .2em; }
  #charts .scroll { max-height: 420px; overflow-y: auto; }
  svg text { font: 11px system-ui, sans-serif; fill: #1f2328; }
  svg .axis { stroke: #8c959f; stroke-width: 1; } svg .grid { stroke: #eaeef2; stroke-width: 1; }
  #controls { position: sticky; top: 0; background: #fff; padding: .5em 0; border-bottom: 1px solid var(--line);
              display: flex; flex-wrap: wrap; gap: .8em; align-items: center; z-index: 2; }
  #controls label { white-space: nowrap; }
  table.rows { border-collapse: collapse; width: 100%; }
  table.rows th, table.rows td { border-bottom: 1px solid var(--line); padding: 2px 6px; text-align: left;
                                 vertical-align: top; }
  table.rows th { background: var(--bg2); cursor: pointer; user-select: none; white-space: nowrap; position: sticky; top: 2.6em; }
  table.rows th.sorted-asc::after { content: " \25B2"; } table.rows th.sorted-desc::after { content: " \25BC"; }
  table.rows td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
  table.rows td.note { font-size: 12px; color: #424a53; max-width: 48em; }
  table.rows tbody tr { cursor: pointer; } table.rows tbody tr:hover { background: #f3f7ff; }
  table.rows tr.current { background: #ddf4ff; }
  .verdict-PASS { color: var(--pass); font-weight: 600; } .verdict-FAIL { color: var(--fail); font-weight: 700; }
  #viewer { scroll-margin-top: 3.2em; border: 2px solid #54aeff; border-radius: 8px; padding: .2em 1em 1em; margin: 1em 0; background: #fbfdff; }
  #viewer header { display: flex; justify-content: space-between; align-items: baseline; }
  .toolbar { display: flex; flex-wrap: wrap; gap: .6em; align-items: center; margin: .4em 0; }
  #readout { font: 12px ui-monospace, monospace; background: var(--bg2); border: 1px solid var(--line);
             padding: 3px 6px; min-height: 1.4em; white-space: pre; overflow-x: auto; }
  .gallery { display: flex; flex-wrap: wrap; gap: .6em; align-items: flex-start; }
  .gallery figure { margin: 0; }
  .gallery figcaption { font-size: 12px; }
  .frame { overflow: auto; max-width: 92vw; width: max-content; max-height: 70vh; border: 1px solid var(--line);
           background: repeating-conic-gradient(#eee 0 25%, #fff 0 50%) 0 0 / 16px 16px; }
  img.px { image-rendering: pixelated; display: block; cursor: crosshair; }
  .compare { position: relative; display: block; }
  .compare img.top { position: absolute; left: 0; top: 0; }
  .compare .wipe-line { position: absolute; top: 0; bottom: 0; width: 0; border-left: 1px solid #ff0; pointer-events: none; }
  table.mini td, table.mini th { padding: 1px 6px; border-bottom: 1px solid var(--line); font-size: 12px; text-align: left; }
  table.mini td.num { text-align: right; }
  kbd { border: 1px solid var(--line); border-radius: 3px; padding: 0 3px; background: var(--bg2); }
</style>
</head>
<body>
<header>
  <h1>lockstep verify</h1>
  <p id="summary"></p>
  <p class="muted" id="legend"></p>
</header>

<section id="charts" aria-label="charts">
  <figure><figcaption>Speed against accuracy (rows other than the reference; log axes)</figcaption>
    <div class="toolbar">x: <select id="speed-x"><option value="worst">max error</option>
      <option value="pct">% over</option></select></div>
    <svg id="chart-speed" width="460" height="330"></svg></figure>
  <figure><figcaption>Time per case (each row's seconds, log axis)</figcaption>
    <div class="scroll"><svg id="chart-time" width="520" height="100"></svg></div></figure>
  <figure><figcaption>Time against work (log axes; k: time &prop; work<sup>k</sup>)</figcaption>
    <div class="toolbar">family: <select id="size-family"></select></div>
    <svg id="chart-size" width="460" height="330"></svg></figure>
  <figure><figcaption>Verdicts per family</figcaption>
    <svg id="chart-fail" width="360" height="100"></svg></figure>
</section>

<div id="controls">
  <label>family <select id="f-family"><option value="">all</option></select></label>
  <label>impl <select id="f-impl"><option value="">all</option></select></label>
  <label>verdict <select id="f-verdict"><option value="">all</option><option>PASS</option><option>FAIL</option></select></label>
  <label>text <input id="f-text" type="search" placeholder="case or note contains"></label>
  <span id="count" class="muted"></span>
</div>

<section id="viewer" hidden>
  <header><h2 id="v-title"></h2><span><span class="muted">keys: <kbd>f</kbd> flip A/B, <kbd>+</kbd>/<kbd>-</kbd> zoom, <kbd>Esc</kbd> close</span>
    <button id="v-close">close</button></span></header>
  <p id="v-info"></p>
  <table class="mini" id="v-rows"></table>
  <div class="toolbar">zoom <button id="zoom-out">&minus;</button> <span id="zoom-level">1&times;</span>
    <button id="zoom-in">+</button> <button id="zoom-1">1:1</button>
    <span class="muted">(or the wheel over a picture; pixels stay square, nearest neighbour)</span></div>
  <div id="readout">move the mouse over a picture</div>
  <h3>Outputs</h3><div class="gallery" id="g-views"></div>
  <h3>Differences from the reference (the reference's: from its golden)</h3><div class="gallery" id="g-heat"></div>
  <div id="g-judge-wrap"><h3>Judge masks</h3><div class="gallery" id="g-judge"></div></div>
  <h3>Compare</h3>
  <div class="toolbar">A <select id="cmp-a"></select> B <select id="cmp-b"></select>
    wipe <input type="range" id="wipe" min="0" max="100" value="50"> <button id="flip">flip A/B (<kbd>f</kbd>)</button> <button id="peek" title="hover: B alone">hover for B</button>
    <span id="flip-state" class="muted"></span></div>
  <div class="frame" id="cmp-frame"><div class="compare" id="compare">
    <img class="px" id="cmp-img-b" alt="B"><img class="px top" id="cmp-img-a" alt="A"><div class="wipe-line" id="wipe-line"></div>
  </div></div>
</section>

<h2 id="rows-title">Rows</h2>
<table class="rows" id="rows">
  <thead><tr>
    <th data-key="case">case</th><th data-key="family">family</th><th data-key="impl">impl</th>
    <th data-key="worst">max err</th><th data-key="pct">% over</th><th data-key="score">score</th>
    <th data-key="seconds">time s</th><th data-key="speedup">speedup</th><th data-key="verdict">verdict</th>
    <th data-key="note">note</th>
  </tr></thead>
  <tbody></tbody>
</table>
<div id="verdicts"></div>

<script id="lockstep-data" type="application/json">@LOCKSTEP_DATA@</script>
<script>
'use strict';
const D = JSON.parse(document.getElementById('lockstep-data').textContent);
const $ = (id) => document.getElementById(id);
const SVGNS = 'http://www.w3.org/2000/svg';
function el(tag, attrs, ...kids) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) {
    if (k === 'class') e.className = v; else if (k === 'text') e.textContent = v; else e.setAttribute(k, v);
  }
  for (const k of kids) e.append(k);
  return e;
}
function sv(tag, attrs, text) {
  const e = document.createElementNS(SVGNS, tag);
  for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  return e;
}
const PALETTE = ['#0969da', '#cf222e', '#1a7f37', '#8250df', '#bc4c00', '#0598bc', '#bf3989', '#6e7781', '#9a6700',
                 '#116329', '#953800', '#4d2d00'];
function colours(names) { const m = new Map(); names.forEach((n, i) => m.set(n, PALETTE[i % PALETTE.length])); return m; }
const uniq = (xs) => [...new Set(xs)];

// ---------------------------------------------------------------- rows
const rows = D.rows.map((r, i) => Object.assign({}, r, {
  index: i, verdict: r.pass ? 'PASS' : 'FAIL', compared: r.ran && r.samples > 0,
  pct: r.ran && r.samples > 0 ? 100 * r.over / r.samples : null,
}));
const info = new Map(D.case_info.map((c) => [c.case, c]));
const families = uniq(rows.map((r) => r.family)), impls = uniq(rows.map((r) => r.impl));
const famColour = colours(families), implColour = colours(impls);
const nfail = rows.filter((r) => !r.pass).length;

function fmtG(x, p) { return x === null ? 'inf' : Number(x.toPrecision(p)).toString(); }
function cell(r, key) {
  switch (key) {
    case 'worst': return r.compared ? fmtG(r.worst, 3) : '-';
    case 'pct': return r.compared ? r.pct.toFixed(3) : '-';
    case 'score': return r.compared ? (r.score === null ? 'inf' : r.score.toFixed(1)) : '-';
    case 'seconds': return r.seconds.toFixed(3);
    case 'speedup': return r.ran && r.speedup !== null ? r.speedup.toFixed(1) + '\u00d7' : '-';
    default: return String(r[key]);
  }
}
// Sort keys: numbers with '-' (not compared) last; infinite (null) worst/score sorts as the extreme.
function sortValue(r, key) {
  if (key === 'worst') return r.compared ? (r.worst === null ? Infinity : r.worst) : undefined;
  if (key === 'score') return r.compared ? (r.score === null ? Infinity : r.score) : undefined;
  if (key === 'pct') return r.compared ? r.pct : undefined;
  if (key === 'speedup') return r.ran && r.speedup !== null ? r.speedup : undefined;
  if (key === 'verdict') return r.pass ? 1 : 0;  // failures first
  return r[key];
}
const sort = { key: 'verdict', dir: 1 };
function compareRows(a, b) {
  const x = sortValue(a, sort.key), y = sortValue(b, sort.key);
  if (x === undefined && y !== undefined) return 1;
  if (y === undefined && x !== undefined) return -1;
  if (x !== undefined && x !== y) return (x < y ? -1 : 1) * sort.dir;
  return a.index - b.index;
}

const tbody = document.querySelector('#rows tbody');
const numeric = new Set(['worst', 'pct', 'score', 'seconds', 'speedup']);
const keys = [...document.querySelectorAll('#rows th')].map((th) => th.dataset.key);
for (const r of rows) {
  const tr = el('tr', { 'data-case': r.case, 'data-family': r.family, 'data-impl': r.impl, 'data-verdict': r.verdict });
  for (const k of keys) {
    const td = el('td', { class: (numeric.has(k) ? 'num' : k === 'note' ? 'note' : '') + (k === 'verdict' ? ' verdict-' + r.verdict : ''),
                          text: cell(r, k) });
    if (k === 'note' && r.detail) td.title = r.detail;
    tr.append(td);
  }
  tr.addEventListener('click', () => openCase(r.case, r.impl));
  r.tr = tr;
}
function render() {
  const fam = $('f-family').value, impl = $('f-impl').value, verdict = $('f-verdict').value;
  const text = $('f-text').value.toLowerCase();
  let shown = 0;
  for (const r of [...rows].sort(compareRows)) {
    const ok = (!fam || r.family === fam) && (!impl || r.impl === impl) && (!verdict || r.verdict === verdict) &&
               (!text || r.case.toLowerCase().includes(text) || r.note.toLowerCase().includes(text));
    r.tr.hidden = !ok;
    shown += ok ? 1 : 0;
    tbody.append(r.tr);
  }
  $('count').textContent = `showing ${shown} of ${rows.length} rows`;
  for (const th of document.querySelectorAll('#rows th')) {
    th.classList.toggle('sorted-asc', th.dataset.key === sort.key && sort.dir > 0);
    th.classList.toggle('sorted-desc', th.dataset.key === sort.key && sort.dir < 0);
  }
}
for (const th of document.querySelectorAll('#rows th')) {
  th.addEventListener('click', () => {
    sort.dir = sort.key === th.dataset.key ? -sort.dir : 1;
    sort.key = th.dataset.key;
    render();
  });
}
for (const f of families) $('f-family').append(el('option', { text: f }));
for (const i of impls) $('f-impl').append(el('option', { text: i }));
for (const id of ['f-family', 'f-impl', 'f-verdict']) $(id).addEventListener('change', render);
$('f-text').addEventListener('input', render);

const s = $('summary');
s.append(`${D.cases} cases, ${rows.length} rows: `, el('b', { class: 'pass', text: `${rows.length - nfail} PASS` }), ', ',
         el('b', { class: nfail ? 'fail' : 'pass', text: `${nfail} FAIL` }),
         ` \u2014 ${families.length} families; lockstep ${D.lockstep}` + (D.threads ? `, ${D.threads} threads` : '') +
         (D.merged_from ? `; merged from ${D.merged_from} reports` : ''));
$('legend').textContent = 'Click a row for its case: the outputs side by side, zoomable, with the pixel under the cursor. ' +
  'Reference rows compare the reference with its golden; other rows compare with the reference. ' +
  uniq(D.case_info.map((c) => c.kind + ': ' + c.legend)).join(' ');
if (D.verdicts.length) {
  $('verdicts').append(el('h2', { text: 'Analytic verdicts' }));
  const ul = el('ul');
  for (const v of D.verdicts) ul.append(el('li', { text: v }));
  $('verdicts').append(ul);
}

// ---------------------------------------------------------------- charts
function logScale(lo, hi, a, b) {  // whole decades, so every tick is inside
  const l0 = Math.floor(Math.log10(lo)), c = Math.ceil(Math.log10(hi)), l1 = c > l0 ? c : l0 + 1;
  const f = (v) => a + (Math.log10(v) - l0) / (l1 - l0) * (b - a);
  f.ticks = []; for (let e = l0; e <= l1; ++e) f.ticks.push(Math.pow(10, e));
  return f;
}
function tickLabel(v) { const e = Math.round(Math.log10(v)); return e >= -2 && e <= 3 ? String(v) : '1e' + e; }
// Every tick gets a grid line; labels only every n-th so that at most `most` show (no overlap).
const labelled = (ticks, i, most) => i % Math.ceil(ticks.length / most) === 0;
function legend(svg, items, x, y) {
  items.forEach(([name, colour], i) => {
    svg.append(sv('circle', { cx: x, cy: y + i * 14, r: 4, fill: colour }));
    svg.append(sv('text', { x: x + 8, y: y + i * 14 + 4 }, name));
  });
}
function drawSpeed() {
  const svg = $('chart-speed'); svg.replaceChildren();
  const xKey = $('speed-x').value;
  const pts = rows.filter((r) => r.impl !== 'reference' && r.compared && r.speedup > 0);
  const W = 330, H = 330, L = 46, T = 10, B = 36;
  const xv = (r) => xKey === 'worst' ? (r.worst === null ? NaN : r.worst) : r.pct;
  const xs = pts.map(xv).filter((v) => v > 0), ys = pts.map((r) => r.speedup);
  if (!pts.length) { svg.append(sv('text', { x: 10, y: 20 }, 'no compared rows')); return; }
  const x = logScale(xs.length ? Math.min(...xs) : 1e-6, xs.length ? Math.max(...xs) : 1e-5, L + 36, W - 6);
  const y = logScale(Math.min(...ys), Math.max(...ys), H - B - 8, T);
  x.ticks.forEach((t, i) => { const p = x(t); svg.append(sv('line', { class: 'grid', x1: p, x2: p, y1: T, y2: H - B }));
    if (labelled(x.ticks, i, 6)) svg.append(sv('text', { x: p, y: H - B + 14, 'text-anchor': 'middle' }, tickLabel(t))); });
  y.ticks.forEach((t, i) => { const p = y(t); svg.append(sv('line', { class: 'grid', x1: L, x2: W - 6, y1: p, y2: p }));
    if (labelled(y.ticks, i, 10)) svg.append(sv('text', { x: L - 4, y: p + 4, 'text-anchor': 'end' }, tickLabel(t) + '\u00d7')); });
  svg.append(sv('line', { class: 'axis', x1: L, x2: W - 6, y1: H - B, y2: H - B }));
  svg.append(sv('line', { class: 'axis', x1: L, x2: L, y1: T, y2: H - B }));
  svg.append(sv('text', { x: L + 8, y: H - B + 14, 'text-anchor': 'middle' }, '0'));
  svg.append(sv('text', { x: (L + W) / 2, y: H - 4, 'text-anchor': 'middle' }, xKey === 'worst' ? 'max error' : '% over'));
  svg.append(sv('text', { x: 12, y: T + (H - B) / 2, transform: `rotate(-90 12 ${T + (H - B) / 2})`, 'text-anchor': 'middle' },
                'speedup over the reference'));
  for (const r of pts) {
    const v = xv(r), px = v > 0 ? x(v) : L + 8, py = y(r.speedup);
    const c = sv('circle', { cx: px, cy: py, r: 4, fill: famColour.get(r.family), 'fill-opacity': 0.75,
                             stroke: r.pass ? 'none' : '#cf222e', 'stroke-width': 2 });
    c.append(sv('title', {}, `${r.case} ${r.impl}: ${cell(r, xKey)} ${xKey === 'worst' ? 'max error' : '% over'}, ` +
                             `${cell(r, 'speedup')}, ${r.verdict}`));
    c.style.cursor = 'pointer'; c.addEventListener('click', () => openCase(r.case, r.impl));
    svg.append(c);
  }
  svg.setAttribute('width', W + 130);
  legend(svg, uniq(pts.map((r) => r.family)).map((f) => [f, famColour.get(f)]), W + 14, T + 6);
}
function drawTime() {
  const svg = $('chart-time'); svg.replaceChildren();
  const cases = uniq(rows.map((r) => r.case)), L = 170, W = 380, T = 8, row = 13;
  const H = T + cases.length * row + 30;
  svg.setAttribute('height', H); svg.setAttribute('width', W + 130);
  const ts = rows.map((r) => r.seconds).filter((t) => t > 0);
  const x = logScale(ts.length ? Math.min(...ts) : 1e-4, ts.length ? Math.max(...ts) : 1, L, W - 6);
  x.ticks.forEach((t, i) => { const p = x(t); svg.append(sv('line', { class: 'grid', x1: p, x2: p, y1: T, y2: H - 26 }));
    if (labelled(x.ticks, i, 6)) svg.append(sv('text', { x: p, y: H - 14, 'text-anchor': 'middle' }, tickLabel(t))); });
  svg.append(sv('text', { x: (L + W) / 2, y: H - 2, 'text-anchor': 'middle' }, 'seconds'));
  cases.forEach((c, i) => {
    const cy = T + i * row + row / 2;
    const label = sv('text', { x: L - 6, y: cy + 4, 'text-anchor': 'end' }, c);
    const ci = info.get(c);
    if (ci && ci.size) label.append(sv('title', {}, `${c}: ${ci.size}`));
    label.style.cursor = 'pointer'; label.addEventListener('click', () => openCase(c));
    svg.append(label);
    svg.append(sv('line', { class: 'grid', x1: L, x2: W - 6, y1: cy, y2: cy }));
    for (const r of rows.filter((r) => r.case === c && r.seconds > 0)) {
      const m = sv('circle', { cx: x(r.seconds), cy, r: 3.5, fill: implColour.get(r.impl), stroke: r.pass ? 'none' : '#cf222e' });
      m.append(sv('title', {}, `${c} ${r.impl}: ${r.seconds.toFixed(4)} s`));
      svg.append(m);
    }
  });
  legend(svg, impls.map((i) => [i, implColour.get(i)]), W + 12, T + 6);
}
// Time against work: one family at a time (units differ between families).
const workOf = (r) => { const ci = info.get(r.case); return ci && ci.work > 0 ? ci.work : 0; };
const sized = families.filter((f) => rows.some((r) => r.family === f && r.seconds > 0 && workOf(r) > 0));
for (const f of sized) $('size-family').append(el('option', { value: f, text: f }));
// The family shown first: the one whose cases span the widest range of work.
const span = (f) => { const w = rows.filter((r) => r.family === f && workOf(r) > 0).map(workOf);
                      return Math.max(...w) / Math.min(...w); };
if (sized.length) $('size-family').value = sized.reduce((a, b) => span(b) > span(a) ? b : a);
// Least-squares slope of log(seconds) against log(work); null with fewer than two distinct works.
function slope(pts) {
  const xs = pts.map((p) => Math.log(p[0])), ys = pts.map((p) => Math.log(p[1]));
  const n = xs.length, mx = xs.reduce((a, b) => a + b, 0) / n, my = ys.reduce((a, b) => a + b, 0) / n;
  let sxx = 0, sxy = 0;
  for (let i = 0; i < n; ++i) { sxx += (xs[i] - mx) ** 2; sxy += (xs[i] - mx) * (ys[i] - my); }
  return sxx > 1e-9 ? sxy / sxx : null;
}
function drawSize() {
  const svg = $('chart-size'); svg.replaceChildren();
  const fam = $('size-family').value;
  const pts = rows.filter((r) => r.family === fam && r.seconds > 0 && workOf(r) > 0);
  if (!pts.length) { svg.append(sv('text', { x: 10, y: 20 }, 'no timed rows with counted work')); return; }
  const W = 330, H = 330, L = 46, T = 10, B = 36;
  const unit = info.get(pts[0].case).unit || 'work';
  const x = logScale(Math.min(...pts.map(workOf)), Math.max(...pts.map(workOf)), L + 6, W - 6);
  const y = logScale(Math.min(...pts.map((r) => r.seconds)), Math.max(...pts.map((r) => r.seconds)), H - B - 8, T);
  x.ticks.forEach((t, i) => { const p = x(t); svg.append(sv('line', { class: 'grid', x1: p, x2: p, y1: T, y2: H - B }));
    if (labelled(x.ticks, i, 6)) svg.append(sv('text', { x: p, y: H - B + 14, 'text-anchor': 'middle' }, tickLabel(t))); });
  y.ticks.forEach((t, i) => { const p = y(t); svg.append(sv('line', { class: 'grid', x1: L, x2: W - 6, y1: p, y2: p }));
    if (labelled(y.ticks, i, 10)) svg.append(sv('text', { x: L - 4, y: p + 4, 'text-anchor': 'end' }, tickLabel(t))); });
  svg.append(sv('line', { class: 'axis', x1: L, x2: W - 6, y1: H - B, y2: H - B }));
  svg.append(sv('line', { class: 'axis', x1: L, x2: L, y1: T, y2: H - B }));
  svg.append(sv('text', { x: (L + W) / 2, y: H - 4, 'text-anchor': 'middle' }, `${unit} (the reference's count)`));
  svg.append(sv('text', { x: 12, y: T + (H - B) / 2, transform: `rotate(-90 12 ${T + (H - B) / 2})`, 'text-anchor': 'middle' },
                'seconds'));
  const famImpls = uniq(pts.map((r) => r.impl));
  for (const r of pts) {
    const c = sv('circle', { cx: x(workOf(r)), cy: y(r.seconds), r: 4, fill: implColour.get(r.impl), 'fill-opacity': 0.75,
                             stroke: r.pass ? 'none' : '#cf222e', 'stroke-width': 2 });
    c.append(sv('title', {}, `${r.case} ${r.impl}: ${workOf(r)} ${unit}, ${r.seconds.toFixed(4)} s`));
    c.style.cursor = 'pointer'; c.addEventListener('click', () => openCase(r.case, r.impl));
    svg.append(c);
  }
  svg.setAttribute('width', W + 150);
  legend(svg, famImpls.map((i) => {
    const k = slope(pts.filter((r) => r.impl === i).map((r) => [workOf(r), r.seconds]));
    return [k === null ? i : `${i} (k ${k.toFixed(2)})`, implColour.get(i)];
  }), W + 14, T + 6);
}
$('size-family').addEventListener('change', drawSize);
function drawFail() {
  const svg = $('chart-fail'); svg.replaceChildren();
  const L = 110, W = 300, T = 6, row = 18, H = T + families.length * row + 24;
  svg.setAttribute('height', H);
  const counts = families.map((f) => [f, rows.filter((r) => r.family === f && r.pass).length,
                                          rows.filter((r) => r.family === f && !r.pass).length]);
  const max = Math.max(1, ...counts.map(([, p, n]) => p + n));
  counts.forEach(([f, p, n], i) => {
    const y = T + i * row;
    svg.append(sv('text', { x: L - 6, y: y + 12, 'text-anchor': 'end' }, f));
    const wp = (W - L - 40) * p / max, wn = (W - L - 40) * n / max;
    svg.append(sv('rect', { x: L, y: y + 2, width: wp, height: row - 5, fill: '#1a7f37' }));
    const bad = sv('rect', { x: L + wp, y: y + 2, width: wn, height: row - 5, fill: '#cf222e', 'data-family': f });
    svg.append(bad);
    svg.append(sv('text', { x: L + wp + wn + 4, y: y + 12 }, n ? `${n} fail / ${p + n}` : `${p} pass`));
  });
  svg.append(sv('text', { x: L, y: H - 6 }, 'rows: green pass, red fail'));
}
$('speed-x').addEventListener('change', drawSpeed);

// ---------------------------------------------------------------- one case
const pixels = new Map();    // report path -> {w, h, data} of its PNG (from CASE/pixels.js)
const requested = new Set();
window.lockstepPixels = function (name, files) {
  for (const [path, uri] of Object.entries(files)) {
    const img = new Image();
    img.onload = () => {
      const c = document.createElement('canvas'); c.width = img.naturalWidth; c.height = img.naturalHeight;
      const g = c.getContext('2d', { willReadFrequently: true }); g.drawImage(img, 0, 0);
      pixels.set(path, { w: c.width, h: c.height, data: g.getImageData(0, 0, c.width, c.height).data });
    };
    img.src = uri;
  }
};
let current = null, zoom = 1, pictures = [];
function caseRows(name) { return rows.filter((r) => r.case === name); }
function pictureList(name) {
  const ci = info.get(name), out = [];
  if (ci && ci.golden) out.push({ path: ci.golden, label: 'golden', group: 'views', impl: 'golden' });
  for (const r of caseRows(name)) {
    if (r.view) out.push({ path: r.view, label: r.impl, group: 'views', impl: r.impl });
  }
  // Another renderer's picture of the same scene, for the eye (not judged).
  if (ci && ci.beside) out.push({ path: ci.beside, label: 'beside: ' + ci.beside_from + ' (not judged)', group: 'views', impl: 'beside' });
  for (const r of caseRows(name)) {
    // The failure map's count in its caption: samples over the case's threshold.
    if (r.difference) out.push({ path: r.difference, label: r.impl + (r.impl === 'reference' ? ' vs golden' : ' vs reference') +
                                 (r.samples > 0 ? `: ${r.over} of ${r.samples} over` : ''), group: 'heat', impl: r.impl });
  }
  for (const r of caseRows(name)) if (r.judged) out.push({ path: r.judged, label: r.impl + ' judged', group: 'judge', impl: r.impl });
  return out;
}
function setZoom(z) {
  zoom = Math.min(32, Math.max(0.25, z));
  $('zoom-level').textContent = zoom + '\u00d7';
  for (const img of document.querySelectorAll('#viewer img.px')) sizeImage(img);
  placeWipe();
}
function sizeImage(img) { if (img.naturalWidth) img.style.width = img.naturalWidth * zoom + 'px'; }
function picture(p) {
  const img = el('img', { class: 'px', src: p.path, alt: p.label, 'data-path': p.path });
  img.addEventListener('load', () => sizeImage(img));
  img.addEventListener('mousemove', (e) => readout(e, img, p.path));
  const frame = el('div', { class: 'frame' }, img);
  frame.addEventListener('wheel', wheel, { passive: false });
  return el('figure', { 'data-group': p.group }, el('figcaption', { text: p.label }), frame);
}
function wheel(e) { if (e.deltaY) { e.preventDefault(); setZoom(e.deltaY < 0 ? zoom * 2 : zoom / 2); } }
function openCase(name, impl) {
  const ci = info.get(name);
  current = name;
  $('viewer').hidden = false;
  $('v-title').textContent = name;
  $('v-info').textContent = ci && ci.kind === '?' ? `${ci.family}; merged from a verify --json file: no pictures or case details.` :
    ci ? `${ci.family} (${ci.kind}${ci.kind === 'mesh' ? ': pictures are rendered previews' : ''}), ` +
      `input ${ci.input}` + (ci.size ? `, ${ci.size}` : '') + `, ${ci.tolerance}; judge ${ci.judge}.` : '';
  const mini = $('v-rows'); mini.replaceChildren();
  const head = el('tr'); for (const k of ['impl', 'max err', '% over', 'score', 'time s', 'speedup', 'verdict', 'note']) head.append(el('th', { text: k }));
  mini.append(head);
  for (const r of caseRows(name)) {
    const tr = el('tr');
    tr.append(el('td', { text: r.impl }));
    for (const k of ['worst', 'pct', 'score', 'seconds', 'speedup']) tr.append(el('td', { class: 'num', text: cell(r, k) }));
    tr.append(el('td', { class: 'verdict-' + r.verdict, text: r.verdict }), el('td', { text: r.note }));
    mini.append(tr);
  }
  pictures = pictureList(name);
  for (const g of ['views', 'heat', 'judge']) $('g-' + g).replaceChildren(...pictures.filter((p) => p.group === g).map(picture));
  $('g-judge-wrap').hidden = !pictures.some((p) => p.group === 'judge');
  for (const id of ['cmp-a', 'cmp-b']) $(id).replaceChildren(...pictures.map((p) => el('option', { value: p.path, text: p.label })));
  const views = pictures.filter((p) => p.group === 'views');
  const a = views.find((p) => p.impl === impl && impl !== 'reference') || views.find((p) => p.impl !== 'reference' && p.impl !== 'golden') || views[0];
  const b = views.find((p) => p.impl === 'reference') || views[0];
  if (a) $('cmp-a').value = a.path;
  if (b) $('cmp-b').value = b.path;
  setCompare();
  for (const r of rows) r.tr.classList.toggle('current', r.case === name);
  if (!requested.has(name) && pictures.length) {  // merged --json shards have no pictures
    requested.add(name);
    const sc = el('script', { src: encodeURI(name) + '/pixels.js' });
    sc.onerror = () => { $('readout').textContent = 'no pixel data (' + name + '/pixels.js did not load)'; };
    document.body.append(sc);
  }
  $('readout').textContent = 'move the mouse over a picture';
  $('viewer').scrollIntoView({ block: 'start' });
  history.replaceState(null, '', '#case=' + encodeURIComponent(name));
}
function pixel(path, x, y) {
  const p = pixels.get(path);
  if (!p || x >= p.w || y >= p.h) return null;
  const i = 4 * (y * p.w + x);
  return [p.data[i], p.data[i + 1], p.data[i + 2], p.data[i + 3]];
}
const show = (v) => v ? v.map((c) => String(c).padStart(3)).join(' ') : '(loading)';
function readout(e, img, path) {
  const rc = img.getBoundingClientRect();
  const x = Math.floor((e.clientX - rc.left) / rc.width * img.naturalWidth);
  const y = Math.floor((e.clientY - rc.top) / rc.height * img.naturalHeight);
  if (x < 0 || y < 0 || x >= img.naturalWidth || y >= img.naturalHeight) return;
  const p = pictures.find((q) => q.path === path) || { label: path, impl: '' };
  const v = pixel(path, x, y);
  let text = `(${x}, ${y})  ${p.label}: RGBA ${show(v)}`;
  const ref = pictures.find((q) => q.group === 'views' && q.impl === 'reference');
  if (p.group === 'views' && ref && ref.path !== path) {
    const rv = pixel(ref.path, x, y);
    if (v && rv) text += `   reference: ${show(rv)}   |error| ${Math.max(...[0, 1, 2].map((k) => Math.abs(v[k] - rv[k])))}/255 (8-bit views)`;
  }
  const heat = pictures.find((q) => q.group === 'heat' && q.impl === p.impl && q.path !== path);
  if (heat) text += `   heat map: ${show(pixel(heat.path, x, y))}`;
  $('readout').textContent = text;
}
function setCompare() {
  const a = $('cmp-img-a'), b = $('cmp-img-b');
  a.src = $('cmp-a').value; b.src = $('cmp-b').value;
  a.dataset.path = a.getAttribute('src'); b.dataset.path = b.getAttribute('src');
  placeWipe();
}
function placeWipe() {
  const w = Number($('wipe').value), a = $('cmp-img-a');
  a.style.clipPath = `inset(0 ${100 - w}% 0 0)`;
  $('wipe-line').style.left = (a.naturalWidth * zoom * w / 100) + 'px';
  $('flip-state').textContent = w === 100 ? 'showing A' : w === 0 ? 'showing B' : `A left of ${w}%, B right`;
}
for (const img of [$('cmp-img-a'), $('cmp-img-b')]) img.addEventListener('load', () => { sizeImage(img); placeWipe(); });
// Both compare pictures sit in one box; the readout names the one under the cursor.
$('compare').addEventListener('mousemove', (e) => {
  const a = $('cmp-img-a'), rc = a.getBoundingClientRect();
  const onA = (e.clientX - rc.left) / rc.width * 100 < Number($('wipe').value);
  const img = onA ? a : $('cmp-img-b');
  readout(e, img, img.dataset.path);
});
$('cmp-frame').addEventListener('wheel', wheel, { passive: false });
$('cmp-a').addEventListener('change', setCompare);
$('cmp-b').addEventListener('change', setCompare);
$('wipe').addEventListener('input', placeWipe);
function flip() { $('wipe').value = Number($('wipe').value) === 100 ? 0 : 100; placeWipe(); }
$('flip').addEventListener('click', flip);
// Hovering "hover for B" shows B alone while the pointer stays, then the wipe as it was.
let peekSaved = null;
$('peek').addEventListener('mouseenter', () => { peekSaved = $('wipe').value; $('wipe').value = 0; placeWipe(); });
$('peek').addEventListener('mouseleave', () => { if (peekSaved !== null) $('wipe').value = peekSaved; peekSaved = null; placeWipe(); });
$('zoom-in').addEventListener('click', () => setZoom(zoom * 2));
$('zoom-out').addEventListener('click', () => setZoom(zoom / 2));
$('zoom-1').addEventListener('click', () => setZoom(1));
function closeCase() { $('viewer').hidden = true; current = null; history.replaceState(null, '', '#');
                       for (const r of rows) r.tr.classList.remove('current'); }
$('v-close').addEventListener('click', closeCase);
document.addEventListener('keydown', (e) => {
  if (!current || e.target.tagName === 'INPUT' && e.target.type !== 'range' || e.target.tagName === 'SELECT') return;
  if (e.key === 'f') flip();
  else if (e.key === '+' || e.key === '=') setZoom(zoom * 2);
  else if (e.key === '-') setZoom(zoom / 2);
  else if (e.key === 'Escape') closeCase();
});

render();
drawSpeed(); drawTime(); drawSize(); drawFail();
const m = /^#case=(.+)$/.exec(location.hash);
if (m && info.has(decodeURIComponent(m[1]))) openCase(decodeURIComponent(m[1]));
</script>
</body>
</html>
)lockstep_page";

}  // namespace lockstep::cli
