// Opens an ausbau-report page in headless Chromium (through playwright-core,
// pointed at the system's Chromium: no browser download) and checks it as a
// person would see it:
//   - it loads from file:// with no network request and no console error,
//   - the 3D view is not blank and shows S (blue) and D (orange),
//   - at each waypoint's time D's pose is that waypoint (path CSV), and mid-
//     segment it is the schemas/path.md interpolation about reference_point,
//   - moving the scrubber (mouse clicks on it) moves D and changes the picture,
//   - Play advances the time,
//   - the headline says the verdict (--expect-headline WORD: REMOVABLE,
//     NOT REMOVABLE or NO VERDICT) in one sentence,
//   - the plots of clearance, rigid penetration and clip intersection are
//     there, aligned, with values; the waypoint table has one row per
//     waypoint, with named parts,
//   - the section plane clips S and D and changes the picture, and off again
//     restores it,
//   - Measure: two mouse clicks on the 3D view give two points on the
//     surfaces under the clicks and their distance, shown,
//   - the path's CSV download has the bytes of the CSV file (--csv),
//   - the headline says its numbers with units, never "inf", "nan", a lone
//     "–" or a bare number before a colon,
//   - the view is upright for the scene's up axis (--expect-up z, and
//     --expect-up-source: where the page says it came from): the camera's up
//     vector is that axis and a point above the view's centre is drawn
//     straight above it,
//   - with --check-layout, at 1280x720 and 1366x768 the page does not scroll
//     sideways and the verdict table (where there is one) fits,
//   - with --check-no-webgl, in a Chromium without WebGL the 3D area says so
//     in one sentence while the headline, the three plots and the tables are
//     all there, with no error,
// and saves a screenshot. Prints one JSON line of measurements.
//
//   node report_test.js --chromium /usr/bin/chromium --html report.html \
//     --screenshot out.png [--csv path-smooth.csv --ref x,y,z --origin x,y,z] [--path-key smoothed]
//     [--load-only] [--expect-labels] [--expect-table ID] [--expect-headline WORD]
//     [--expect-part NAME] [--expect-up AXIS] [--expect-up-source TEXT] [--check-layout]
//     [--check-no-webgl] [--timeout-ms 60000]
'use strict';
const fs = require('fs');
const path = require('path');
const { chromium } = require('playwright-core');

function parseArgs(argv) {
  const args = { pathKey: 'smoothed', timeoutMs: 60000 };
  for (let i = 2; i < argv.length; ++i) {
    const key = argv[i].replace(/^--/, '');
    if (key === 'load-only') { args.loadOnly = true; continue; }
    if (key === 'expect-labels') { args.expectLabels = true; continue; }
    if (key === 'check-layout') { args.checkLayout = true; continue; }
    if (key === 'check-no-webgl') { args.checkNoWebgl = true; continue; }
    const value = argv[++i];
    if (value === undefined) throw new Error('missing value for --' + key);
    args[key.replace(/-([a-z])/g, (_, c) => c.toUpperCase())] = value;
  }
  for (const required of ['chromium', 'html', 'screenshot']) {
    if (!args[required]) throw new Error('--' + required + ' is required');
  }
  args.timeoutMs = Number(args.timeoutMs);
  return args;
}

const failures = [];
function check(condition, message) {
  if (!condition) failures.push(message);
  return condition;
}

// ---- the expected poses, computed here from the CSV (schemas/path.md) ----

function readCsv(file) {
  const lines = fs.readFileSync(file, 'utf8').trim().split('\n');
  if (lines[0] !== 'x,y,z,qw,qx,qy,qz') throw new Error(file + ': unexpected header ' + lines[0]);
  return lines.slice(1).map((l) => {
    const v = l.split(',').map(Number);
    return { t: v.slice(0, 3), q: v.slice(3, 7) };
  });
}

