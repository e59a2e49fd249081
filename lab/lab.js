// The lab's page: controls -> POST /api/simulate -> the structure drawn
// rocking, synchronised traces (uPlot), the devices' loops and the summary.
// A control's move re-runs at once; moves made while a run is in flight are
// gathered into one run after it. window.lab exposes the state for the
// browser test.
import {
  formatG, buildRequest, twinChoices, tendonOf, damperDevices, peakOf, exaggeration, bodyPoints, pulses, ownPulse, groundStill,
  forStudents, axisRange, describeRun, peakTitle, groundDrawn, scaleBar, drawnRows, energyBars, chartsFrom, columnOf,
  chainPoints, columnsPoints, columnsThetaOf, twinRequest, otherOverrides, outcomeStatement,
} from './format.js';
import { lessons } from './lessons.js';

const $ = (id) => document.getElementById(id);
const state = {
  scenes: [], records: [], data: null, runs: 0, failures: 0, redrawMs: null, index: 0, playing: false, charts: [], dampersWanted: true,
};
window.lab = state;

const colors = { main: '#1f5fa8', twin: '#c0392b', ground: '#555' };

function sceneOf(id) {
  return state.scenes.find((s) => s.id === id);
}

function controls() {
  return {
    scene: $('scene').value,
    record: $('record').value,
    amplitude: Number($('amplitude').value),
    period: Number($('period').value),
    scale: Number($('scale').value),
    dampers: $('dampers').checked,
    thickness: Number($('thickness').value),
    prestress: Number($('prestress').value),
    restitution: $('own-restitution').checked ? null : Number($('restitution').value),
    compare: $('compare').value,
    twinExtra: $('twin-extra').value,
    extra: $('extra').value,
  };
}

function setStatus(text, kind) {
  $('status').textContent = text;
  $('status').dataset.state = kind;
}

function showError(message) {
  $('error').textContent = message || '';
  $('error').hidden = !message;
}

// A run that failed: what is drawn is greyed (the last run that worked) and
// the reason is said in words a student can act on.
function showFailure(message) {
  state.failures += 1;
  $('view').classList.add('stale');
  showError(`This run could not be made: ${forStudents(message)}. The greyed plots are the last run that worked; ` +
    'change the setting named here (or press reset) and it runs again.');
  setStatus('run failed', 'error');
  $('run-text').textContent = 'The last run failed; the plots show the run before it.';
}

// The controls that apply to the scene, and its twins.
function fitControls() {
  const scene = sceneOf($('scene').value);
  if (!scene) return;
  $('scene-description').textContent = scene.description || '';
  if (state.shownScene !== scene.id) {  // a new scene: the pulse sliders start at its own pulse
    state.shownScene = scene.id;
    if (scene.pulse) {
      $('amplitude').value = scene.pulse.amplitude_g;
      $('period').value = scene.pulse.period;
    }
  }
  // A scene without dampers shows the box unticked and greyed, whatever was chosen on another.
  const hasDampers = scene.damper || damperDevices(scene).length > 0;
  $('dampers').disabled = !hasDampers;
  $('dampers').checked = hasDampers && state.dampersWanted;
  $('thickness').disabled = !scene.damper || !$('dampers').checked;
  $('prestress').disabled = !tendonOf(scene);
  const keep = $('compare').value;
  $('compare').replaceChildren(...twinChoices(scene).map((c) => new Option(c.label, c.value)));
  if ([...$('compare').options].some((o) => o.value === keep)) $('compare').value = keep;
  $('twin-extra-box').hidden = $('compare').value !== otherOverrides;
  // The pulse sliders act on a pulse: one chosen from the list, or the scene's own.
  const still = groundStill($('extra').value);
  const pulse = $('record').value.startsWith('pulse:') || ownPulse(controls(), scene);
  $('amplitude').disabled = !pulse;
  $('period').disabled = !pulse;
  $('pulse-note').textContent = pulse ? '' : still ? 'The ground stays still in this run (no excitation).'
    : 'The pulse sliders act on a pulse; this record is scaled by the scale slider.';
  for (const id of ['amplitude', 'period', 'scale', 'thickness', 'prestress', 'restitution'])
    $(`${id}-value`).textContent = $(id).value;
  $('record').options[0].textContent = `the scene's own (${still ? 'none: the ground stays still' : scene.excitation})`;
}

let inFlight = false;
let pending = null;

