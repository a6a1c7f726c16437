#!/usr/bin/env node
// lockstep verify --report DIR: DIR/index.html in a real browser (Debian's
// chromium, driven by puppeteer-core from tests/browser/node_modules, installed
// by scripts/setup.sh). Registered as the ctest report.browser.
//
// usage: report_test.js LOCKSTEP CORPUS_DIR OUT_DIR
//
// Makes a small corpus in OUT_DIR/corpus from CORPUS_DIR's files (a case of
// each of several families, a mesh case, and near-sphere with its manifest
// expectation flipped to ref=wrong, so one row fails), runs
// `lockstep verify --report OUT_DIR/report --json OUT_DIR/verify.json` on it
// (exit 1 expected: one row fails), or with --report-dir DIR uses a report
// already made (e.g. by merge-reports), then opens DIR/index.html from file://
// and checks:
//   * no console error, page error or failed request;
//   * the table has one row per row printed on stdout (case, impl, verdict),
//     or per row of the JSON; failures first;
//   * the family filter (every family), the implementation filter (every
//     implementation) and the verdict filter show exactly the JSON's rows of
//     that family / implementation / verdict; sorting by time sorts;
//   * opening a case shows its pictures (naturalWidth > 0), golden included;
//     the mouse over a picture gives a pixel readout with numbers; zoom doubles
//     the pictures' size (image-rendering: pixelated); the flip key shows A then
//     B; the wipe clips A at the slider; hovering "hover for B" shows B alone;
//   * a mesh case shows its rendered previews;
//   * the four charts have their marks (the time-against-work chart for every family it offers).
// Saves OUT_DIR/report-table.png, OUT_DIR/report-case.png and OUT_DIR/report-diff.png
// (the row that differs most from its reference, at 2x). Exits 1 on the
// first failed check (a missing puppeteer-core or chromium is a failure too).
'use strict';
const fs = require('fs');
const path = require('path');
const { spawnSync } = require('child_process');

function fail(msg) {
  console.error('FAIL: ' + msg);
  process.exit(1);
}

const argv = process.argv.slice(2);
let reportDir = null;
const ri = argv.indexOf('--report-dir');
if (ri >= 0) { reportDir = argv[ri + 1]; argv.splice(ri, 2); }
const [lockstep, corpus, out] = argv;
if (!out) fail('usage: report_test.js LOCKSTEP CORPUS_DIR OUT_DIR [--report-dir DIR]');

let puppeteer;
try {
  puppeteer = require(path.join(__dirname, 'node_modules', 'puppeteer-core'));
} catch (e) {
  fail('puppeteer-core is not installed in tests/browser/node_modules (run scripts/setup.sh): ' + e.message);
}
const chromium = process.env.CHROMIUM || '/usr/bin/chromium';
if (!fs.existsSync(chromium)) fail(`no browser at ${chromium} (scripts/setup.sh installs Debian's chromium)`);

// Cases of the small corpus: families ray_cast (failing), composite, zbuffer,
// scanline, painter, marching_cubes (mesh), volume, volume_iso.
const CASES = ['near-sphere', 'composite-two-layers', 'zb-tetra-3-phong', 'sl-patches-affine', 'painter-plain',
               'mc-sphere-32', 'vr-neghip', 'vi-torus-32'];

// Rows printed on stdout by verify: case, impl, ..., PASS|FAIL.
function stdoutRows(text) {
  const re = /^(\S+)\s+(\S+)\s+\S+\s+\S+\s+\S+\s+[\d.]+\s+\S+\s+(PASS|FAIL)\b/;
  const rows = [];
  for (const line of text.split('\n')) {
    const m = re.exec(line);
    if (m && m[1] !== 'case') rows.push(`${m[1]} ${m[2]} ${m[3]}`);
  }
  return rows;
}

function makeReport() {
  const dir = path.join(out, 'corpus');
  fs.rmSync(out, { recursive: true, force: true });
  fs.mkdirSync(dir, { recursive: true });
  for (const d of ['golden', 'scenes', 'stacks', 'tf', 'volumes']) fs.symlinkSync(path.resolve(corpus, d), path.join(dir, d));
  const lines = fs.readFileSync(path.join(corpus, 'manifest.txt'), 'utf8').split('\n').filter((l) => {
    const w = l.split('#')[0].trim().split(/\s+/);
    return CASES.includes(w[0]) || CASES.includes(w[1]);
  });
  if (lines.length !== CASES.length) fail(`found ${lines.length} of the ${CASES.length} cases in ${corpus}/manifest.txt`);
  const flipped = lines.map((l) => l.replace('ref=right', 'ref=wrong:browser-test'));
  if (flipped.join() === lines.join()) fail('near-sphere no longer says ref=right: pick another failing row');
  fs.writeFileSync(path.join(dir, 'manifest.txt'), flipped.join('\n') + '\n');
  const report = path.join(out, 'report'), json = path.join(out, 'verify.json');
  const run = spawnSync(lockstep, ['verify', dir, '--report', report, '--json', json], { encoding: 'utf8' });
  if (run.status !== 1) fail(`verify exited ${run.status}, expected 1 (one failing row)\n${run.stdout}\n${run.stderr}`);
  const printed = stdoutRows(run.stdout);
  const m = /^(\d+) cases, (\d+) rows/m.exec(run.stdout);
  if (!m || Number(m[2]) !== printed.length) fail(`parsed ${printed.length} rows on stdout; summary says ${m && m[2]}`);
  return { report, printed };
}

