// The lab in a real browser: Debian's headless Chromium driven through the
// DevTools protocol (puppeteer-core). Starts `rocking serve` on a free port,
// loads the lab, checks there are no console errors, moves the
// damper-thickness slider as a user would (arrow keys) and checks that the
// rocking-angle trace and the summary change and equal the same run made by
// `rocking simulate --json` (the summary to the digits shown, the trace to
// the six digits sent), switches compare mode on (a server variant, then a
// twin of overrides of the user's own, run and laddered by the IDA as the
// command line runs them), checks that every chart
// has data in its plot area and that the structure drawn at its peak tilts by
// the history's theta (times the drawing's exaggeration), opens every lesson,
// and saves a screenshot; checks that the charts are built from the schema
// entries the server sends (altered on their way, the page shows the altered
// words, symbol, unit and factor); draws the stacked blocks, each block
// turning about its joint's corner by the history's rotations, with a chart
// of the joints' rotations; draws the chimney on rocking columns, each column
// turned about its pivot corner by the columns' rocking angle and the cap
// beam moved on their tops as MODEL.md 16 says, the chimney standing on it.
// Reports the page's re-run-and-redraw time.
//
//   ROCKING_BIN=build/bin/rocking node lab/tests/browser.test.mjs
// Environment: ROCKING_RECORDS (the records), ROCKING_LAB_SCREENSHOT (where
// the screenshot goes, and beside it, named -joints and -columns, those of
// the stacked blocks and of the chimney on columns; default
// build/lab/lab.png), ROCKING_LAB_MOVES (slider
// moves timed, default 8; `make bench` asks for more), CI=true (a missing
// browser or record is a failure, not a skip).
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdirSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join } from 'node:path';
import { formatG } from '../format.js';
import { lessons } from '../lessons.js';
import {
  repo, bin, records, requireBrowserAndRecords, startServer, launchBrowser, settled, runsOf,
} from './harness.mjs';

const screenshot = process.env.ROCKING_LAB_SCREENSHOT || join(repo, 'build', 'lab', 'lab.png');
const moves = Number(process.env.ROCKING_LAB_MOVES || 8);
const record = 'elcentro_1940_ns.at2';
requireBrowserAndRecords('browser test', [record, 'christchurch2011_pphs_s57e.at2']);  // and the lessons'

// The same run by the command line: its summary and its history.
function commandLine(set) {
  const dir = mkdtempSync(join(tmpdir(), 'lab-cli-'));
  const args = ['simulate', '--record', join(records, record), '--scale', '3', '--every', '0.02', '--json',
    '--history', 't,theta_over_alpha', '--out', dir, ...set.flatMap((s) => ['--set', s])];
  const summary = JSON.parse(execFileSync(bin, args, { stdio: ['ignore', 'pipe', 'ignore'] }).toString());
  const lines = readFileSync(join(dir, 'history.csv'), 'utf8').trim().split('\n');
  const header = lines[0].split(',');
  const column = header.findIndex((h) => h.startsWith('theta_over_alpha'));
  const theta = lines.slice(1).map((l) => Number(l.split(',')[column]));
  rmSync(dir, { recursive: true });
  return { summary, theta };
}

// The summary cells the page shows for the main run: {peak: text}.
const shownPeaks = (page) => page.evaluate(() => Object.fromEntries(
  [...document.querySelectorAll('td[data-run="main"]')].map((td) => [td.dataset.peak, td.textContent])));

// From now on, every line segment the page strokes on #drawing (from, to,
// width, colour) goes into window.drawnSegments, emptied here; the recorder
// is installed once on the canvas's context.
const recordStrokes = (page) => page.evaluate(() => {
  const ctx = document.querySelector('#drawing').getContext('2d');
  window.drawnSegments = [];
  if (ctx.strokesRecorded) return;
  ctx.strokesRecorded = true;
  const move = ctx.moveTo.bind(ctx), line = ctx.lineTo.bind(ctx);
  let from = null;
  ctx.moveTo = (x, y) => { from = [x, y]; move(x, y); };
  ctx.lineTo = (x, y) => {
    if (from) window.drawnSegments.push({ from, to: [x, y], width: ctx.lineWidth, color: ctx.strokeStyle });
    from = [x, y];
    line(x, y);
  };
});

