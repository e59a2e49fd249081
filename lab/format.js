// The lab's pure parts, shared by the page (lab.js) and its unit tests
// (tests/unit.test.mjs): number formatting as the command line prints it, the
// request the controls make, the drawing's exaggeration and geometry.

// A number as fmt's {:.Pg} (C's %g) prints it: P significant digits, trailing
// zeros dropped, exponent form below 1e-4 or from 10^P on.
export function formatG(v, p = 4) {
  if (v === null || v === undefined || Number.isNaN(v)) return 'n/a';
  if (!Number.isFinite(v)) return v > 0 ? 'inf' : '-inf';
  if (v === 0) return '0';
  const strip = (s) => (s.includes('.') ? s.replace(/0+$/, '').replace(/\.$/, '') : s);
  const rounded = Number(v.toPrecision(p));
  const e = Math.floor(Math.log10(Math.abs(rounded)));
  if (e < -4 || e >= p) {
    const [m, x] = v.toExponential(p - 1).split('e');
    const n = Number(x);
    return `${strip(m)}e${n < 0 ? '-' : '+'}${String(Math.abs(n)).padStart(2, '0')}`;
  }
  return strip(v.toFixed(Math.max(0, p - 1 - e)));
}

// The devices that dissipate energy (their law's trait, from /api/scenes):
// the dampers the "dampers" box switches off, the [damper] pair among them.
export function damperDevices(scene) {
  return (scene.devices || []).filter((d) => d.dissipates);
}

// The first device with a prestress (a tendon), or null.
export function tendonOf(scene) {
  return (scene.devices || []).find((d) => d.prestress && d.prestress.value > 0) || null;
}

// Texts of an "extra overrides" field: one per line or separated by spaces.
export function splitOverrides(text) {
  return (text || '').split(/\s+/).filter((s) => s.length > 0);
}

// The excitation list's pulses: its values "pulse:SHAPE" (the scene's
// [excitation] made a pulse of that shape, amplitude and period).
export const pulses = [{ value: 'pulse:one-sine', label: 'one-sine pulse' }, { value: 'pulse:ricker', label: 'Ricker pulse' }];

// The request the controls make (POST /api/simulate), in the --set texts of
// the command line. `controls`: {scene, record (a record's id, a pulse's
// value or '' for the scene's own excitation), amplitude [g] and period [s]
// (of a pulse), scale, dampers, thickness, prestress (a factor on the
// tendon's own P0), restitution (null: the scene's), compare, extra};
// `scene`: the scene's entry of /api/scenes.
export function buildRequest(controls, scene) {
  const set = [];
  const pulse = (controls.record || '').startsWith('pulse:') ? controls.record.slice(6) : null;
  if (pulse)
    set.push('excitation.kind=pulse', `excitation.pulse=${pulse}`, `excitation.amplitude_g=${controls.amplitude}`,
      `excitation.period=${controls.period}`);
  else if (ownPulse(controls, scene)) {  // the scene's own pulse, as the pulse sliders set it
    if (controls.amplitude !== scene.pulse.amplitude_g) set.push(`excitation.amplitude_g=${controls.amplitude}`);
    if (controls.period !== scene.pulse.period) set.push(`excitation.period=${controls.period}`);
  }
  if (!controls.dampers) {
    for (const d of damperDevices(scene)) set.push(d.remove);
  } else if (scene.damper && controls.thickness !== 1) {
    set.push(`damper.thickness=${controls.thickness}`);
  }
  const tendon = tendonOf(scene);
  if (tendon && controls.prestress !== 1)
    set.push(`${tendon.prestress.set}=${tendon.prestress.value * controls.prestress}`);
  if (controls.restitution !== null && controls.restitution !== undefined)
    set.push(`contact.restitution=${controls.restitution}`);
  set.push(...splitOverrides(controls.extra));
  const request = { scene: controls.scene, scale: controls.scale, set };
  if (controls.record && !pulse) request.record = controls.record;
  if (controls.compare && controls.compare !== otherOverrides) request.compare = controls.compare;
  return request;
}

// The twin choice that is not one of the server's variants: the same run
// with overrides of the user's own after the controls' (`twinExtra`), made by
// the page as a second request.
export const otherOverrides = 'overrides';