// Re-runs for the controls as they are; `started` is when the user moved one.
async function rerun(started = performance.now()) {
  state.busy = true;
  if (inFlight) {
    pending = pending ?? started;
    return;
  }
  inFlight = true;
  fitControls();
  const scene = sceneOf($('scene').value);
  const request = buildRequest(controls(), scene);
  const twin = twinRequest(controls(), scene);
  setStatus('running…', 'running');
  try {
    const t0 = performance.now();
    // A twin with other overrides is a run of its own, asked for beside this one.
    const asked = twin ? fetch('/api/simulate', { method: 'POST', body: JSON.stringify(twin.request) }) : null;
    if (asked) asked.catch(() => {});  // read below; when this run's request fails first, its failure is the one said
    const response = await fetch('/api/simulate', { method: 'POST', body: JSON.stringify(request) });
    const t1 = performance.now();
    const text = await response.text();
    const t2 = performance.now();
    const body = JSON.parse(text);
    state.timing = { headers: t1 - t0, body: t2 - t1, parse: performance.now() - t2 };
    const twinResponse = asked && await asked;
    const twinBody = twinResponse && await twinResponse.json();
    if (!response.ok) {
      showFailure(body.error);
    } else if (twinResponse && !twinResponse.ok) {
      showFailure(`the twin (${twin.variant}): ${twinBody.error}`);
    } else {
      showError('');
      $('view').classList.remove('stale');
      if (twinBody) body.twin = { variant: twin.variant, ...twinBody, twin: null };
      state.data = body;
      state.request = request;
      state.twinRequest = twin && twin.request;
      drawAll();
      state.runs += 1;
      state.redrawMs = performance.now() - started;
      const s = body.summary;
      const stated = outcomeStatement(s);
      setStatus(`${s.outcome}${stated ? ` (${stated})` : ''}; run ${formatG(s.wall_s * 1000, 3)} ms, re-run and redraw ${Math.round(state.redrawMs)} ms`, 'ready');
      $('status').dataset.runs = state.runs;
      $('status').dataset.redrawMs = state.redrawMs.toFixed(1);
    }
  } catch (e) {
    showFailure(`the lab's server did not answer (${e.message}); is rocking serve still running?`);
    setStatus('no server', 'error');
  }
  inFlight = false;
  if (pending !== null) {
    const t = pending;
    pending = null;
    rerun(t);
  } else {
    state.busy = false;
  }
}

// --- traces -------------------------------------------------------------------

function column(run, name, factor = 1) {
  const c = run && run.history[name];
  return c ? c.map((v) => (v === null ? null : v * factor)) : null;
}

// The charts, as the server's schema entries of the runs' columns give them
// (chartsFrom): their titles, axes, series and display factors. The span
// shown when a trace is all zero, in its display unit:
const zeroSpan = 0.1;
const chartHeight = 250;
const seriesShades = ['#1f5fa8', '#6a9fd8', '#0b2f57', '#3d8bd9', '#7aa7d9'];

// A chart's series and data: each run's columns at the rows worth drawing
// in `columns` pixel columns (drawnRows), on one time axis.
function chartData(def, columns) {
  const runs = [['', state.data], [' (twin)', state.data.twin]].filter(([, r]) => r);
  const tables = [];
  const series = [{}];
  for (const [suffix, run] of runs) {
    const ys = [];
    def.series.forEach(({ name, symbol, factor, ground }, k) => {
      const y = column(run, name, factor);
      if (!y || (ground && suffix)) return;  // the twin shakes under the same ground
      ys.push(y);
      series.push({
        label: symbol + suffix,
        stroke: suffix ? colors.twin : seriesShades[k % seriesShades.length],
        dash: suffix ? [6, 4] : undefined,
        width: 1.3,
        spanGaps: true,
        value: (u, v) => (v === null ? '–' : formatG(v, 4)),
      });
    });
    if (ys.length === 0) continue;
    const rows = drawnRows(run.history.t, ys, columns);
    tables.push([rows.map((i) => run.history.t[i]), ...ys.map((y) => rows.map((i) => y[i]))]);
  }
  if (tables.length === 0) return null;
  return { data: tables.length === 1 ? tables[0] : uPlot.join(tables), series };
}

// A red line at the drawing's time on every trace.
const timeCursor = {
  hooks: {
    draw: (u) => {
      const x = Math.round(u.valToPos(Number($('time').value), 'x', true));
      const { ctx } = u;
      ctx.save();
      ctx.strokeStyle = '#d62728';
      ctx.lineWidth = 1.5;
      ctx.beginPath();
      ctx.moveTo(x, u.bbox.top);
      ctx.lineTo(x, u.bbox.top + u.bbox.height);
      ctx.stroke();
      ctx.restore();
    },
  },
};

// The traces. A run whose charts have the same series as those on screen
// (a slider's move) only gives them its data, drawn at their width;
// otherwise they are built anew (and measured in the page's grid).
function drawCharts(rebuild = false) {
  const host = $('charts');
  // A chart of the ground's quantities only, all zero: the ground stays still.
  const still = (def) => def.series.every((x) => x.ground && peakOf(state.data.history[x.name]) === 0);
  const columns = (width) => Math.round(width * (window.devicePixelRatio || 1));
  const defs = chartsFrom([state.data.columns, state.data.twin && state.data.twin.columns]);
  const build = (width) => defs.map((def) => ({ def, ...(chartData(def, columns(width)) || {}) })).filter((b) => b.data);
  let width = state.chartWidth || Math.max(240, host.clientWidth - 2);
  let built = build(width);
  const key = JSON.stringify(built.map((b) => [b.def.title, b.series.map((x) => x.label || '')]));
  const reuse = !rebuild && key === state.chartKey && state.charts.length === built.length;
  const divs = [];
  if (!reuse) {
    for (const c of state.charts) c.destroy();
    state.charts = [];
    host.replaceChildren(...built.map(({ def }) => {
      const div = document.createElement('div');
      div.dataset.chart = def.key;
      div.setAttribute('role', 'img');
      divs.push(div);
      return div;
    }));
    const measured = Math.max(240, (divs[0] ? divs[0].clientWidth : host.clientWidth) - 2);
    if (measured !== width) built = build(measured);
    width = measured;
  }
  state.chartKey = key;
  state.chartWidth = width;
  built.forEach(({ def, data, series }, k) => {
    const title = still(def) ? `${def.title}: none (the ground stays still)` : def.title;
    const peaks = series.slice(1).map((x, j) => `${x.label} peak ${formatG(peakOf(data[j + 1]), 3)}`);
    const label = `chart of ${title} [${def.y}] against time: ${peaks.join(', ')}`;
    if (reuse) {
      const chart = state.charts[k];
      chart.setData(data);
      chart.root.querySelector('.u-title').textContent = title;
      chart.root.parentElement.setAttribute('aria-label', label);
      return;
    }
    divs[k].setAttribute('aria-label', label);
    state.charts.push(new uPlot({
      title,
      width,
      height: chartHeight,
      cursor: { sync: { key: 'lab' }, drag: { x: true, y: false } },
      scales: { x: { time: false }, y: { range: (u, min, max) => axisRange(min, max, zeroSpan) } },
      axes: [{ label: 'time t [s]', size: 40 }, { label: def.y, size: 64, labelSize: 20 }],
      series,
      legend: { live: true },
      plugins: [timeCursor],
    }, data, divs[k]));
  });
}