const { server, url } = await startServer();
const browser = await launchBrowser();
const failures = [];
try {
  const page = await browser.newPage();
  await page.setViewport({ width: 1280, height: 1000 });
  const consoleErrors = [];
  page.on('console', (m) => { if (m.type() === 'error') consoleErrors.push(m.text()); });
  page.on('pageerror', (e) => consoleErrors.push(String(e)));

  await page.goto(url, { waitUntil: 'load' });
  await settled(page, 0);
  assert.equal(await page.$eval('#error', (e) => e.hidden), true, 'the first run shows no error');

  // El Centro x3, then the damper thickness moved from 1 to 1.5 by ten presses of the right arrow.
  let n = await runsOf(page);
  await page.select('#record', record);
  await settled(page, n);
  n = await runsOf(page);
  await page.$eval('#scale', (e) => { e.value = '3'; e.dispatchEvent(new Event('input', { bubbles: true })); });
  await settled(page, n);
  const before = { peaks: await shownPeaks(page), theta: await page.evaluate(() => window.lab.data.history.theta_over_alpha) };
  const request0 = await page.evaluate(() => window.lab.request);
  assert.deepEqual(request0.set, [], 'thickness 1 asks for no override');
  n = await runsOf(page);
  await page.focus('#thickness');
  for (let k = 0; k < 10; k += 1) await page.keyboard.press('ArrowRight');
  await settled(page, n);
  const thickness = await page.$eval('#thickness', (e) => e.value);
  assert.equal(thickness, '1.5', 'ten steps of 0.05 from 1');
  const after = { peaks: await shownPeaks(page), theta: await page.evaluate(() => window.lab.data.history.theta_over_alpha) };
  const request = await page.evaluate(() => window.lab.request);
  assert.deepEqual(request.set, ['damper.thickness=1.5']);
  assert.notEqual(after.peaks.theta_over_alpha, before.peaks.theta_over_alpha, 'the peak rocking angle changed');
  assert.ok(after.theta.some((v, i) => v !== before.theta[i]), 'the rocking-angle trace changed');

  const cli = commandLine(['damper.thickness=1.5']);
  for (const [name, value] of Object.entries(cli.summary.peaks))
    assert.equal(after.peaks[name], formatG(value, 4), `peak ${name}: the page shows the command line's ${value}`);
  assert.equal(after.peaks.outcome, cli.summary.outcome);
  assert.equal(after.peaks.counts, `${cli.summary.counts.uplifts}, ${cli.summary.counts.impacts}`);
  // The command line's rows, and one more at the run's end when the last is earlier (the energy bars' last frame).
  const tEnd = await page.evaluate(() => window.lab.data.summary.t_end);
  const pageT = await page.evaluate(() => window.lab.data.history.t);
  assert.ok(after.theta.length === cli.theta.length || after.theta.length === cli.theta.length + 1,
    `the trace has the command line history's rows (${after.theta.length} against ${cli.theta.length})`);
  assert.ok(Math.abs(pageT[pageT.length - 1] - tEnd) <= 1e-6 * tEnd, 'the last row is the run\'s end');
  after.theta.length = cli.theta.length;
  after.theta.forEach((v, i) => assert.ok(Math.abs(v - cli.theta[i]) <= 5e-6 * Math.abs(cli.theta[i]) + 1e-12,
    `theta/alpha at row ${i}: page ${v}, command line ${cli.theta[i]}`));

  // Redraw time: further slider moves, each waited for.
  const times = [];
  for (let k = 0; k < moves; k += 1) {
    n = await runsOf(page);
    await page.keyboard.press(k % 2 ? 'ArrowRight' : 'ArrowLeft');
    await settled(page, n);
    times.push(await page.evaluate(() => window.lab.redrawMs));
  }
  times.sort((a, b) => a - b);
  console.log(`lab redraw (chimney, El Centro x3, a slider move to the traces redrawn), ${moves} moves: ` +
    `min ${times[0].toFixed(1)} ms, median ${times[Math.floor(times.length / 2)].toFixed(1)} ms, ` +
    `max ${times[times.length - 1].toFixed(1)} ms`);

  // Compare mode: the fixed-base twin beside it.
  n = await runsOf(page);
  await page.select('#compare', 'fixed-base');
  await settled(page, n);
  const twin = await page.evaluate(() => ({
    variant: window.lab.data.twin && window.lab.data.twin.variant,
    cells: [...document.querySelectorAll('td[data-run="twin"]')].map((td) => td.textContent).filter((t) => t && t !== '–'),
    legends: [...document.querySelectorAll('.u-legend .u-label')].map((e) => e.textContent),
  }));
  assert.equal(twin.variant, 'fixed-base');
  assert.ok(twin.cells.length >= 5, 'the twin\'s summary is shown');
  assert.ok(twin.legends.some((l) => l.includes('(twin)')), 'the traces show the twin');
  // A small IDA from the page: the record scaled 0.5 to 5, the structure and its twin.
  await page.click('#ida');
  await page.waitForFunction(() => window.lab.ida && !window.lab.idaBusy, { timeout: 60000 });
  const ida = await page.evaluate(() => ({ rows: window.lab.ida.rows.length, chart: Boolean(document.querySelector('#ida-chart canvas')) }));
  assert.equal(ida.rows, 20, 'ten levels for the structure and its twin');
  assert.ok(ida.chart, 'the IDA is drawn');

  // Every chart has data in its plot area: coloured pixels (the traces; grid
  // and axes are grey) in most of the plot's columns, not only the one the
  // time cursor crosses.
  await page.evaluate(() => new Promise((ok) => requestAnimationFrame(() => ok())));
  const covered = await page.evaluate(() => [...window.lab.charts, window.lab.idaChart].map((u) => {
    const { left, top, width, height } = u.bbox;
    const { data } = u.ctx.getImageData(Math.round(left), Math.round(top), Math.round(width), Math.round(height));
    const w = Math.round(width);
    const columns = new Set();
    for (let i = 0; i < data.length; i += 4) {
      const [r, g, b, a] = [data[i], data[i + 1], data[i + 2], data[i + 3]];
      if (a > 128 && Math.max(r, g, b) - Math.min(r, g, b) > 60) columns.add((i / 4) % w);
    }
    return { title: u.root.querySelector('.u-title')?.textContent || '', fraction: columns.size / w };
  }));
  assert.ok(covered.length >= 2, 'the traces and the IDA are charts');
  for (const [k, c] of covered.entries())
    assert.ok(c.fraction >= (k === covered.length - 1 ? 0.25 : 0.5), `chart '${c.title}': data in ${(100 * c.fraction).toFixed(0)} % of its plot's columns`);

  // The structure as drawn: the foundation beams' lines (the first path of
  // width 3 of each run, main first) recorded as the page strokes them.
  await recordStrokes(page);
  // The screenshot at the main run's peak rocking angle: the structures drawn rocking and bent.
  const peak = await page.evaluate(() => {
    const h = window.lab.data.history;
    let k = 0;
    h.theta.forEach((v, i) => { if (Math.abs(v) > Math.abs(h.theta[k])) k = i; });
    window.drawnSegments = [];
    const time = document.querySelector('#time');
    time.value = h.t[k];
    time.dispatchEvent(new Event('input', { bubbles: true }));
    return { theta: h.theta[k], factor: window.lab.factors.theta };
  });
  await page.evaluate(() => new Promise((ok) => requestAnimationFrame(() => ok())));
  const beams = await page.evaluate(() => window.drawnSegments.filter((s) => s.width === 3));
  assert.ok(peak.theta !== 0, 'the run rocks');
  assert.ok(beams.length >= 2, `the structure and its twin drawn: ${beams.length} foundation beams`);
  // Screen y points down: the beam's angle atan2(dy, dx) is the drawn tilt theta x factor.
  const drawnTilt = (b) => Math.atan2(b.to[1] - b.from[1], b.to[0] - b.from[0]);
  assert.ok(Math.abs(drawnTilt(beams[0]) - peak.theta * peak.factor) <= 1e-9,
    `the structure drawn at its peak tilts ${drawnTilt(beams[0])} rad, the history's theta ${peak.theta} x ${peak.factor}`);
  assert.ok(Math.abs(drawnTilt(beams[1])) <= 1e-12, 'the fixed-base twin stands upright');
  mkdirSync(dirname(screenshot), { recursive: true });
  await page.screenshot({ path: screenshot, fullPage: true });
  console.log(`wrote ${screenshot}`);

  // A twin of the user's own overrides, which the page asks for as a second run: it is the command line's
  // run with those overrides after the page's; its IDA ladder runs beside this run's; its failure is said.
  n = await runsOf(page);
  await page.$eval('#twin-extra', (e) => { e.value = 'damper.thickness=3'; });
  await page.select('#compare', 'overrides');
  await settled(page, n);
  const own = await page.evaluate(() => ({ variant: window.lab.data.twin && window.lab.data.twin.variant,
    peaks: window.lab.data.twin && window.lab.data.twin.summary.peaks, request: window.lab.request }));
  assert.equal(own.variant, 'with damper.thickness=3');
  assert.equal(own.request.compare, undefined, 'no server twin asked for');
  const thicker = commandLine(['damper.thickness=1.5', 'damper.thickness=3']).summary.peaks;
  for (const [name, value] of Object.entries(thicker))
    assert.equal(formatG(own.peaks[name], 4), formatG(value, 4), `the twin's peak ${name}: the command line's ${value}`);
  await page.click('#ida');
  await page.waitForFunction(() => window.lab.ida && window.lab.ida.rows.some((r) => r.variant.startsWith('with ')) && !window.lab.idaBusy,
    { timeout: 60000 });
  const ladders = await page.evaluate(() => window.lab.ida.rows.map((r) => [r.variant, r.level, r.peaks.theta_over_alpha]));
  assert.deepEqual([...new Set(ladders.map((r) => r[0]))], ['scene', 'with damper.thickness=3'], 'this run\'s ladder and the twin\'s');
  assert.equal(ladders.length, 20, 'ten levels each');
  const at3 = ladders.filter((r) => r[1] === 3);
  assert.equal(formatG(at3[1][2], 4), formatG(thicker.theta_over_alpha, 4), 'the twin\'s ladder at scale 3 is the twin\'s run');
  const failed = await page.evaluate(() => window.lab.failures);
  await page.$eval('#twin-extra', (e) => { e.value = 'structure.EI_scale=-1'; e.dispatchEvent(new Event('change', { bubbles: true })); });
  await page.waitForFunction((k) => window.lab.failures > k && !window.lab.busy, { timeout: 30000 }, failed);
  const twinError = await page.$eval('#error', (e) => e.textContent);
  assert.match(twinError, /the twin \(with structure\.EI_scale=-1\).*EI_scale/, twinError);
  n = await runsOf(page);
  await page.$eval('#twin-extra', (e) => { e.value = ''; });
  await page.select('#compare', 'fixed-base');
  await settled(page, n);

  // A record file of the user's own, uploaded from the page, runs as the folder's.
  n = await runsOf(page);
  const input = await page.$('#upload');
  await input.uploadFile(join(records, record));
  await settled(page, n);
  const uploaded = await page.evaluate(() => ({ record: document.querySelector('#record').value, peaks: window.lab.data.summary.peaks }));
  assert.match(uploaded.record, /^upload\/\d+\/elcentro_1940_ns\.at2$/);
  const again = cli.summary.peaks;  // the same record, scale 3, thickness 1.5 (the twin changes no peak of the run)
  assert.equal(formatG(uploaded.peaks.theta_over_alpha, 4), formatG(again.theta_over_alpha, 4), 'the upload runs as the file');

  // Bad input from the page: the server's one line, shown.
  n = await runsOf(page);
  await page.$eval('#extra', (e) => { e.value = 'structure.EI_scale=-1'; e.dispatchEvent(new Event('change', { bubbles: true })); });
  await page.waitForFunction(() => !document.querySelector('#error').hidden, { timeout: 30000 });
  const message = await page.$eval('#error', (e) => e.textContent);
  assert.match(message, /EI_scale/, 'the error names the key');
  assert.ok(!message.includes('\n'), 'in one line');

  // Every lesson opens, runs and shows no error.
  for (let k = 0; k < lessons.length; k += 1) {
    await page.goto(`${url}?lesson=${k}`, { waitUntil: 'load' });
    await settled(page, 0);
    const shown = await page.evaluate(() => ({
      error: document.querySelector('#error').hidden ? '' : document.querySelector('#error').textContent,
      title: document.querySelector('#lesson-text h2') && document.querySelector('#lesson-text h2').textContent,
      twin: Boolean(window.lab.data.twin),
    }));
    assert.equal(shown.error, '', `lesson ${k}: no error`);
    assert.equal(shown.title, lessons[k].title);
    assert.equal(shown.twin, Boolean(lessons[k].controls.compare), `lesson ${k}: its twin`);
  }
  // The charts are built from what the server states: its schema entries, altered on their way to the
  // page (the total drift's words, symbol, display unit and factor), are what the page shows.
  await page.setRequestInterception(true);
  page.on('request', async (request) => {
    if (!request.url().endsWith('/api/simulate')) {
      request.continue();
      return;
    }
    const response = await fetch(request.url(), { method: 'POST', body: request.postData() });
    const body = await response.json();
    for (const c of body.columns || [])
      if (c.name === 'delta_t') Object.assign(c, { words: 'sway as the server words it', symbol: 'Σ', display_unit: 'permille', factor: 1000 });
    request.respond({ status: response.status, contentType: 'application/json', body: JSON.stringify(body) });
  });
  await page.goto(url, { waitUntil: 'load' });
  await settled(page, 0);
  const drift = await page.evaluate(() => {
    const u = window.lab.charts.find((c) => c.root.parentElement.dataset.chart === 'delta_t');
    const h = window.lab.data.history;
    let k = 0;
    h.delta_t.forEach((v, i) => { if (Math.abs(v) > Math.abs(h.delta_t[k])) k = i; });
    const row = u.data[0].indexOf(h.t[k]);
    return { title: u.root.querySelector('.u-title').textContent, axis: u.axes[1].label, legend: u.series[1].label,
      shown: row >= 0 ? u.data[1][row] : null, value: h.delta_t[k] };
  });
  assert.equal(drift.title, 'sway as the server words it');
  assert.match(drift.axis, /^Σ(, δ_e)? \[permille(, %)?\]$/, drift.axis);
  assert.equal(drift.legend, 'Σ');
  assert.ok(drift.shown !== null && Math.abs(drift.shown - 1000 * drift.value) <= 1e-9 * Math.abs(drift.shown),
    `drawn at the factor stated: ${drift.shown} for ${drift.value}`);
  await page.setRequestInterception(false);
  page.removeAllListeners('request');

  // Joints: the stacked blocks drawn block by block, the artefact turning on its plinth's corner by joint1.theta
  // (times the drawing's exaggeration) at the frame of its peak, and a chart of the joints' rotations.
  await page.goto(url, { waitUntil: 'load' });
  await settled(page, 0);
  n = await runsOf(page);
  await page.select('#scene', 'stacked_blocks');
  await settled(page, n);
  await recordStrokes(page);
  const jointed = await page.evaluate(() => {
    const h = window.lab.data.history;
    const j = h['joint1.theta'];
    let k = 0;
    j.forEach((v, i) => { if (Math.abs(v) > Math.abs(j[k])) k = i; });
    const time = document.querySelector('#time');
    time.value = h.t[k];
    time.dispatchEvent(new Event('input', { bubbles: true }));
    return { base: h.theta[k], joint: j[k], factor: window.lab.factors.theta, t: h.t[k],
      beams: window.drawnSegments.filter((s) => s.width === 3),
      charts: window.lab.charts.map((u) => u.root.parentElement.dataset.chart) };
  });
  assert.ok(jointed.joint !== 0, 'the artefact rocks');
  assert.equal(jointed.beams.length, 2, 'the plinth and the artefact, each its own base');
  const tilt = (b) => Math.atan2(b.to[1] - b.from[1], b.to[0] - b.from[0]);
  assert.ok(Math.abs(tilt(jointed.beams[0]) - jointed.base * jointed.factor) <= 1e-9,
    `the plinth drawn at t = ${jointed.t} s tilts ${tilt(jointed.beams[0])}, theta ${jointed.base} x ${jointed.factor}`);
  assert.ok(Math.abs(tilt(jointed.beams[1]) - tilt(jointed.beams[0]) - jointed.joint * jointed.factor) <= 1e-9,
    `the artefact drawn turns ${tilt(jointed.beams[1]) - tilt(jointed.beams[0])} on the plinth, joint1.theta ${jointed.joint} x ${jointed.factor}`);
  assert.ok(jointed.charts.includes('joint1.theta'), `a chart of the joints' rotations: ${jointed.charts}`);
  await page.screenshot({ path: screenshot.replace(/\.png$/, '-joints.png'), fullPage: true });

  // Columns: the chimney (flexible, its rocking exaggerated) and the bridge bent (a rigid deck) on rocking
  // columns, each at the frame of the columns' peak rocking angle. Each column's corners are drawn where its
  // rest corners go, turned by theta (times the drawing's exaggeration) about its bottom corner on theta's
  // side; the cap beam, moved by MODEL.md 16's (dx, dy) without turning; the structure's axis standing on
  // the beam's middle. Theta is the history's columns.theta, or its columns.theta_over_alpha times the
  // columns' alpha = atan(b/h) where only that is sent. The screenshot is the bent's.
  for (const scene of ['chimney_on_columns', 'rocking_frame']) {
    n = await runsOf(page);
    await page.select('#scene', scene);
    await settled(page, n);
    await recordStrokes(page);
    const onColumns = await page.evaluate(() => {
      const { history: h, structure } = window.lab.data;
      const c = structure.columns;
      const theta = h['columns.theta'] || h['columns.theta_over_alpha'].map((v) => v * Math.atan(c.half_width / c.half_height));
      let k = 0;
      theta.forEach((v, i) => { if (Math.abs(v) > Math.abs(theta[k])) k = i; });
      window.drawnSegments = [];
      const time = document.querySelector('#time');
      time.value = h.t[k];
      time.dispatchEvent(new Event('input', { bubbles: true }));
      return { columns: c, theta: theta[k], t: h.t[k], factor: window.lab.factors.theta, scale: window.lab.scaleBar.scale,
        origin: window.lab.origins[0], segments: window.drawnSegments.filter((x) => x.color === '#1f5fa8'),
        peaks: window.lab.data.summary.peaks, text: document.querySelector('#run-text').textContent, rigid: structure.rigid };
    });
    const { columns: c, theta, factor, scale, origin, segments } = onColumns;
    assert.ok(c && c.count >= 2, `${scene} stands on columns: ${JSON.stringify(c)}`);
    assert.ok(theta !== 0, `${scene}: the columns rock`);
    const phi = theta * factor;
    const s = Math.sign(phi);
    const R = Math.hypot(c.half_width, c.half_height);
    const alpha = Math.atan(c.half_width / c.half_height);
    const b = c.half_width;
    const top = 2 * c.half_height;
    // A point [m] of the ground's frame where the page draws it [px]: y up in metres, down on the screen.
    const px = ([x, y]) => [origin[0] + x * scale, origin[1] - y * scale];
    const near = (drawn, expected, what) => drawn.forEach((v, j) => assert.ok(Math.abs(v - expected[j]) <= 1e-9 * Math.max(1, Math.abs(expected[j])),
      `${scene}: ${what} at t = ${onColumns.t} s: drawn at ${drawn}, expected ${expected}`));
    // Turned clockwise by phi (theta > 0 tips the top towards +x) about the pivot.
    const turned = ([x, y], [px0, py0]) => [px0 + (x - px0) * Math.cos(phi) + (y - py0) * Math.sin(phi),
      py0 - (x - px0) * Math.sin(phi) + (y - py0) * Math.cos(phi)];
    const outlines = segments.filter((x) => x.width === 2);
    assert.ok(outlines.length >= 4 * c.count, `${outlines.length} outline strokes for ${c.count} columns`);
    for (let k = 0; k < c.count; k += 1) {
      const axis = -c.spacing / 2 + (c.spacing * k) / (c.count - 1);
      const pivot = [axis + s * b, 0];
      const rest = [[axis - b, 0], [axis - b, top], [axis + b, top], [axis + b, 0], [axis - b, 0]];
      for (let j = 0; j < 4; j += 1) {
        const stroke = outlines[4 * k + j];
        near(stroke.from, px(turned(rest[j], pivot)), `column ${k}, corner ${j}`);
        near(stroke.to, px(turned(rest[j + 1], pivot)), `column ${k}, corner ${j + 1}`);
      }
    }
    const dx = 2 * R * s * (Math.sin(alpha) - Math.sin(alpha - s * phi));
    const dy = 2 * R * (Math.cos(alpha - s * phi) - Math.cos(alpha));
    const beams = segments.filter((x) => x.width === 3);
    assert.equal(beams.length, 1, `${scene}: one cap beam`);
    const ends = [-c.spacing / 2 - b, c.spacing / 2 + b];
    near(beams[0].from, px([ends[0] + dx, top + dy]), 'the beam\'s left end');
    near(beams[0].to, px([ends[1] + dx, top + dy]), 'the beam\'s right end');
    const axis = segments.filter((x) => x.width === (onColumns.rigid ? 1.5 : 4));  // a block's axis is thin
    assert.ok(axis.length > 0, `${scene}: the structure drawn`);
    near(axis[0].from, px([dx, top + dy]), `${scene}: the structure's base, on the beam's middle`);
    // The server's beam.x is this dx (relative to the ground) at true scale: its peak is dx at the peak theta.
    const p = onColumns.peaks;
    const peakDx = 2 * R * (Math.sin(alpha) - Math.sin(alpha - Math.abs(p['columns.theta'])));
    assert.ok(Math.abs(p['beam.x'] - peakDx) <= 1e-6 * peakDx, `peak beam.x ${p['beam.x']} m, 2R (sin alpha - sin(alpha - theta)) ${peakDx} m`);
    assert.match(onColumns.text, /rocking columns.*tilt together/, 'the words say the columns rock');
  }
  await page.screenshot({ path: screenshot.replace(/\.png$/, '-columns.png'), fullPage: true });

  consoleErrors.splice(0, consoleErrors.length, ...consoleErrors.filter((e) => !e.includes('status of 400')));
  assert.deepEqual(consoleErrors, [], 'no console errors');
} catch (e) {
  failures.push(e);
} finally {
  await browser.close();
  server.kill('SIGINT');
}
if (failures.length > 0) {
  console.error(`browser test FAILED: ${failures[0].stack || failures[0]}`);
  process.exit(1);
}
console.log('browser test passed');