async function main() {
  let printed = null;
  if (reportDir) {
    reportDir = path.resolve(reportDir);
    fs.mkdirSync(out, { recursive: true });
  } else {
    const r = makeReport();
    reportDir = path.resolve(r.report);
    printed = r.printed;
  }
  const data = JSON.parse(fs.readFileSync(path.join(reportDir, 'report.json'), 'utf8'));
  const expected = data.rows.map((r) => `${r.case} ${r.impl} ${r.pass ? 'PASS' : 'FAIL'}`);
  if (printed && printed.slice().sort().join('\n') !== expected.slice().sort().join('\n'))
    fail('report.json rows differ from the rows printed on stdout');

  const browser = await puppeteer.launch({
    executablePath: chromium, headless: true, args: ['--no-sandbox', '--headless=new', '--allow-file-access-from-files=false'],
  });
  const problems = [];
  let failure = null;
  try {
    const page = await browser.newPage();
    await page.setViewport({ width: 1400, height: 1000 });
    page.on('console', (m) => { if (m.type() === 'error') problems.push('console error: ' + m.text()); });
    page.on('pageerror', (e) => problems.push('page error: ' + e.message));
    page.on('requestfailed', (r) => problems.push('request failed: ' + r.url() + ' ' + (r.failure() || {}).errorText));
    const check = (ok, msg) => { if (!ok) throw new Error(msg); };
    await page.goto('file://' + path.join(reportDir, 'index.html'), { waitUntil: 'load' });

    // One table row per row; failures first.
    const table = await page.$$eval('#rows tbody tr', (trs) => trs.map((tr) =>
      `${tr.dataset.case} ${tr.dataset.impl} ${tr.dataset.verdict}`));
    check(table.length === expected.length, `table has ${table.length} rows, expected ${expected.length}`);
    check(table.slice().sort().join('\n') === expected.slice().sort().join('\n'), 'table rows differ from the run\'s');
    const nfail = expected.filter((r) => r.endsWith('FAIL')).length;
    check(table.slice(0, nfail).every((r) => r.endsWith('FAIL')), 'failures are not first: ' + table.slice(0, 3));
    const summary = await page.$eval('#summary', (e) => e.textContent);
    check(summary.includes(`${expected.length} rows`) && summary.includes(`${nfail} FAIL`), 'summary: ' + summary);

    const visible = () => page.$$eval('#rows tbody tr', (trs) => trs.filter((tr) => !tr.hidden).map((tr) => ({ ...tr.dataset })));
    // The family filter, every family.
    const families = [...new Set(data.rows.map((r) => r.family))];
    check(families.length >= 5, `only ${families.length} families`);
    for (const f of families) {
      await page.select('#f-family', f);
      const shown = await visible();
      const want = data.rows.filter((r) => r.family === f).length;
      check(shown.length === want && shown.every((d) => d.family === f), `family ${f}: ${shown.length} rows shown, JSON has ${want}`);
    }
    await page.select('#f-family', '');
    // The implementation filter, every implementation.
    for (const i of [...new Set(data.rows.map((r) => r.impl))]) {
      await page.select('#f-impl', i);
      const shown = await visible();
      const want = data.rows.filter((r) => r.impl === i).length;
      check(shown.length === want && shown.every((d) => d.impl === i), `impl ${i}: ${shown.length} rows shown, JSON has ${want}`);
    }
    await page.select('#f-impl', '');
    await page.select('#f-verdict', 'FAIL');
    check((await visible()).length === nfail, 'verdict filter FAIL');
    await page.select('#f-verdict', '');
    check((await visible()).length === expected.length, 'filters cleared');
    // Sorting by time (ascending on the first click).
    await page.click('#rows th[data-key="seconds"]');
    const secs = await page.$$eval('#rows tbody tr', (trs) => trs.map((tr) => Number(tr.children[6].textContent)));
    check(secs.every((s, i) => i === 0 || secs[i - 1] <= s), 'not sorted by time: ' + secs.join(' '));
    await page.click('#rows th[data-key="verdict"]');

    // Charts: a mark per compared non-reference row, a case per line, a bar per family.
    const marks = await page.evaluate(() => ({
      speed: document.querySelectorAll('#chart-speed circle title').length,
      time: document.querySelectorAll('#chart-time circle title').length,
      fail: document.querySelectorAll('#chart-fail rect[data-family]').length,
    }));
    const compared = data.rows.filter((r) => r.impl !== 'reference' && r.ran && r.samples > 0 && r.speedup > 0).length;
    check(marks.speed === compared, `speed chart: ${marks.speed} marks, ${compared} rows`);
    check(marks.time === data.rows.filter((r) => r.seconds > 0).length, `time chart: ${marks.time} marks`);
    check(marks.fail === families.length, `failure chart: ${marks.fail} bars`);
    // Time against work: for every family offered, a mark per timed row whose case counted its work.
    const workOf = (r) => (data.case_info.find((c) => c.case === r.case) || {}).work || 0;
    const offered = await page.$$eval('#size-family option', (os) => os.map((o) => o.value));
    const counted = families.filter((f) => data.rows.some((r) => r.family === f && r.seconds > 0 && workOf(r) > 0));
    check(JSON.stringify(offered) === JSON.stringify(counted), `size chart offers ${offered}, expected ${counted}`);
    for (const f of offered) {
      await page.select('#size-family', f);
      const n = await page.$$eval('#chart-size circle title', (ts) => ts.length);
      const want = data.rows.filter((r) => r.family === f && r.seconds > 0 && workOf(r) > 0).length;
      check(n === want, `size chart ${f}: ${n} marks, ${want} rows`);
    }
    await page.screenshot({ path: path.join(out, 'report-table.png') });

    // A case: click its first row (the failing one if any).
    async function open(name) {
      await page.click(`#rows tbody tr[data-case="${name}"]`);
      await page.waitForFunction(() => !document.getElementById('viewer').hidden);
      await page.waitForFunction(() => [...document.querySelectorAll('#viewer img.px')].every((i) => i.complete),
                                 { timeout: 10000 });
      return page.$$eval('#g-views img', (imgs) => imgs.map((i) => ({ alt: i.alt, w: i.naturalWidth, h: i.naturalHeight })));
    }
    const failing = data.rows.find((r) => !r.pass);
    const name = failing ? failing.case : data.rows[0].case;
    const views = await open(name);
    const info = data.case_info.find((c) => c.case === name);
    const wantViews = data.rows.filter((r) => r.case === name && r.view).length + (info.golden ? 1 : 0) +
                      (info.beside ? 1 : 0);
    check(views.length === wantViews && views.every((v) => v.w > 0 && v.h > 0),
          `case ${name}: pictures ${JSON.stringify(views)}, expected ${wantViews} loaded`);
    check(!info.golden || views.some((v) => v.alt === 'golden'), 'no golden picture');
    const heat = await page.$$eval('#g-heat img', (imgs) => imgs.filter((i) => i.naturalWidth > 0).length);
    check(heat === data.rows.filter((r) => r.case === name && r.difference).length, `case ${name}: ${heat} heat maps`);
    // The pixel under the cursor: the middle of the second output (an implementation's).
    const target = (await page.$$('#g-views img'))[Math.min(2, views.length - 1)];
    const box = await target.boundingBox();
    let text = '';
    for (let i = 0; i < 50 && !/RGBA +\d+ +\d+ +\d+ +\d+/.test(text); ++i) {
      await page.mouse.move(box.x + box.width / 2 + (i % 2), box.y + box.height / 2);
      text = await page.$eval('#readout', (e) => e.textContent);
      if (!/RGBA +\d+/.test(text)) await new Promise((r) => setTimeout(r, 100));
    }
    const m = /^\((\d+), (\d+)\) .*RGBA +\d+ +\d+ +\d+ +\d+/.exec(text);
    check(m, 'pixel readout has no numbers: ' + JSON.stringify(text));
    const [cx, cy] = [Number(m[1]), Number(m[2])];
    check(Math.abs(cx - Math.floor(views[2 < views.length ? 2 : 0].w / 2)) <= 1 && Math.abs(cy - Math.floor(views[0].h / 2)) <= 1,
          `readout at (${cx}, ${cy}), expected the middle`);
    if (name !== 'reference') check(/\|error\| \d+\/255/.test(text) || /reference/.test(text), 'no error in readout: ' + text);
    // Zoom doubles the size (nearest neighbour); flip shows A, then B.
    const before = await target.evaluate((i) => i.getBoundingClientRect().width);
    await page.click('#zoom-in');
    const after = await target.evaluate((i) => i.getBoundingClientRect().width);
    check(Math.abs(after - 2 * before) < 1, `zoom: ${before} -> ${after}`);
    const rendering = await target.evaluate((i) => getComputedStyle(i).imageRendering);
    check(rendering === 'pixelated', 'image-rendering ' + rendering);
    await page.click('#zoom-1');
    await page.keyboard.press('f');
    const s1 = await page.$eval('#flip-state', (e) => e.textContent);
    await page.keyboard.press('f');
    const s2 = await page.$eval('#flip-state', (e) => e.textContent);
    check(s1 === 'showing A' && s2 === 'showing B', `flip: ${s1} / ${s2}`);
    await page.$eval('#wipe', (w) => { w.value = 50; w.dispatchEvent(new Event('input')); });
    // The wipe clips A at the slider; hovering "hover for B" shows B alone, then the wipe again.
    check(await page.$eval('#cmp-img-a', (i) => i.style.clipPath) === 'inset(0px 50% 0px 0px)', 'wipe does not clip A at 50%');
    await page.hover('#peek');
    const peek = await page.$eval('#flip-state', (e) => e.textContent);
    await page.mouse.move(0, 0);
    const after50 = await page.$eval('#flip-state', (e) => e.textContent);
    check(peek === 'showing B' && after50.includes('50%'), `hover flip: ${peek} / ${after50}`);
    const cmp = await page.$$eval('#compare img', (imgs) => imgs.map((i) => i.naturalWidth));
    check(cmp.every((w) => w > 0), 'compare pictures not loaded');
    // The screenshot at 4x, the cursor over the middle of the picture.
    await page.click('#zoom-in');
    await page.click('#zoom-in');
    const big = await target.boundingBox();
    await page.mouse.move(big.x + big.width / 2, big.y + big.height / 2);
    await page.screenshot({ path: path.join(out, 'report-case.png') });

    // A mesh case shows its rendered previews.
    // (Not an empty one: an isosurface that misses every cell has no picture.)
    const mesh = data.case_info.find((c) => c.kind === 'mesh' && /^[1-9]/.test(c.size));
    check(mesh, 'no mesh case in the report');
    const mv = await open(mesh.case);
    check(mv.length > 0 && mv.every((v) => v.w > 0), `mesh case ${mesh.case}: ${JSON.stringify(mv)}`);
    check((await page.$eval('#v-info', (e) => e.textContent)).includes('mesh'), 'mesh case info');

    // A case with another renderer's picture beside it (the corpus' POV-Ray cases):
    // the picture is shown, loaded, at the frame's size, labelled as not judged.
    const beside = data.case_info.find((c) => c.beside);
    if (beside) {
      const bv = await open(beside.case);
      const pic = bv.find((v) => v.alt.startsWith('beside'));
      const ref = bv.find((v) => v.alt === 'reference');
      check(pic && pic.w > 0 && ref && pic.w === ref.w && pic.h === ref.h && pic.alt.includes('not judged'),
            `case ${beside.case}: beside picture ${JSON.stringify(pic)}, reference ${JSON.stringify(ref)}`);
    }

    // The row that differs most from its reference, opened on its own row, at 2x:
    // the screenshot README shows (report-diff.png).
    const differs = data.rows.filter((r) => r.impl !== 'reference' && r.samples > 0)
      .sort((a, b) => b.over / b.samples - a.over / a.samples || (b.worst || 0) - (a.worst || 0))[0];
    if (differs) {
      await page.click(`#rows tbody tr[data-case="${differs.case}"][data-impl="${differs.impl}"]`);
      await page.waitForFunction(() => [...document.querySelectorAll('#viewer img.px')].every((i) => i.complete && i.naturalWidth > 0));
      check(await page.$eval('#cmp-a', (s) => s.value) === differs.view, 'compare A is not the row clicked');
      await page.click('#zoom-1');
      await page.click('#zoom-in');
      const pic = await page.$(`#g-views img[data-path="${differs.view}"]`);
      const pb = await pic.boundingBox();
      for (let i = 0; i < 30; ++i) {
        await page.mouse.move(pb.x + pb.width * 0.45 + (i % 2), pb.y + pb.height * 0.5);
        if (/\|error\| \d+/.test(await page.$eval('#readout', (e) => e.textContent))) break;
        await new Promise((r) => setTimeout(r, 100));
      }
      await page.screenshot({ path: path.join(out, 'report-diff.png') });
    }

    check(problems.length === 0, problems.join('\n'));
    console.log(`ok: ${expected.length} rows (${nfail} failing), ${families.length} families filtered, ` +
                `case ${name}: ${views.length} pictures, readout ${JSON.stringify(text.slice(0, 60))}; mesh ${mesh.case}; ` +
                (beside ? `beside ${beside.case}; ` : '') +
                `screenshots in ${out}`);
  } catch (e) {
    failure = e.message;
  } finally {
    await browser.close();  // before exiting: no browser left behind
  }
  if (failure) {
    if (problems.length) console.error(problems.join('\n'));
    fail(failure);
  }
}

main().catch((e) => fail(e.stack || String(e)));