// --- drawing ------------------------------------------------------------------

// Each node's elastic displacement at row i: the nodes sent (a tall tower
// sends 16 of them), linearly between them by height (zero at the base).
function nodeDisplacements(run, i) {
  const h = run.structure.heights;
  const known = [[0, 0]];
  for (let k = 1; k <= h.length; k += 1) {
    const c = run.history[`node${k}.u`];
    if (c) known.push([h[k - 1], c[i] ?? 0]);
  }
  let j = 0;
  return h.map((z) => {
    while (j + 1 < known.length - 1 && known[j + 1][0] < z) j += 1;
    const [z0, u0] = known[j];
    const [z1, u1] = known[Math.min(j + 1, known.length - 1)];
    return z1 > z0 ? u0 + ((u1 - u0) * (z - z0)) / (z1 - z0) : u1;
  });
}

function indexAt(t, times) {
  let lo = 0;
  let hi = times.length - 1;
  while (lo < hi) {
    const mid = (lo + hi + 1) >> 1;
    if (times[mid] <= t) lo = mid;
    else hi = mid - 1;
  }
  return lo;
}

// A rigid block's height: its nodes sit at the middles of equal slices.
function blockHeight(structure) {
  const h = structure.heights;
  return h[h.length - 1] + h[0];
}

// The polyline through points (drawing coordinates by X, Y), to be stroked.
function tracePath(ctx, points, X, Y) {
  points.forEach((pt, k) => (k === 0 ? ctx.moveTo(X(pt), Y(pt)) : ctx.lineTo(X(pt), Y(pt))));
}

// The devices, in orange: each a line from its anchor to its other end (a
// damper's stretch is the gap it spans).
function strokeDevices(ctx, devices, X, Y) {
  ctx.save();
  ctx.strokeStyle = '#e67e22';
  ctx.lineWidth = 2.5;
  for (const d of devices) {
    ctx.beginPath();
    ctx.moveTo(X(d.from), Y(d.from));
    ctx.lineTo(X(d.to), Y(d.to));
    ctx.stroke();
  }
  ctx.restore();
}

// The rotations of a structure with joints at row i: the base's theta, then jointK.theta, K = 1 ..
function jointThetas(run, i) {
  const out = [run.history.theta ? run.history.theta[i] ?? 0 : 0];
  for (let k = 1; k < run.structure.segments.length; k += 1) {
    const c = run.history[`joint${k}.theta`];
    out.push(c ? c[i] ?? 0 : 0);
  }
  return out;
}

// A structure with joints: each segment drawn turning about its joint's
// corner (chainPoints), its base as a thick line, its outline, its nodes and
// the tendons.
function drawChain(ctx, run, i, factors, X, Y, color) {
  const p = chainPoints(run.structure, jointThetas(run, i).map((v) => v * factors.theta));
  ctx.strokeStyle = color;
  ctx.fillStyle = color;
  for (const g of p.segments) {
    ctx.lineWidth = 3;
    ctx.beginPath();
    ctx.moveTo(X(g.left), Y(g.left));
    ctx.lineTo(X(g.right), Y(g.right));
    ctx.stroke();
    ctx.lineWidth = 2;
    ctx.beginPath();
    tracePath(ctx, [g.left, g.topLeft, g.topRight, g.right], X, Y);
    ctx.stroke();
  }
  strokeDevices(ctx, p.devices, X, Y);
  for (const g of p.segments)
    for (const pt of g.nodes) {
      ctx.beginPath();
      ctx.arc(X(pt), Y(pt), 3, 0, 2 * Math.PI);
      ctx.fill();
    }
  return p.segments[0].left;
}

// A structure on rocking columns: each column outlined from its bottom
// corners round its top (columnsPoints: turned about its pivot corner).
function strokeColumns(ctx, c, X, Y) {
  ctx.lineWidth = 2;
  for (const col of c.columns) {
    ctx.beginPath();
    tracePath(ctx, [col.left, col.topLeft, col.topRight, col.right, col.left], X, Y);
    ctx.stroke();
  }
}