function quatMul(a, b) {
  return [a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
    a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
    a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
    a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]];
}
// R(q) v as q v q*, written differently from the viewer on purpose.
function rotate(q, v) {
  const r = quatMul(quatMul(q, [0, v[0], v[1], v[2]]), [q[0], -q[1], -q[2], -q[3]]);
  return [r[1], r[2], r[3]];
}
// slerp by axis-angle of the relative rotation a^-1 b (shorter arc).
function slerp(a, b, s) {
  let rel = quatMul([a[0], -a[1], -a[2], -a[3]], b);
  if (rel[0] < 0) rel = rel.map((c) => -c);
  const angle = 2 * Math.acos(Math.min(1, rel[0]));
  const sinHalf = Math.sin(angle / 2);
  if (sinHalf < 1e-12) return a.slice();
  const axis = [rel[1] / sinHalf, rel[2] / sinHalf, rel[3] / sinHalf];
  const h = (s * angle) / 2;
  return quatMul(a, [Math.cos(h), axis[0] * Math.sin(h), axis[1] * Math.sin(h), axis[2] * Math.sin(h)]);
}
function expectedPose(wps, ref, origin, i, s) {
  const off = [ref[0] - origin[0], ref[1] - origin[1], ref[2] - origin[2]];
  const a = wps[i], b = wps[i + 1];
  const ra = rotate(a.q, off).map((c, k) => c + a.t[k]);
  const rb = rotate(b.q, off).map((c, k) => c + b.t[k]);
  const q = slerp(a.q, b.q, s);
  const tr = ra.map((c, k) => c + s * (rb[k] - c));
  return { t: rotate(q, off).map((c, k) => tr[k] - c), q };
}
function poseError(p, e) {
  const dt = Math.hypot(p.t[0] - e.t[0], p.t[1] - e.t[1], p.t[2] - e.t[2]);
  // About the rotation angle between them (q and -q are one rotation); unlike
  // 2 acos(|dot|) it does not lose half the digits near zero.
  const minus = Math.hypot(...p.q.map((c, k) => c - e.q[k])), plus = Math.hypot(...p.q.map((c, k) => c + e.q[k]));
  return { dt, dq: 2 * Math.min(minus, plus) };
}


// ---- the report's answers: headline, plots, table, section, measurement, download ----

async function checkHeadline(page, args, result) {
  const headline = await page.evaluate(() => {
    const word = document.getElementById('verdict-word'), why = document.getElementById('verdict-why');
    const section = document.getElementById('headline');
    const main = document.querySelector('main');
    return word && why ? { word: word.textContent, why: why.textContent, first: main.firstElementChild === section }
      : null;
  });
  result.headline = headline;
  if (!check(headline, 'no headline (#verdict-word, #verdict-why)')) return;
  check(headline.first, 'the headline is not the first thing in the page');
  if (args.expectHeadline) {
    check(headline.word === args.expectHeadline, `headline says '${headline.word}', expected '${args.expectHeadline}'`);
  } else {
    check(['REMOVABLE', 'NOT REMOVABLE', 'NO VERDICT'].includes(headline.word), `headline word '${headline.word}'`);
  }
  // One sentence: ends with a full stop, and no full stop followed by a capital inside.
  check(/\.$/.test(headline.why) && headline.why.length > 20 && !/\. [A-Z]/.test(headline.why),
    `the headline's reason is not one sentence: '${headline.why}'`);
  checkPlainWords(headline.why, 'the headline');
}

// Numbers in plain words: at least one with its unit, none missing as
// "inf", "nan", "null" or a lone dash, none bare before a colon ("after 195:";
// "waypoint 9:" names a waypoint).
const UNIT = /\d(\.\d+)?(e[+-]?\d+)? ?(mm|cm|m|in|inch|scene units|cubic scene units|s|rad)(?![A-Za-z])|\d°/;
function checkPlainWords(text, what) {
  check(UNIT.test(text), `${what} has no number with a unit: '${text}'`);
  check(!/(^|[^A-Za-z])(inf|infinity|nan|null|undefined)(?![A-Za-z])/i.test(text),
    `${what} says inf, nan or null: '${text}'`);
  check(!/(^|\s)–(\s|$|[.,;:])/.test(text), `${what} has a lone '–' for a missing value: '${text}'`);
  check(!/(^|[^\w.])(?<!waypoint )\d+(\.\d+)?:/.test(text), `${what} has a bare number before a colon: '${text}'`);
}