// The twins a scene can be compared with: rocking.study's variants the server
// runs beside it, and the same run with other overrides.
export function twinChoices(scene) {
  const out = [{ value: '', label: 'none' }];
  if (scene.fixed_base) out.push({ value: 'fixed-base', label: 'fixed base' });
  for (const d of scene.devices || []) out.push({ value: `without:${d.name}`, label: `without ${d.name}` });
  if ((scene.devices || []).length > 1) out.push({ value: 'no-devices', label: 'no devices' });
  out.push({ value: otherOverrides, label: 'the same with other overrides' });
  return out;
}

// The twin with other overrides: {request (the controls' run with the twin's
// overrides after its own, and no server twin), variant (its name: the
// overrides)}; null when the twin chosen is none or a server variant.
export function twinRequest(controls, scene) {
  if (controls.compare !== otherOverrides) return null;
  const own = splitOverrides(controls.twinExtra);
  const request = buildRequest(controls, scene);
  return { request: { ...request, set: [...request.set, ...own] }, variant: own.length ? `with ${own.join(' ')}` : 'the same' };
}

// Largest |value| of a column (nulls skipped), 0 for none.
export function peakOf(values) {
  let m = 0;
  for (const v of values || []) if (v !== null && Math.abs(v) > m) m = Math.abs(v);
  return m;
}

// Factors the drawing multiplies the rocking angle and the bending by, so
// that both show (as `rocking animate` does): the peak rotation drawn as
// about 0.12 rad and the peak elastic top displacement as 4 % of the height,
// never less than their true size.
export function exaggeration(peakTheta, peakU, height) {
  const nice = (x) => {
    if (!(x > 1)) return 1;
    const p = 10 ** Math.floor(Math.log10(x));
    const m = x / p;
    return (m >= 5 ? 5 : m >= 2 ? 2 : 1) * p;
  };
  return {
    theta: peakTheta > 0 ? nice(0.12 / peakTheta) : 1,
    u: peakU > 0 && height > 0 ? nice((0.04 * height) / peakU) : 1,
  };
}

// Where the body's points are in the ground's frame [m]: the body rotates by
// theta about the pivot on its side (x = sign(theta) B), the elastic
// displacements u act along its own x axis (MODEL.md 2; rocking.drawing).
// Returns the axis (base centre, then each node), the two base corners, the
// two corners at height `top` (a block's outline; 0 when not given), and each
// device as a segment from its anchor on the ground (x, 0) to its end on the
// body: the base at x (a chord device, a damper across the gap) or the
// height of its free length (a vertical one, a tendon up the structure).
export function bodyPoints(structure, theta, u, top = 0) {
  const B = structure.half_width;
  const s = theta > 0 ? 1 : theta < 0 ? -1 : 0;
  const c = Math.cos(theta);
  const sn = Math.sin(theta);
  const place = (x, y) => {
    const px = x - s * B;
    return [s * B + px * c + y * sn, -px * sn + y * c];
  };
  const axis = [place(0, 0)];
  structure.heights.forEach((h, k) => axis.push(place(u ? u[k] : 0, h)));
  const devices = (structure.devices || []).map((d) => ({
    name: d.name,
    from: [d.x, 0],
    to: place(d.x, d.vertical ? d.free_length : 0),
  }));
  return { axis, left: place(-B, 0), right: place(B, 0), topLeft: place(-B, top), topRight: place(B, top), devices };
}