function drawStructure(ctx, run, t, factors, origin, scale, color, label) {
  const i = indexAt(t, run.history.t);
  const X = (pt) => origin[0] + pt[0] * scale;
  const Y = (pt) => origin[1] - pt[1] * scale;
  ctx.strokeStyle = color;
  ctx.fillStyle = color;
  ctx.font = '13px DejaVu Sans, sans-serif';
  if ((run.structure.segments || []).length > 0) {
    const at = drawChain(ctx, run, i, factors, X, Y, color);
    ctx.fillText(label, X(at) - 10, origin[1] + 20);
    return;
  }
  // On rocking columns, the columns turn and the structure stands upright on
  // the cap beam, which is its base, moved with the beam; otherwise its base
  // is the foundation beam, turning by theta on the ground.
  const c = run.structure.columns
    ? columnsPoints(run.structure.columns, (columnsThetaOf(run)[i] ?? 0) * factors.theta, run.structure.devices)
    : null;
  const theta = c ? 0 : (run.history.theta ? run.history.theta[i] ?? 0 : 0) * factors.theta;
  const u = nodeDisplacements(run, i).map((v) => v * factors.u);
  const p = bodyPoints(run.structure, theta, u, blockHeight(run.structure));
  const lift = c ? [c.shift[0], c.top + c.shift[1]] : [0, 0];
  const BX = (pt) => X([pt[0] + lift[0], pt[1] + lift[1]]);
  const BY = (pt) => Y([pt[0] + lift[0], pt[1] + lift[1]]);
  if (c) strokeColumns(ctx, c, X, Y);
  ctx.lineWidth = 3;
  ctx.beginPath();
  if (c) tracePath(ctx, c.beam, X, Y);
  else tracePath(ctx, [p.left, p.right], BX, BY);
  ctx.stroke();
  ctx.lineWidth = run.structure.rigid ? 1.5 : 4;
  ctx.beginPath();
  tracePath(ctx, p.axis, BX, BY);
  ctx.stroke();
  if (run.structure.rigid) {  // the block's outline, as tall as twice its centre of mass
    ctx.lineWidth = 2;
    ctx.beginPath();
    tracePath(ctx, [p.left, p.topLeft, p.topRight, p.right], BX, BY);
    ctx.stroke();
  }
  // The devices stand at the columns' bases on columns (or join the ground to the beam), else at the structure's.
  if (c) {
    for (const col of c.columns) strokeDevices(ctx, col.devices, X, Y);
    strokeDevices(ctx, c.beamDevices, X, Y);
  } else {
    strokeDevices(ctx, p.devices, BX, BY);
  }
  for (const pt of p.axis.slice(1)) {
    ctx.beginPath();
    ctx.arc(BX(pt), BY(pt), 4, 0, 2 * Math.PI);
    ctx.fill();
  }
  ctx.fillText(label, X(c ? [0, 0] : p.axis[0]) - 40, origin[1] + 20);
}

// The size [m] a run's structure is drawn in: its height (its top node, a
// rigid block's a tenth more; on columns, their height and above it the
// structure, a rigid block as tall as drawn) and the width it is given (its
// base's four half-widths, or the cap beam's length, and room to rock).
function drawnSize(structure) {
  const top = structure.heights[structure.heights.length - 1] * (structure.rigid ? 1.1 : 1);
  const c = structure.columns;
  if (!c) return { height: top, width: 4 * structure.half_width + 0.6 * top };
  const height = 2 * c.half_height + Math.max(top, structure.rigid ? blockHeight(structure) : 0);
  return { height, width: c.spacing + 2 * c.half_width + 0.6 * height };
}

function drawFrame() {
  const run = state.data;
  if (!run) return;
  const canvas = $('drawing');
  const ctx = canvas.getContext('2d');
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  const t = Number($('time').value);
  const runs = [[run, colors.main, 'this run'], [run.twin, colors.twin, 'twin']].filter(([r]) => r);
  const size = drawnSize(run.structure);
  const scale = Math.min((canvas.height - 50) / (size.height * 1.15), canvas.width / (runs.length * size.width));
  // The ground, moving as it does (by the factor shown), hatched so that its motion shows.
  const ground = state.ground ? state.ground[indexAt(t, run.history.t)] * state.factors.ground * scale : 0;
  state.groundShift = ground;
  const y0 = canvas.height - 30;
  ctx.strokeStyle = '#999';
  ctx.lineWidth = 1;
  ctx.beginPath();
  ctx.moveTo(0, y0);
  ctx.lineTo(canvas.width, y0);
  const offset = ((ground % 16) + 16) % 16;
  for (let x = offset - 16; x < canvas.width; x += 16) {
    ctx.moveTo(x, y0);
    ctx.lineTo(x - 8, y0 + 8);
  }
  ctx.stroke();
  state.origins = runs.map((x, k) => [(canvas.width * (k + 0.5)) / runs.length + ground, y0]);
  runs.forEach(([r, color, label], k) => drawStructure(ctx, r, t, state.factors, state.origins[k], scale, color, label));
  // The scale bar: lengths in the drawing at their true size.
  const bar = scaleBar(scale, Math.min(120, canvas.width / 5));
  ctx.fillStyle = '#333';
  ctx.fillRect(10, 12, bar * scale, 4);
  ctx.font = '12px DejaVu Sans, sans-serif';
  ctx.fillText(`${formatG(bar, 3)} m`, 10, 30);
  state.scaleBar = { metres: bar, px: bar * scale, scale };
  $('time-value').textContent = `t = ${t.toFixed(2)} s`;
  for (const c of state.charts) c.redraw(false, false);
  drawLoops(t);
  drawEnergy(indexAt(t, run.history.t));
}