// The view is upright for the scene's up axis: the camera's up vector is the
// axis, the page says it, and a point above the view's centre (along up) is
// drawn straight above the centre on the screen.
async function checkUp(page, args, result) {
  const up = await page.evaluate(() => {
    const a = window.ausbau, v = a.view();
    if (!v) return { hook: a.up, view: null };
    const reach = Math.hypot(...v.position.map((c, k) => c - v.target[k]));
    const above = v.target.map((c, k) => c + 0.1 * reach * v.up[k]);
    return { hook: a.up, view: v, centre: a.project(v.target), above: a.project(above),
      said: document.getElementById('upinfo').textContent, table: document.getElementById('up-axis').textContent };
  });
  result.up = up;
  const axis = args.expectUp;
  const want = [0, 0, 0];
  want['xyz'.indexOf(axis.slice(-1))] = axis[0] === '-' ? -1 : 1;
  const same = (v) => v && v.length === 3 && v.every((c, k) => Math.abs(c - want[k]) < 1e-12);
  check(up.hook && up.hook.axis === axis && same(up.hook.vector),
    `window.ausbau.up is ${JSON.stringify(up.hook)}, expected axis ${axis} (${want})`);
  if (!check(up.view, 'no 3D view to check the up axis in')) return;
  check(same(up.view.up), `the camera's up vector is ${up.view.up}, expected ${want}`);
  check(up.above.y < up.centre.y - 5 && Math.abs(up.above.x - up.centre.x) < 1,
    `the view is not upright: up from the centre (${up.centre.x}, ${up.centre.y}) is drawn at (${up.above.x}, ${up.above.y})`);
  const words = 'up: ' + (axis[0] === '-' ? axis : '+' + axis) +
    (args.expectUpSource ? ' (' + args.expectUpSource + ')' : '');
  check(up.said.startsWith(words) && up.table.startsWith(words.slice(4)),
    `the page says '${up.said}' / '${up.table}', expected '${words}'`);
}

// At laptop sizes the page does not scroll sideways and the verdict table
// fits (long names wrap); the waypoint table may scroll inside its own box.
async function checkLayout(browser, html, args, result) {
  result.layout = [];
  for (const [width, height] of [[1280, 720], [1366, 768]]) {
    const page = await browser.newPage({ viewport: { width, height } });
    await page.goto('file://' + html, { waitUntil: 'load', timeout: args.timeoutMs });
    await page.waitForFunction(() => window.ausbau && (window.ausbau.ready || window.ausbau.error),
      null, { timeout: args.timeoutMs });
    const r = await page.evaluate(() => {
      const doc = document.documentElement, width = doc.clientWidth;
      const verdict = document.getElementById('json-verdict');
      // Elements that reach past the right edge, outside boxes that scroll.
      const over = Array.from(document.querySelectorAll('main *'))
        .filter((e) => !e.closest('#waypointbox') && e.getBoundingClientRect().right > width + 0.5)
        .slice(0, 5).map((e) => e.tagName + (e.id ? '#' + e.id : '') + ' ' + Math.round(e.getBoundingClientRect().right));
      return { scrollWidth: doc.scrollWidth, clientWidth: width, over,
        verdictRight: verdict ? verdict.getBoundingClientRect().right : null };
    });
    await page.close();
    result.layout.push(Object.assign({ width, height }, r));
    check(r.scrollWidth <= r.clientWidth, `at ${width}x${height} the page scrolls sideways ` +
      `(scrollWidth ${r.scrollWidth} > clientWidth ${r.clientWidth}; past the edge: ${r.over.join(', ')})`);
    check(r.over.length === 0, `at ${width}x${height} these reach past the right edge: ${r.over.join(', ')}`);
    if (args.expectTable === 'json-verdict') {
      check(r.verdictRight !== null && r.verdictRight <= r.clientWidth,
        `at ${width}x${height} the verdict table does not fit (right edge ${r.verdictRight} > ${r.clientWidth})`);
    }
  }
}