// A structure on rocking columns (MODEL.md 16; the server's structure.columns:
// count, half_width b, half_height h, spacing between the outer axes) drawn at
// the columns' rocking angle theta: each column a block 2h tall (bodyPoints)
// on its axis, the axes evenly spread over the spacing about x = 0, turned by
// theta about its bottom corner on the side of theta's sign; the cap beam on
// the top corners opposite the pivots, moved without turning by
//   shift = (2R s (sin alpha - sin(alpha - s theta)), 2R (cos(alpha - s theta) - cos alpha)),
// R = sqrt(b^2 + h^2), alpha = atan(b / h), s = sign(theta). Returns each
// column's corners (left, right at the ground; topLeft, topRight) and the
// devices at its base (each standing at every column alike, MODEL.md 16: x
// from the column's axis, from its ground anchor to its end on the column,
// as bodyPoints places a rocking body's), the beam's
// two ends over the outer columns' outer faces, the shift, and the height of
// the column tops at rest (2h), where the structure's base stands.
export function columnsPoints(columns, theta, devices = []) {
  const { count, half_width: b, half_height: h, spacing } = columns;
  const R = Math.hypot(b, h);
  const alpha = Math.atan2(b, h);
  const s = theta > 0 ? 1 : theta < 0 ? -1 : 0;
  const shift = [2 * R * s * (Math.sin(alpha) - Math.sin(alpha - s * theta)), 2 * R * (Math.cos(alpha - s * theta) - Math.cos(alpha))];
  const axes = Array.from({ length: count }, (_, k) => (count === 1 ? 0 : -spacing / 2 + (spacing * k) / (count - 1)));
  // One column as a rigid block with the devices at its base (x from its axis), then each column moved to its axis;
  // a device between the ground and the cap beam (beam) from its ground anchor to its point on the moved beam.
  const block = bodyPoints({ half_width: b, heights: [h], devices: devices.filter((d) => !d.beam) }, theta, null, 2 * h);
  const at = (x) => (pt) => [pt[0] + x, pt[1]];
  const list = axes.map((x) => {
    const move = at(x);
    return {
      axis: x, left: move(block.left), right: move(block.right), topLeft: move(block.topLeft), topRight: move(block.topRight),
      devices: block.devices.map((d) => ({ name: d.name, from: move(d.from), to: move(d.to) })),
    };
  });
  const top = 2 * h;
  const beam = [[axes[0] - b + shift[0], top + shift[1]], [axes[count - 1] + b + shift[0], top + shift[1]]];
  const beamDevices = devices.filter((d) => d.beam)
    .map((d) => ({ name: d.name, from: [d.x, d.ground_y || 0], to: [d.beam_x + shift[0], top + shift[1]] }));
  return { columns: list, beam, shift, top, beamDevices };
}

// The columns' rocking angle through a run (MODEL.md 16), row by row: its
// history's columns.theta, or, where it sends only the angle over the
// columns' slenderness, columns.theta_over_alpha times alpha = atan(b / h);
// null for a structure not on columns.
export function columnsThetaOf(run) {
  const h = run && run.history;
  const c = run && run.structure && run.structure.columns;
  if (!h || !c) return null;
  if (h['columns.theta']) return h['columns.theta'];
  const ratio = h['columns.theta_over_alpha'];
  if (!ratio) return null;
  const alpha = Math.atan2(c.half_width, c.half_height);
  return ratio.map((v) => (v === null ? null : v * alpha));
}

// Whether the run is shaken by the scene's own pulse (no record chosen, and no
// override that stills the ground): the pulse sliders then act on it.
export function ownPulse(controls, scene) {
  return !controls.record && Boolean(scene && scene.pulse) && controls.amplitude !== undefined && !groundStill(controls.extra);
}

// Whether the overrides keep the ground still (excitation.kind=none).
export function groundStill(extra) {
  return splitOverrides(extra).includes('excitation.kind=none');
}