// The loops' two views: each device's force against its elongation, or the
// devices' moment about the pivot against the rocking angle (the flag of
// controlled rocking). Each axis is its quantity's words, symbol and display
// unit, at its display factor, as the server's schema entries give them (a
// device's symbol, "dampers F", without the device's name: the axis is every
// device's).
function loopView(run, which) {
  const axis = (c) => (c ? { label: `${c.words} ${c.symbol.replace(/^\S+ /, '')} [${c.display_unit}]`, factor: c.factor }
    : { label: '', factor: 1 });
  if (which === 'moment') {
    const x = axis(columnOf(run, 'theta'));
    const y = axis(columnOf(run, 'M_dev'));
    return { moment: true, title: `${y.label.split(' [')[0]} against ${x.label.split(' [')[0]}`, x: x.label, y: y.label, fx: x.factor, fy: y.factor };
  }
  const d = (run.structure.devices || [])[0];
  const x = axis(d && columnOf(run, `${d.name}.elongation`));
  const y = axis(d && columnOf(run, `${d.name}.force`));
  return { moment: false, title: 'devices: force against elongation', x: x.label, y: y.label, fx: x.factor, fy: y.factor };
}

// Axis ends for a label: the data's extremes, zero when it is round-off
// (four digits: 3920, not 3.92e+03).
function axisEnd(v, range) {
  return formatG(Math.abs(v) < 1e-9 * range ? 0 : v, Math.abs(v) >= 1000 && Math.abs(v) < 1e5 ? 4 : 3);
}

function drawLoops(t) {
  const canvas = $('loop');
  const ctx = canvas.getContext('2d');
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  const view = loopView(state.data, $('loop-view').value);
  // Each device in a shade of its run's colour (this run blue, the twin red, dashed).
  const shades = { main: ['#1f5fa8', '#7aa7d9', '#0b2f57', '#3d8bd9'], twin: ['#c0392b', '#e8948a', '#6e1a12', '#e05a47'] };
  const runs = [[state.data, 'main', []], [state.data.twin, 'twin', [6, 4]]].filter(([r]) => r);
  const loops = [];
  for (const [run, which, dash] of runs) {
    const suffix = which === 'twin' ? ' (twin)' : '';
    if (view.moment) {
      const e = run.history.theta;
      const f = run.history.M_dev;
      if (e && f) loops.push({ run, color: shades[which][0], dash, name: `all devices${suffix}`, e, f });
      continue;
    }
    run.structure.devices.forEach((d, k) => {
      const e = run.history[`${d.name}.elongation`];
      const f = run.history[`${d.name}.force`];
      const color = shades[which][k % shades[which].length];
      if (e && f) loops.push({ run, color, dash, name: d.name + suffix, e, f });
    });
  }
  ctx.font = '12px DejaVu Sans, sans-serif';
  ctx.fillStyle = '#333';
  if (loops.length === 0) {
    ctx.fillText('no devices: no loops', 20, 30);
    return;
  }
  // Each axis spans every loop's values and zero.
  const span = (key, factor) => {
    let lo = 0;
    let hi = 0;
    for (const l of loops)
      for (const v of l[key])
        if (v !== null) {
          lo = Math.min(lo, v * factor);
          hi = Math.max(hi, v * factor);
        }
    const pad = 0.05 * (hi - lo || 1);
    return [lo - pad, hi + pad];
  };
  const [e0, e1] = span('e', view.fx);
  const [f0, f1] = span('f', view.fy);
  const m = { l: 76, r: 10, t: 22, b: 34 };
  const w = canvas.width - m.l - m.r;
  const h = canvas.height - m.t - m.b;
  const X = (e) => m.l + ((e * view.fx - e0) / (e1 - e0)) * w;
  const Y = (f) => m.t + h - ((f * view.fy - f0) / (f1 - f0)) * h;
  ctx.strokeStyle = '#999';
  ctx.strokeRect(m.l, m.t, w, h);
  ctx.beginPath();
  ctx.moveTo(X(0), m.t);
  ctx.lineTo(X(0), m.t + h);
  ctx.moveTo(m.l, Y(0));
  ctx.lineTo(m.l + w, Y(0));
  ctx.strokeStyle = '#ddd';
  ctx.stroke();
  ctx.fillText(view.title, 6, 14);
  const de = (e1 - e0) / 22;
  const df = (f1 - f0) / 22;
  ctx.fillText(axisEnd(e0 + de, e1 - e0), m.l, m.t + h + 14);
  ctx.textAlign = 'right';
  ctx.fillText(axisEnd(e1 - de, e1 - e0), m.l + w, m.t + h + 14);
  const yLabels = [axisEnd(f1 - df, f1 - f0), axisEnd(f0 + df, f1 - f0)];
  ctx.fillText(yLabels[0], m.l - 3, m.t + 10);
  ctx.fillText(yLabels[1], m.l - 3, m.t + h);
  state.loopLabels = yLabels.map((text) => ({ text, left: m.l - 3 - ctx.measureText(text).width }));
  ctx.textAlign = 'left';
  ctx.fillText(view.x, m.l + w / 2 - 40, m.t + h + 28);
  ctx.save();  // the y axis's title, up its side
  ctx.translate(14, m.t + h / 2);
  ctx.rotate(-Math.PI / 2);
  ctx.textAlign = 'center';
  ctx.fillText(view.y, 0, 0);
  ctx.restore();
  loops.forEach((l, k) => {  // the legend, inside the frame's top left
    ctx.fillStyle = l.color;
    ctx.fillRect(m.l + 6, m.t + 6 + 14 * k, 10, 3);
    ctx.fillStyle = '#333';
    ctx.fillText(l.name, m.l + 20, m.t + 11 + 14 * k);
  });
  for (const l of loops) {
    ctx.strokeStyle = l.color;
    ctx.setLineDash(l.dash);
    ctx.lineWidth = 1.2;
    ctx.beginPath();
    let pen = false;
    l.e.forEach((e, k) => {
      if (e === null || l.f[k] === null) {
        pen = false;
        return;
      }
      if (pen) ctx.lineTo(X(e), Y(l.f[k]));
      else ctx.moveTo(X(e), Y(l.f[k]));
      pen = true;
    });
    ctx.stroke();
    ctx.setLineDash([]);
    const k = Math.min(indexAt(t, l.run.history.t), l.e.length - 1);
    if (l.e[k] !== null && l.f[k] !== null && l.run === state.data) {
      ctx.fillStyle = l.color;
      ctx.beginPath();
      ctx.arc(X(l.e[k]), Y(l.f[k]), 3.5, 0, 2 * Math.PI);
      ctx.fill();
    }
  }
}