// In a Chromium without WebGL: the sentence in the 3D area, and the
// headline, the three plots (drawn) and every table still there, no error.
async function checkWithoutWebGL(args, html, result) {
  const browser = await chromium.launch({
    executablePath: args.chromium,
    headless: true,
    args: ['--disable-webgl', '--disable-webgl2', '--disable-3d-apis', '--no-sandbox'],
  });
  const out = {};
  result.withoutWebGL = out;
  try {
    const page = await browser.newPage({ viewport: { width: 1280, height: 720 } });
    const errors = [];
    page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
    page.on('pageerror', (e) => errors.push('page error: ' + e.message));
    await page.route('**/*', (route) => {
      const url = route.request().url();
      return url.startsWith('file://') || url.startsWith('data:') || url.startsWith('blob:') ? route.continue()
        : route.abort();
    });
    await page.goto('file://' + html, { waitUntil: 'load', timeout: args.timeoutMs });
    await page.waitForFunction(() => window.ausbau && (window.ausbau.ready || window.ausbau.error),
      null, { timeout: args.timeoutMs });
    Object.assign(out, await page.evaluate(() => {
      const a = window.ausbau, c = document.createElement('canvas');
      const drawn = Array.from(document.querySelectorAll('#plots canvas.plot')).map((canvas) => {
        const px = canvas.getContext('2d').getImageData(0, 0, canvas.width, canvas.height).data;
        let n = 0;
        for (let i = 3; i < px.length; i += 4) n += px[i] > 0;
        return { name: canvas.dataset.series, pixels: n, width: canvas.width, height: canvas.height };
      });
      const table = document.getElementById('waypoints');
      return { probe: !!(c.getContext('webgl2') || c.getContext('webgl')), ready: a.ready, error: a.error,
        webgl: a.webgl, sentence: (document.getElementById('nowebgl') || {}).textContent || null,
        headline: document.getElementById('verdict-why').textContent, drawn,
        paths: a.paths().map((p) => ({ key: p.key, waypoints: p.waypoints })),
        rows: table ? table.tBodies[0].rows.length : 0,
        tables: Array.from(document.querySelectorAll('table')).map((t) => t.id) };
    }));
    // The scrubber and Play still move the plots' cursor.
    out.timeAfterSeek = await page.evaluate(() => { window.ausbau.setTime(0.5); return window.ausbau.time(); });
    await page.evaluate(() => window.ausbau.setTime(0));
    await page.click('#play');
    out.played = await page.waitForFunction(() => window.ausbau.time() > 0, null, { timeout: 10000 })
      .then(() => true, () => false);
    await page.click('#play');
    await page.screenshot({ path: args.screenshot.replace(/\.png$/, '') + '-nowebgl.png', fullPage: true });
    out.errors = errors;
  } finally {
    await browser.close();
  }
  check(!out.probe, 'the browser started without WebGL still offers it: the no-WebGL check proves nothing');
  check(out.ready && !out.error && out.webgl === false, `without WebGL: ready ${out.ready}, error ${out.error}, ` +
    `webgl ${out.webgl}`);
  check(out.sentence === '3D view needs WebGL, which this browser does not offer; the plots and tables below do not.',
    `without WebGL the 3D area says '${out.sentence}'`);
  check(out.headline && out.headline.length > 20, 'without WebGL there is no headline');
  for (const name of ['clearance', 'rigid', 'clip']) {
    const plot = out.drawn.find((d) => d.name === name);
    check(plot && plot.width > 100 && plot.pixels > 500, `without WebGL the '${name}' plot is not drawn: ` +
      JSON.stringify(plot));
  }
  const shown = out.paths.find((p) => p.key === args.pathKey) || out.paths[0];
  check(shown && out.rows === shown.waypoints, `without WebGL the waypoint table has ${out.rows} rows`);
  for (const id of ['waypoints', 'stats', 'scene'].concat(args.expectTable ? [args.expectTable] : [])) {
    check(out.tables.includes(id), `without WebGL there is no table #${id} (has: ${out.tables.join(', ')})`);
  }
  check(out.timeAfterSeek === 0.5 && out.played, 'without WebGL the scrubber or Play does not work');
  check(out.errors.length === 0, 'without WebGL: console errors: ' + out.errors.join(' | '));
}