// A server's error in words a student acts on: the command line's flags
// ("--set", "--vertical") and folders of the machine left out.
export function forStudents(message) {
  let m = String(message || 'the run failed');
  m = m.replace(/--set\s+device-=([\w.-]+)/g, "removing the device '$1'");
  m = m.replace(/--set\s+/g, 'the override ');
  m = m.replace(/\(?--[a-z][a-z-]*(\s+[^\s),;]+)?\)?/g, '');
  m = m.replace(/(^|[\s'"(])\/(?:[^\s/'"]+\/)+/g, '$1');  // /abs/folder/file.toml -> file.toml
  return m.replace(/\s{2,}/g, ' ').replace(/\s+([:;,.)])/g, '$1').trim();
}

// An axis range that shows the data: its extremes padded by 5 %, never a
// span of zero (an all-zero trace gets -1..1 of `unit`, not uPlot's 0..100).
export function axisRange(min, max, unit = 0.1) {
  if (min === null || max === null || !Number.isFinite(min) || !Number.isFinite(max)) return [-unit, unit];
  const span = max - min;
  const size = Math.max(Math.abs(min), Math.abs(max));
  if (span <= 1e-9 * size || size === 0) return size === 0 ? [-unit, unit] : [min - 0.1 * size, max + 0.1 * size];
  return [min - 0.05 * span, max + 0.05 * span];
}

// The run in a sentence or two, for those who cannot see the plots: the
// outcome, the counts of uplifts and impacts, and the peaks (the twin's
// beside); a structure on rocking columns, how they move.
export function describeRun(data) {
  const one = (run, who) => {
    const s = run.summary;
    const peak = (name, label, unit) => (s.peaks[name] === undefined ? null : `${label} ${formatG(s.peaks[name], 3)}${unit}`);
    const peaks = [peak('theta_over_alpha', 'peak rocking angle θ/α_cg', ''),
      peak('columns.theta_over_alpha', 'the columns\' peak rocking angle θ_c/α_c', ''), peak('base_moment', 'peak base moment', ' M_ref'),
      peak('delta_t', 'peak top drift', ''), peak('a_g', 'peak ground acceleration', ' m/s²')].filter(Boolean);
    const c = run.structure && run.structure.columns;
    const beam = s.peaks['beam.x'] === undefined ? '' : ` (at most ${formatG(s.peaks['beam.x'], 3)} m)`;
    const columns = c ? ` It stands on ${c.count} rocking column${c.count === 1 ? '' : 's'}, ${formatG(2 * c.half_height, 3)} m tall: ` +
      `they tilt together about their bottom corners, and the cap beam on their tops moves sideways${beam} without tilting, ` +
      'the structure upright on it.' : '';
    const counted = (k, word) => `${k} ${word}${k === 1 ? '' : 's'}`;
    const stated = outcomeStatement(s);
    return `${who}: ${s.outcome}${stated ? ` (${stated})` : ''}, ${counted(s.counts.uplifts, 'uplift')} and ${counted(s.counts.impacts, 'impact')}` +
      (peaks.length ? `; ${peaks.join(', ')}` : '') + `.${columns}`;
  };
  let text = one(data, 'This run');
  if (data.twin) text += ` ${one(data.twin, `Its twin (${data.twin.variant})`)}`;
  return text;
}

// The sentence a run that ended short of its duration states (summary.json's
// separation, sliding or undecided: where and why), or '' for a run that
// completed or overturned, which its outcome says in full.
export function outcomeStatement(summary) {
  return summary.separation || summary.sliding || summary.undecided || '';
}

// What each peak of the summary means, in words (the table's tooltips; the
// page's glossary says the same of the symbols).
export const peakWords = {
  theta: 'θ: the rocking angle, how far the body tilts on a corner of its base',
  theta_over_alpha: 'θ/α_cg: the rocking angle as a share of the tipping angle (1: tips over from rest)',
  theta_dot: 'the rocking speed',
  delta_t: 'total top drift: how far the top moves sideways, as a share of the height (tilt and bending)',
  delta_e: 'elastic top drift: the bending alone, as a share of the height',
  u_N: 'the top\'s elastic displacement (bending)',
  a_N: 'the top\'s acceleration',
  base_shear: 'the sideways force at the base, in multiples of V_ref (the weight times B/H)',
  base_moment: 'the moment at the base, in multiples of M_ref (the weight times half the base width)',
  mid_shear: 'the sideways force at mid-height, in multiples of V_ref',
  mid_moment: 'the moment at mid-height, in multiples of M_ref',
  damper_d: 'the dampers\' stretch',
  damper_F: 'the dampers\' force',
  M_dev: 'the devices\' moment about the corner the body rocks on',
  'columns.theta': 'θ_c: the columns\' rocking angle, how far the columns carrying the structure tilt on their bottom corners',
  'columns.theta_over_alpha': 'θ_c/α_c: the columns\' rocking angle as a share of their slenderness (1: they tip over from rest)',
  'columns.theta_dot': 'the columns\' rocking speed',
  'beam.x': 'how far the cap beam on the columns\' tops moves sideways (it does not tilt)',
  a_g: 'the ground\'s horizontal acceleration',
  a_v: 'the ground\'s vertical acceleration',
  outcome: 'what the run ended in: completed (rocked or not, and stayed up), overturned, or, for a structure with joints, ' +
    'separated (a part would leave its joint), sliding (a joint would slide past its friction limit) or undecided ' +
    '(an impact the model cannot settle): the model stops there and says where',
  counts: 'uplifts: a corner of the base leaving the ground; impacts: the base landing again',
};

// A peak's tooltip: its words, or for a device's column ("dampers.force") the device and the quantity.
export function peakTitle(name) {
  if (peakWords[name]) return peakWords[name];
  const dot = name.indexOf('.');
  return dot > 0 ? `the device '${name.slice(0, dot)}': its ${name.slice(dot + 1).replace(/_/g, ' ')}` : name;
}

// The ground's displacement as drawn: x_g (the acceleration integrated from
// rest, no baseline correction) less its least-squares straight line, so that
// a record's drift does not carry the drawing off the canvas.
export function groundDrawn(t, x) {
  if (!t || !x || x.length < 2) return null;
  let st = 0, sx = 0, stt = 0, stx = 0, n = 0;
  x.forEach((v, i) => {
    if (v === null) return;
    n += 1; st += t[i]; sx += v; stt += t[i] * t[i]; stx += t[i] * v;
  });
  const d = n * stt - st * st;
  const b = d > 0 ? (n * stx - st * sx) / d : 0;
  const a = n > 0 ? (sx - b * st) / n : 0;
  return x.map((v, i) => (v === null ? 0 : v - a - b * t[i]));
}

// A scale bar's length [m]: 1, 2 or 5 times a power of ten, drawn about `px` pixels long at `scale` px/m.
export function scaleBar(scale, px = 100) {
  const target = px / scale;
  const p = 10 ** Math.floor(Math.log10(target));
  const m = target / p;
  return (m >= 5 ? 5 : m >= 2 ? 2 : 1) * p;
}

// The rows of a history worth drawing in `buckets` pixel columns: in each
// column's span of time, the rows of each column's least and greatest value
// (nulls skipped), and the first and last rows. A line through them covers,
// in every pixel column, what a line through all the rows covers there. All
// rows when there are few (under four per column). Returns ascending indices.
export function drawnRows(t, columns, buckets) {
  const n = t.length;
  if (n <= 4 * buckets || buckets < 1) return Array.from({ length: n }, (_, i) => i);
  const t0 = t[0];
  const span = t[n - 1] - t0;
  const keep = new Uint8Array(n);
  keep[0] = 1;
  keep[n - 1] = 1;
  for (const y of columns) {
    let bucket = -1;
    let lo = -1;
    let hi = -1;
    for (let i = 0; i <= n; i += 1) {
      const b = i < n ? Math.min(buckets - 1, Math.floor(((t[i] - t0) / span) * buckets)) : buckets;
      if (b !== bucket) {
        if (lo >= 0) { keep[lo] = 1; keep[hi] = 1; }
        bucket = b;
        lo = -1;
        hi = -1;
      }
      if (i === n) break;
      const v = y[i];
      if (v === null || v === undefined) continue;
      if (lo < 0 || v < y[lo]) lo = i;
      if (hi < 0 || v > y[hi]) hi = i;
    }
  }
  const out = [];
  for (let i = 0; i < n; i += 1) if (keep[i]) out.push(i);
  return out;
}

// The run's energy budget at row i of its history, as bars: the terms of
// the energy balance E(t) - E(0) = W_ground - W_viscous - W_devices -
// W_impacts (MODEL.md 7 and 11), columns the server sends by their schema
// names, each W from the start: what was put in (the energy at the start, the
// ground's work), where it went (each device, the impacts, viscous damping)
// and what is there now; each labelled by the schema's words. At the run's
// last row (its end) they are summary.energy_J's totals. null when the run
// does not track energy. {name, label, kind, J}; residual: the balance's
// residual at row i.
export function energyBars(run, i) {
  const h = run && run.history;
  const names = ['E', 'W_ground', 'W_devices', 'W_impacts', 'W_viscous'];
  if (!h || names.some((n) => !h[n] || h[n].length === 0)) return null;
  const words = (n) => ((run.columns || []).find((c) => c.name === n) || { words: n }).words;
  const at = (n, k) => h[n][Math.max(0, Math.min(k, h[n].length - 1))] ?? 0;
  // The devices' work: one bar per device when the history has each one's
  // (NAME.work), else their total.
  const works = ((run.structure && run.structure.devices) || []).map((d) => `${d.name}.work`);
  const each = works.length > 0 && works.every((n) => h[n] && h[n].length > 0);
  const devices = (each ? works : ['W_devices']).map((n) => ({ name: n, label: words(n), kind: 'out', J: at(n, i) }));
  const bars = [
    { name: 'E', label: `${words('E')} at the start`, kind: 'in', J: at('E', 0) },
    { name: 'W_ground', label: words('W_ground'), kind: 'in', J: at('W_ground', i) },
    ...devices,
    { name: 'W_impacts', label: words('W_impacts'), kind: 'out', J: at('W_impacts', i) },
    { name: 'W_viscous', label: words('W_viscous'), kind: 'out', J: at('W_viscous', i) },
    { name: 'E', label: `${words('E')} now`, kind: 'left', J: at('E', i) },
  ];
  const out = bars.filter((b) => b.kind === 'out').reduce((sum, b) => sum + b.J, 0);
  return { bars, residual: (at('E', i) - at('E', 0)) - (at('W_ground', i) - out) };
}

// The charts against time, from the columns' schema entries the server sent
// with each run (name, words, symbol, display unit and factor, use, chart):
// one chart per chart number, in their order, with the columns of that number
// (the main run's first, then any only the twin has). Each: {key (its first
// column's name), title (its first column's words), y (the axis's title:
// the symbols and the display unit), series: [{name, symbol, factor, ground}]}.
export function chartsFrom(columnLists) {
  const byChart = new Map();
  for (const columns of columnLists)
    for (const c of columns || []) {
      if (c.use !== 'chart') continue;
      if (!byChart.has(c.chart)) byChart.set(c.chart, []);
      const list = byChart.get(c.chart);
      if (!list.some((x) => x.name === c.name)) list.push(c);
    }
  return [...byChart.keys()].sort((a, b) => a - b).map((k) => {
    const cols = byChart.get(k);
    const units = [...new Set(cols.map((c) => c.display_unit))];
    return {
      key: cols[0].name,
      title: cols[0].words,
      y: `${cols.map((c) => c.symbol).join(', ')} [${units.join(', ') || '–'}]`,
      series: cols.map((c) => ({ name: c.name, symbol: c.symbol, factor: c.factor, ground: Boolean(c.ground) })),
    };
  });
}

// A column's schema entry (the server's) of a run, or null.
export function columnOf(run, name) {
  return ((run && run.columns) || []).find((c) => c.name === name) || null;
}

// A rigid segment's (or block's) top: its nodes' heights above its base,
// when they are the middles of equal slices, end half a slice above the
// last; otherwise the last node is its top face.
export function segmentTop(base, heights) {
  const n = heights.length;
  const first = heights[0] - base;
  const last = heights[n - 1] - base;
  return Math.abs(last - (2 * n - 1) * first) <= 1e-9 * Math.max(1, last) ? heights[n - 1] + first : heights[n - 1];
}

// A structure with joints (MODEL.md 15) drawn: segment j turns by thetas[j]
// (its rotation relative to the face below; j = 0: the base's theta) about
// the corner of its joint on the side of its sign, the face being segment
// j-1's at the joint's height; a point (x, z) of segment j (z its height at
// rest) is then placed through every segment below. Returns per segment its
// place function, base corners, top corners and angle (the sum of the
// rotations up to it), and each device (a tendon, or a device across a
// joint above the base) from its anchor on the ground (x, 0), or on its
// from_segment at height bottom, to its end on its segment at height top.
export function chainPoints(structure, thetas) {
  const segments = structure.segments;
  const places = [];
  const out = segments.map((g, j) => {
    const th = thetas[j] || 0;
    const s = th > 0 ? 1 : th < 0 ? -1 : 0;
    const c = Math.cos(th);
    const sn = Math.sin(th);
    const B = g.half_width;
    const h = g.base_height;
    const below = j > 0 ? places[j - 1] : (x, z) => [x, z];
    const place = (x, z) => {
      const px = x - s * B;
      const zl = z - h;
      return below(s * B + px * c + zl * sn, h - px * sn + zl * c);
    };
    places.push(place);
    const top = j + 1 < segments.length ? segments[j + 1].base_height : segmentTop(h, g.heights);
    return {
      place,
      angle: thetas.slice(0, j + 1).reduce((a, b) => a + (b || 0), 0),
      left: place(-B, h), right: place(B, h), topLeft: place(-B, top), topRight: place(B, top),
      nodes: g.heights.map((z) => place(0, z)),
    };
  });
  const devices = (structure.devices || []).map((d) => ({
    name: d.name,
    from: d.from_segment !== undefined && out[d.from_segment] ? out[d.from_segment].place(d.x, d.bottom) : [d.x, 0],
    to: d.segment !== undefined && out[d.segment] ? out[d.segment].place(d.x, d.top) : [d.x, 0],
  }));
  return { segments: out, devices };
}