// --- energy -------------------------------------------------------------------

// The run's energy budget at history row i, the drawing's (energyBars): a
// bar for each term, as long as its share of the most any term reaches in
// the run, so that the bars grow and shrink as the animation plays. The rows
// are made once per run; a frame sets their lengths and numbers.
function drawEnergy(i) {
  const e = energyBars(state.data, i);
  $('energy-box').hidden = !e;
  state.energyShown = e ? { index: i, J: e.bars.map((b) => b.J), residual: e.residual } : null;
  if (!e) return;
  const host = $('energy');
  if (host.children.length !== e.bars.length || state.energyRun !== state.data) {
    state.energyRun = state.data;
    host.replaceChildren(...e.bars.map(() => energyRow()));
  }
  const h = state.data.history;
  const most = Math.max(1e-300, ...e.bars.map((b) => peakOf(h[b.name])));
  e.bars.forEach((b, k) => {
    const [name, bar, value] = host.children[k].children;
    host.children[k].dataset.name = b.name;
    name.textContent = b.label;
    bar.dataset.kind = b.kind;
    bar.style.width = `${(100 * Math.abs(b.J)) / most}%`;
    value.textContent = `${formatG(b.J, 3)} J`;
  });
}

function energyRow() {
  const row = document.createElement('div');
  row.className = 'bar-row';
  const name = document.createElement('span');
  const bar = document.createElement('div');
  bar.className = 'bar';
  bar.setAttribute('aria-hidden', 'true');
  const value = document.createElement('span');
  value.className = 'value';
  row.append(name, bar, value);
  return row;
}

// --- summary ------------------------------------------------------------------

function drawSummary() {
  const run = state.data;
  const twin = run.twin;
  $('twin-head').textContent = twin ? `twin: ${twin.variant}` : 'twin';
  const rows = [];
  const cell = (text, attrs = {}) => {
    const td = document.createElement('td');
    td.textContent = text;
    Object.assign(td.dataset, attrs);
    return td;
  };
  const add = (label, unit, main, other, key) => {
    const tr = document.createElement('tr');
    const name = cell(label);
    name.title = peakTitle(key);
    tr.append(name, cell(unit), cell(main, { peak: key, run: 'main' }), cell(other, { peak: key, run: 'twin' }));
    rows.push(tr);
  };
  const s = run.summary;
  add('outcome', '', s.outcome, twin ? twin.summary.outcome : '', 'outcome');
  add('uplifts, impacts', '', `${s.counts.uplifts}, ${s.counts.impacts}`,
    twin ? `${twin.summary.counts.uplifts}, ${twin.summary.counts.impacts}` : '', 'counts');
  const names = Object.keys(s.peaks);
  for (const name of twin ? Object.keys(twin.summary.peaks) : []) if (!names.includes(name)) names.push(name);
  for (const name of names) {
    const v = s.peaks[name];
    const w = twin ? twin.summary.peaks[name] : undefined;
    add(name, run.structure.units[name] || (twin && twin.structure.units[name]) || '',
      v === undefined ? '–' : formatG(v, 4), w === undefined ? (twin ? '–' : '') : formatG(w, 4), name);
  }
  $('summary').tBodies[0].replaceChildren(...rows);
}

function drawAll() {
  const run = state.data;
  const all = [run, run.twin].filter(Boolean);
  const H = run.structure.heights[run.structure.heights.length - 1];
  // The rocking angle drawn: the base's, a structure with joints' each joint's, and the columns'.
  const peakTheta = Math.max(...all.map((r) => Math.max(peakOf(r.history.theta), peakOf(columnsThetaOf(r)),
    ...Object.keys(r.history).filter((n) => /^joint\d+\.theta$/.test(n)).map((n) => peakOf(r.history[n])))));
  const peakU = Math.max(...all.map((r) => peakOf(r.history[`node${r.structure.heights.length}.u`])));
  state.factors = exaggeration(peakTheta, peakU, H);
  state.ground = groundDrawn(run.history.t, run.history.x_g);
  state.factors.ground = exaggeration(0, peakOf(state.ground), H).u;  // its peak drawn as 4 % of the height
  $('factors').textContent = `drawn: rocking angle ×${state.factors.theta}, bending ×${state.factors.u}, ` +
    `ground motion ×${state.factors.ground}`;
  $('run-text').textContent = describeRun(run);
  showVerdict();
  const tEnd = run.history.t[run.history.t.length - 1];
  $('time').max = tEnd;
  $('time').step = 'any';  // frame steps land on the history's rows
  if (Number($('time').value) > tEnd) $('time').value = 0;
  let t = performance.now();
  drawCharts();
  state.timing.charts = performance.now() - t;
  t = performance.now();
  drawSummary();
  state.timing.summary = performance.now() - t;
  t = performance.now();
  drawFrame();
  state.timing.frame = performance.now() - t;
}