async function checkPlotsAndTable(page, entry, args, result) {
  const plots = await page.evaluate(() => window.ausbau.plots());
  result.plots = plots;
  for (const name of ['clearance', 'rigid', 'clip']) {
    const plot = plots.find((p) => p.name === name);
    if (!check(plot, `no '${name}' plot (has: ${plots.map((p) => p.name).join(', ')})`)) continue;
    check(plot.width > 100 && plot.height > 50, `the '${name}' plot is not drawn (${plot.width} x ${plot.height})`);
    check(plot.finite >= entry.waypoints && plot.finite > 0.5 * plot.points,
      `the '${name}' plot has ${plot.finite} values of ${plot.points}`);
  }
  // Aligned: the panels are stacked, one width, one x range.
  const boxes = await page.evaluate(() => Array.from(document.querySelectorAll('#plots canvas.plot'))
    .map((c) => { const r = c.getBoundingClientRect(); return { left: r.left, width: r.width, top: r.top }; }));
  check(boxes.every((b) => Math.abs(b.left - boxes[0].left) < 0.5 && Math.abs(b.width - boxes[0].width) < 0.5),
    'the plots are not aligned (different left edges or widths)');
  const clearance = plots.find((p) => p.name === 'clearance');
  check(clearance && clearance.max > 0, 'the clearance plot is zero everywhere');
  const table = await page.evaluate(() => {
    const t = document.getElementById('waypoints');
    if (!t) return null;
    const head = Array.from(t.tHead.rows[0].cells).map((c) => c.textContent);
    const rows = Array.from(t.tBodies[0].rows);
    const col = (name) => head.findIndex((h) => h.startsWith(name));
    const d = col('part of D'), s = col('part of S');
    return { head, rows: rows.length, hook: window.ausbau.waypointRows(),
      dParts: [...new Set(rows.map((r) => r.cells[d].textContent))],
      sParts: [...new Set(rows.map((r) => r.cells[s].textContent))],
      firstPose: rows.length ? rows[0].cells[2].textContent : '' };
  });
  result.table = table && { rows: table.rows, head: table.head, dParts: table.dParts.slice(0, 5),
    sParts: table.sParts.slice(0, 5) };
  if (!check(table, 'no waypoint table (#waypoints)')) return;
  check(table.rows === entry.waypoints && table.hook === entry.waypoints,
    `the waypoint table has ${table.rows} rows, the path ${entry.waypoints} waypoints`);
  for (const h of ['t = ', 'q = ', 'clearance', 'rigid penetration', 'clip intersection', 'part of D', 'part of S']) {
    check(table.head.some((x) => x.startsWith(h)), `the waypoint table has no '${h}' column (${table.head.join(' | ')})`);
  }
  check(table.dParts.every((n) => n && n !== '–' && !/^triangle \d+$/.test(n)) &&
        table.sParts.every((n) => n && n !== '–' && !/^triangle \d+$/.test(n)),
    `parts without names: D ${table.dParts.join('; ')} / S ${table.sParts.join('; ')}`);
  if (args.expectPart) {
    check(table.dParts.concat(table.sParts).some((n) => n.includes(args.expectPart)),
      `no part named '${args.expectPart}' (D: ${table.dParts.join('; ')}; S: ${table.sParts.join('; ')})`);
  }
}