// --- a record of the user's own ----------------------------------------------------

async function uploadRecord() {
  const file = $('upload').files[0];
  if (!file) return;
  if (file.size > 3.5e6) {
    showError(`${file.name} is ${(file.size / 1e6).toFixed(1)} MB; the lab takes record files up to 3.5 MB: upload a shorter record`);
    return;
  }
  const response = await fetch('/api/upload', { method: 'POST', body: JSON.stringify({ name: file.name, text: await file.text() }) });
  const body = await response.json();
  if (!response.ok) {
    showError(`This record could not be read: ${forStudents(body.error)}.`);
    return;
  }
  $('record').append(new Option(`${body.name} (uploaded)`, body.id));
  $('record').value = body.id;
  rerun();
}

// --- IDA ----------------------------------------------------------------------

const idaScales = [0.5, 1, 1.5, 2, 2.5, 3, 3.5, 4, 4.5, 5];

async function runIda() {
  const scene = sceneOf($('scene').value);
  const r = buildRequest(controls(), scene);
  const twin = twinRequest(controls(), scene);
  if (!r.record) {
    showError('IDA: choose a record to scale (a pulse is scaled by its amplitude)');
    return;
  }
  const request = { scene: r.scene, record: r.record, set: r.set, scales: idaScales };
  if (r.compare) request.compare = r.compare;
  setStatus('IDA running…', 'running');
  state.idaBusy = true;
  try {
    // A twin with other overrides: its own ladder, its rows named by its overrides.
    const asks = [request, ...(twin ? [{ ...request, set: twin.request.set }] : [])];
    const answers = await Promise.all(asks.map((a) => fetch('/api/ida', { method: 'POST', body: JSON.stringify(a) })));
    const bodies = await Promise.all(answers.map((a) => a.json()));
    const failed = answers.findIndex((a) => !a.ok);
    const body = bodies[0];
    if (failed >= 0) {
      showError(`The IDA could not be made: ${forStudents(bodies[failed].error)}.`);
      setStatus('IDA failed', 'error');
    } else {
      if (twin) body.rows.push(...bodies[1].rows.map((row) => ({ ...row, variant: twin.variant })));
      showError('');
      state.ida = body;
      const keep = $('ida-quantity').value || 'theta_over_alpha';
      $('ida-quantity').replaceChildren(...body.columns.map((c) => new Option(c, c)));
      $('ida-quantity').value = body.columns.includes(keep) ? keep : body.columns[0];
      drawIda();
      setStatus(`IDA: ${body.rows.length} runs`, 'ready');
    }
  } catch (e) {
    showError(`the lab's server did not answer (${e.message})`);
  }
  state.idaBusy = false;
}

function drawIda() {
  const host = $('ida-chart');
  if (state.idaChart) state.idaChart.destroy();
  host.replaceChildren();
  const q = $('ida-quantity').value;
  const variants = [...new Set(state.ida.rows.map((r) => r.variant))];
  const data = [idaScales];
  const series = [{ label: 'scale' }];
  variants.forEach((v, k) => {
    const rows = state.ida.rows.filter((r) => r.variant === v);
    data.push(idaScales.map((s) => {
      const row = rows.find((r) => r.level === s);
      return row && row.outcome !== 'overturned' && row.peaks[q] !== null ? row.peaks[q] : null;
    }));
    series.push({
      label: k === 0 ? 'this structure' : `twin: ${v}`,
      stroke: k === 0 ? colors.main : colors.twin,
      dash: k === 0 ? undefined : [6, 4],
      width: 1.5,
      points: { show: true, size: 6 },
      value: (u, val) => (val === null ? '–' : formatG(val, 4)),
    });
  });
  state.idaChart = new uPlot({
    title: `${q} [${state.data ? state.data.structure.units[q] || '' : ''}] against the scale on the record (a gap: overturned)`,
    width: Math.max(300, host.clientWidth || 600),
    height: 220,
    scales: { x: { time: false } },
    axes: [{ label: 'scale factor' }, { size: 60 }],
    series,
  }, data, host);
}

// --- playing ------------------------------------------------------------------

let last = null;
function tick(now) {
  if (!state.playing) return;
  if (last !== null) {
    const tEnd = Number($('time').max);
    let t = Number($('time').value) + ((now - last) / 1000) * Number($('speed').value);
    if (t > tEnd) t = 0;
    $('time').value = t;
    drawFrame();
  }
  last = now;
  requestAnimationFrame(tick);
}

// One row of the history forward or back (`step` +1 or -1), paused.
function stepFrame(step) {
  if (!state.data) return;
  play(false);
  const times = state.data.history.t;
  const i = Math.min(times.length - 1, Math.max(0, indexAt(Number($('time').value) + 1e-9, times) + step));
  $('time').value = times[i];
  drawFrame();
}

function play(on) {
  state.playing = on;
  $('play').textContent = on ? '❚❚ pause' : '▶ play';
  last = null;
  if (on) requestAnimationFrame(tick);
}

// --- set-up -------------------------------------------------------------------