async function checkSection(page, result) {
  const before = await page.evaluate(() => window.ausbau.pixelStats());
  const on = await page.evaluate(() => window.ausbau.setSection('x', 0.5));
  const cut = await page.evaluate(() => window.ausbau.pixelStats());
  const off = await page.evaluate(() => window.ausbau.setSection('', 0.5));
  const after = await page.evaluate(() => window.ausbau.pixelStats());
  result.section = { on, drawnBefore: before.nonBackground, drawnCut: cut.nonBackground };
  check(on.axis === 'x' && Number.isFinite(on.position) && on.clippedMaterials >= 2,
    `the section plane is not applied to S and D: ${JSON.stringify(on)}`);
  check(cut.hash !== before.hash && cut.nonBackground < before.nonBackground,
    `the section plane did not cut the picture (${before.nonBackground} -> ${cut.nonBackground} pixels drawn)`);
  check(off.clippedMaterials === 0 && after.hash === before.hash, 'switching the section plane off does not restore the view');
}

async function checkMeasurement(page, result) {
  const px = await page.evaluate(() => window.ausbau.pixelStats());
  if (!check(px.dPixel && px.sPixel, 'no pixel of D or of S to click')) return;
  await page.evaluate(() => window.ausbau.setMeasuring(true));
  await page.mouse.click(px.dPixel.x, px.dPixel.y);
  await page.mouse.click(px.sPixel.x, px.sPixel.y);
  const m = await page.evaluate(() => {
    const r = window.ausbau.measurement();
    return Object.assign(r, { projected: r.points.map((p) => window.ausbau.project(p)) });
  });
  await page.evaluate(() => window.ausbau.setMeasuring(false));
  result.measurement = { distance: m.distance, on: m.on, text: m.text };
  if (!check(m.points.length === 2, `two clicks gave ${m.points.length} measured points`)) return;
  const expected = Math.hypot(...m.points[0].map((c, k) => c - m.points[1][k]));
  check(m.distance > 0 && Math.abs(m.distance - expected) <= 1e-9 * (1 + expected),
    `measured distance ${m.distance}, the points are ${expected} apart`);
  [px.dPixel, px.sPixel].forEach((click, k) => {
    const p = m.projected[k];
    check(Math.hypot(p.x - click.x, p.y - click.y) < 2,
      `measured point ${k + 1} projects to (${p.x}, ${p.y}), not to the click (${click.x}, ${click.y})`);
  });
  const shown = /distance ([0-9.e+-]+)/.exec(m.text);
  check(shown && Math.abs(Number(shown[1]) - expected) <= 1e-5 * expected,
    `the page does not show the distance ${expected}: '${m.text}'`);
}

async function checkDownload(page, entry, args, result) {
  const link = page.locator('#download-' + entry.key);
  if (!check(await link.count() === 1, `no download link #download-${entry.key}`)) return;
  const [download] = await Promise.all([page.waitForEvent('download'), link.click()]);
  const file = await download.path();
  const got = fs.readFileSync(file, 'utf8'), want = fs.readFileSync(args.csv, 'utf8');
  result.download = { name: download.suggestedFilename(), bytes: got.length };
  check(got === want, `the downloaded CSV (${got.length} bytes) differs from ${args.csv} (${want.length} bytes)`);
}

async function main() {
  const args = parseArgs(process.argv);
  const html = path.resolve(args.html);
  const sizeBytes = fs.statSync(html).size;
  const browser = await chromium.launch({
    executablePath: args.chromium,
    headless: true,
    // WebGL without a GPU: SwiftShader through ANGLE.
    args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist', '--no-sandbox'],
  });
  const result = { html, sizeBytes };
  try {
    const page = await browser.newPage({ viewport: { width: 1280, height: 900 }, acceptDownloads: true });
    const consoleErrors = [];
    const external = [];
    page.on('console', (m) => { if (m.type() === 'error') consoleErrors.push(m.text()); });
    page.on('pageerror', (e) => consoleErrors.push('page error: ' + e.message));
    // Offline: any request for something other than the file itself or inline data fails the test.
    await page.route('**/*', (route) => {
      const url = route.request().url();
      if (url.startsWith('file://') || url.startsWith('data:') || url.startsWith('blob:')) return route.continue();
      external.push(url);
      return route.abort();
    });
    const t0 = Date.now();
    await page.goto('file://' + html, { waitUntil: 'load', timeout: args.timeoutMs });
    await page.waitForFunction(() => window.ausbau && (window.ausbau.ready || window.ausbau.error),
      null, { timeout: args.timeoutMs });
    result.wallToReadyMs = Date.now() - t0;
    result.loadMs = await page.evaluate(() => window.ausbau.loadMs);
    const error = await page.evaluate(() => window.ausbau.error);
    check(!error, 'the viewer reported an error: ' + error);
    result.pixels = await page.evaluate(() => window.ausbau.pixelStats());
    const px = result.pixels;
    check(px.nonBackground > 0.02 * px.pixels, `the 3D view is (nearly) blank: ${px.nonBackground} of ${px.pixels} pixels drawn`);
    check(px.sPixels > 0.01 * px.pixels, `S is not visible (hiding it changes ${px.sPixels} pixels)`);
    check(px.dPixels > 100, `D is not visible (hiding it changes ${px.dPixels} pixels)`);
    if (args.expectLabels) {
      check(await page.evaluate(() => window.ausbau.labelsShown()), 'D is not coloured by its labels (or no legend)');
    }
    await checkHeadline(page, args, result);
    if (args.expectUp) await checkUp(page, args, result);
    if (args.expectTable) {
      const rows = await page.evaluate((id) => { const t = document.getElementById(id); return t ? t.rows.length : -1; },
        args.expectTable);
      check(rows > 0, `no table #${args.expectTable} in the page (rows: ${rows})`);
    }

    if (!args.loadOnly) {
      const paths = await page.evaluate(() => window.ausbau.paths());
      const entry = paths.find((p) => p.key === args.pathKey);
      check(entry, `no '${args.pathKey}' path in the page (has: ${paths.map((p) => p.key).join(', ')})`);
      if (entry) {
        await page.evaluate((key) => window.ausbau.selectPath(key), entry.key);
        // Waypoints and mid-segment poses against the CSV.
        if (args.csv) {
          const wps = readCsv(args.csv);
          check(wps.length === entry.waypoints, `the page has ${entry.waypoints} waypoints, the CSV ${wps.length}`);
          const ref = args.ref.split(',').map(Number), origin = args.origin.split(',').map(Number);
          check(Math.hypot(...ref.map((c, k) => c - entry.reference_point[k])) < 1e-9,
            `reference point in the page ${entry.reference_point} != artifact's ${ref}`);
          let worstWaypoint = 0, worstMid = { dt: 0, dq: 0 };
          for (let i = 0; i < wps.length; ++i) {
            const pose = await page.evaluate((u) => { window.ausbau.setTime(u); return window.ausbau.poseOfD(); }, entry.times[i]);
            const err = poseError(pose, wps[i]);
            worstWaypoint = Math.max(worstWaypoint, err.dt, err.dq);
            if (i + 1 < wps.length) {
              for (const s of [0.3, 0.5]) {
                const u = entry.times[i] + s * (entry.times[i + 1] - entry.times[i]);
                const mid = await page.evaluate((v) => { window.ausbau.setTime(v); return window.ausbau.poseOfD(); }, u);
                const e = poseError(mid, expectedPose(wps, ref, origin, i, s));
                worstMid = { dt: Math.max(worstMid.dt, e.dt), dq: Math.max(worstMid.dq, e.dq) };
              }
            }
          }
          result.worstWaypointError = worstWaypoint;
          result.worstMidSegmentError = worstMid;
          check(worstWaypoint < 1e-12, `D is not at the waypoints at their times (error ${worstWaypoint})`);
          check(worstMid.dt < 1e-9 && worstMid.dq < 1e-9,
            `mid-segment poses differ from the path.md interpolation (dt ${worstMid.dt}, dq ${worstMid.dq})`);
        }
        await checkPlotsAndTable(page, entry, args, result);
        await page.evaluate(() => window.ausbau.setTime(0.5));
        await checkSection(page, result);
        await checkMeasurement(page, result);
        if (args.csv) await checkDownload(page, entry, args, result);
        // The scrubber, with the mouse: D moves and the picture changes.
        const scrubber = page.locator('#scrubber');
        const box = await scrubber.boundingBox();
        await scrubber.click({ position: { x: box.width * 0.05, y: box.height / 2 } });
        const before = await page.evaluate(() => ({ pose: window.ausbau.poseOfD(), u: window.ausbau.time(),
          hash: window.ausbau.pixelStats().hash }));
        await scrubber.click({ position: { x: box.width * 0.8, y: box.height / 2 } });
        const after = await page.evaluate(() => ({ pose: window.ausbau.poseOfD(), u: window.ausbau.time(),
          hash: window.ausbau.pixelStats().hash }));
        result.scrubber = { before: before.u, after: after.u };
        check(after.u > before.u + 0.5, `the scrubber did not move the time (${before.u} -> ${after.u})`);
        const moved = poseError(before.pose, after.pose);
        check(moved.dt > 0 || moved.dq > 0, 'moving the scrubber did not change D\'s pose');
        check(before.hash !== after.hash, 'moving the scrubber did not change the picture');
        // Play advances the time.
        // (Software rendering of a large S can take a second per frame: wait for it.)
        await page.evaluate(() => window.ausbau.setTime(0));
        const frames0 = await page.evaluate(() => window.ausbau.frames);
        const playStart = Date.now();
        await page.click('#play');
        await page.waitForTimeout(1000);
        const advanced = await page.waitForFunction(() => window.ausbau.time() > 0, null, { timeout: 30000 })
          .then(() => true, () => false);
        const [playing, frames1] = await page.evaluate(() => [window.ausbau.time(), window.ausbau.frames]);
        const playedS = (Date.now() - playStart) / 1000;
        await page.click('#play');
        result.timeAfterPlay = playing;
        result.framesPerSecondPlaying = (frames1 - frames0) / playedS;  // software rendering here
        check(advanced && playing > 0, 'Play did not advance the animation');
        // For the screenshot: D on its way out.
        await page.evaluate(() => window.ausbau.setTime(0.45));
      }
    }
    await page.waitForTimeout(200);
    await page.screenshot({ path: args.screenshot, fullPage: true });
    result.screenshot = args.screenshot;
    check(consoleErrors.length === 0, 'console errors: ' + consoleErrors.join(' | '));
    check(external.length === 0, 'requests outside the file: ' + external.join(', '));
    if (args.checkLayout) await checkLayout(browser, html, args, result);
  } finally {
    await browser.close();
  }
  if (args.checkNoWebgl) await checkWithoutWebGL(args, html, result);
  result.failures = failures;
  console.log(JSON.stringify(result));
  if (failures.length) {
    for (const f of failures) console.error('report_test: FAIL: ' + f);
    process.exit(1);
  }
  console.error('report_test: all checks passed');
}

main().catch((e) => {
  console.error('report_test: error: ' + (e && e.stack ? e.stack : e));
  process.exit(1);
});