function applyLesson(n) {
  const lesson = lessons[n];
  const text = $('lesson-text');
  if (!lesson) {
    text.hidden = true;
    return;
  }
  const c = { record: '', scale: 1, compare: '', twinExtra: '', extra: '', ...lesson.controls };
  $('scene').value = c.scene;
  state.shownScene = null;  // the pulse sliders start at the scene's own pulse
  state.dampersWanted = true;
  $('record').value = c.record;
  $('scale').value = c.scale;
  $('dampers').checked = true;
  $('thickness').value = 1;
  $('prestress').value = 1;
  $('own-restitution').checked = true;
  fitControls();
  if (c.amplitude !== undefined) $('amplitude').value = c.amplitude;
  if (c.period !== undefined) $('period').value = c.period;
  $('compare').value = c.compare;
  $('twin-extra').value = c.twinExtra.split(' ').join('\n');
  $('loop-view').value = c.loops || 'force';
  $('extra').value = c.extra.split(' ').join('\n');
  if (c.restitution !== undefined) {
    $('own-restitution').checked = false;
    $('restitution').value = c.restitution;
  }
  fitControls();
  const h = document.createElement('h2');
  h.textContent = lesson.title;
  const p = document.createElement('p');
  p.textContent = lesson.text;
  text.replaceChildren(h, p, predictionBox(lesson));
  text.hidden = false;
}

// The lesson's question, asked before its run is looked at; a choice is
// answered by the run on screen (the lesson's, or the run the controls made since).
function predictionBox(lesson) {
  state.prediction = undefined;
  const box = document.createElement('div');
  box.id = 'predict';
  const q = document.createElement('p');
  const lead = document.createElement('strong');
  lead.textContent = 'Predict first: ';
  q.append(lead, lesson.predict.question);
  box.append(q);
  lesson.predict.choices.forEach((choice, k) => {
    const b = document.createElement('button');
    b.type = 'button';
    b.textContent = choice;
    b.dataset.choice = k;
    b.addEventListener('click', () => {
      state.prediction = k;
      showVerdict();
    });
    box.append(b);
  });
  const verdict = document.createElement('p');
  verdict.id = 'verdict';
  verdict.setAttribute('aria-live', 'polite');
  box.append(verdict);
  return box;
}

function showVerdict() {
  const lesson = lessons[Number($('lesson').value)];
  if (!lesson || !lesson.predict || state.prediction === undefined || !state.data || !$('verdict')) return;
  const right = lesson.predict.answer(state.data);
  const said = lesson.predict.choices[state.prediction];
  $('verdict').textContent = `You said: ${said}. The run says: ${lesson.predict.choices[right]}` +
    `${right === state.prediction ? ' (as you predicted)' : ''}: ${lesson.predict.because(state.data)}`;
}

// Every control back to where the lesson (or, in free play, the lab) starts it, and a run.
function reset() {
  play(false);
  $('time').value = 0;
  const k = $('lesson').value;
  if (k !== '') {
    applyLesson(Number(k));
  } else {
    const scene = $('scene').value;
    $('controls').reset();
    $('scene').value = scene;
    state.shownScene = null;
    state.dampersWanted = true;
    fitControls();
  }
  $('speed').value = '1';
  rerun();
}

async function start() {
  try {
    const [scenes, records] = await Promise.all([fetch('/api/scenes').then((r) => r.json()),
      fetch('/api/records').then((r) => r.json())]);
    state.scenes = scenes.filter((s) => s.usable);
    state.records = records.filter((r) => !r.error);
  } catch (e) {
    showError(`the lab's server did not answer (${e.message})`);
    setStatus('no server', 'error');
    return;
  }
  $('scene').replaceChildren(...state.scenes.map((s) => new Option(s.name === s.id ? s.id : `${s.name} (${s.id})`, s.id)));
  $('scene').value = 'christchurch_chimney';
  $('record').replaceChildren(new Option("the scene's own", ''), ...pulses.map((p) => new Option(p.label, p.value)),
    ...state.records.map((r) => new Option(r.name, r.id)));
  lessons.forEach((l, k) => $('lesson').append(new Option(l.title, String(k))));
  const n = new URLSearchParams(location.search).get('lesson');
  if (n !== null && lessons[Number(n)]) {
    $('lesson').value = n;
    applyLesson(Number(n));
  }
  fitControls();
  // Sliders, boxes and lists re-run as they move; the overrides once typed (on leaving the field).
  $('controls').addEventListener('input', (e) => {
    if (e.target.tagName !== 'TEXTAREA' && e.target.type !== 'file') rerun();
  });
  // Moving the restitution slider replaces the scene's own restitution; the box says which is used.
  $('restitution').addEventListener('input', () => { $('own-restitution').checked = false; });
  $('dampers').addEventListener('input', () => { state.dampersWanted = $('dampers').checked; });
  $('reset').addEventListener('click', () => reset());
  $('step').addEventListener('click', () => stepFrame(1));
  $('step-back').addEventListener('click', () => stepFrame(-1));
  $('upload').addEventListener('change', () => uploadRecord());
  $('extra').addEventListener('change', () => rerun());
  $('twin-extra').addEventListener('change', () => rerun());
  $('controls').addEventListener('submit', (e) => e.preventDefault());
  $('lesson').addEventListener('change', () => {
    const k = $('lesson').value;
    history.replaceState(null, '', k === '' ? location.pathname : `?lesson=${k}`);
    if (k !== '') applyLesson(Number(k));
    else $('lesson-text').hidden = true;
    rerun();
  });
  $('time').addEventListener('input', () => drawFrame());
  $('ida').addEventListener('click', () => runIda());
  $('loop-view').addEventListener('change', () => state.data && drawLoops(Number($('time').value)));
  $('ida-quantity').addEventListener('change', () => state.ida && drawIda());
  $('play').addEventListener('click', () => play(!state.playing));
  window.addEventListener('resize', () => state.data && drawCharts(true));
  await rerun();
}

start();
