// The lessons of docs/teaching.md as guided pages of the lab: each sets the
// controls (scene, record, the pulse's amplitude and period, scale, twin and
// the twin's overrides, overrides) and says what to look for. Opened as
// index.html?lesson=N. Controls not named keep their defaults.
// Each asks a prediction first (`predict`): a question, its choices, and the
// choice the lesson's run bears out (answer(data) -> index) with the numbers
// that show it (because(data)).

const peak = (run, name) => (run && run.summary.peaks[name] !== undefined ? run.summary.peaks[name] : 0);
const fmt = (v) => Number(v.toPrecision(3)).toString();

const elcentro = 'elcentro_1940_ns.at2';
const papanui = 'christchurch2011_pphs_s57e.at2';

export const lessons = [
  {
    title: '0. A rigid block, tilted and let go',
    predict: {
      question: 'Let go from a tilt, will the block swing for ever, or will each swing be shorter than the last?',
      choices: ['for ever, like a pendulum', 'each swing shorter'],
      answer: (d) => (d.summary.counts.impacts > 0 ? 1 : 0),
      because: (d) => `${d.summary.counts.impacts} impacts, each taking a share of the energy; the block comes to rest.`,
    },
    controls: { scene: 'rigid_block', record: '', scale: 1, extra: 'excitation.kind=none initial.theta=0.134' },
    text:
      'No earthquake: the block (0.4 m wide, 1.5 m tall) is tilted to half its slenderness and released. ' +
      'Watch the rocking angle: each impact takes a fixed share of the energy, and each swing is shorter than ' +
      'the last. Unlike a pendulum, a rocking block has no period of its own. Try the restitution slider: ' +
      'r = 1 would rock for ever.',
  },
  {
    title: '1. Rocking caps the base moment a fixed base would carry',
    predict: {
      question: 'Which base carries the larger moment: the rocking chimney\u2019s or the fixed-base twin\u2019s?',
      choices: ['the rocking one', 'the fixed base'],
      answer: (d) => (peak(d, 'base_moment') > peak(d.twin, 'base_moment') ? 0 : 1),
      because: (d) => `peak base moment: rocking ${fmt(peak(d, 'base_moment'))} M_ref, fixed base ${fmt(peak(d.twin, 'base_moment'))} M_ref.`,
    },
    controls: { scene: 'christchurch_chimney', record: elcentro, scale: 3, compare: 'fixed-base' },
    text:
      'The chimney under El Centro, three times as strong as recorded, beside the same chimney on a fixed base ' +
      '(dashed). Look at the base moment: on a fixed base it reaches about 11 M_ref; rocking, it stays near ' +
      '1.7 M_ref, because the base cannot carry more than the weight can hold down. Move the scale: the ' +
      'fixed-base moment grows with it, the rocking one hardly does.',
  },
  {
    title: '2. The price: larger total displacements',
    predict: {
      question: 'Whose top moves further sideways (total drift): the rocking chimney\u2019s or the fixed-base twin\u2019s?',
      choices: ['the rocking one', 'the fixed base'],
      answer: (d) => (peak(d, 'delta_t') > peak(d.twin, 'delta_t') ? 0 : 1),
      because: (d) => `peak total drift: rocking ${fmt(100 * peak(d, 'delta_t'))} %, fixed base ${fmt(100 * peak(d.twin, 'delta_t'))} % of the height.`,
    },
    controls: { scene: 'christchurch_chimney', record: elcentro, scale: 3, compare: 'fixed-base' },
    text:
      'The same pair. Look at the drift panel: the rocking chimney\u2019s top moves more (total drift) because ' +
      'the whole body tilts, even though it bends less (elastic drift). A rocking structure trades force for ' +
      'displacement: leave room around it, and keep it from tipping over.',
  },
  {
    title: '3. The damper controls rotation, and only for large motions',
    predict: {
      question: 'At the record\u2019s own strength (scale 1), do the dampers change the peak rocking angle by more than a fifth?',
      choices: ['yes, by more than a fifth', 'no, hardly'],
      answer: (d) => (Math.abs(peak(d, 'theta_over_alpha') - peak(d.twin, 'theta_over_alpha')) >
        0.2 * Math.max(peak(d, 'theta_over_alpha'), peak(d.twin, 'theta_over_alpha')) ? 0 : 1),
      because: (d) => `peak θ/α_cg: with dampers ${fmt(peak(d, 'theta_over_alpha'))}, without ${fmt(peak(d.twin, 'theta_over_alpha'))}.`,
    },
    controls: { scene: 'christchurch_chimney', record: papanui, scale: 1, compare: 'without:damper' },
    text:
      'The Papanui record of 22 February 2011, with and without the dampers (dashed). As recorded, the two ' +
      'rocking angles are nearly the same. Move the scale to 3: the damper cuts the rotation by about four, ' +
      'while the base moment hardly changes. Watch the damper loops grow: it dissipates energy, it does not ' +
      'stiffen the base. Try the thickness slider.',
  },
  {
    title: '4. A flexible rocking structure can excite its higher modes',
    predict: {
      question: 'At a quarter of its stiffness, does the rocking chimney bend less than the same chimney on a fixed base (elastic drift)?',
      choices: ['it bends less', 'it bends more'],
      answer: (d) => (peak(d, 'delta_e') < peak(d.twin, 'delta_e') ? 0 : 1),
      because: (d) => `peak elastic drift: rocking ${fmt(100 * peak(d, 'delta_e'))} %, fixed base ${fmt(100 * peak(d.twin, 'delta_e'))} %.`,
    },
    controls: {
      scene: 'christchurch_chimney', record: papanui, scale: 2, compare: 'fixed-base', extra: 'structure.EI_scale=0.25',
    },
    text:
      'The chimney at a quarter of its stiffness. Each impact is a sudden change of velocity that sets the ' +
      'structure\u2019s own modes ringing: watch the bending in the drawing right after an impact. Change ' +
      'EI_scale in the overrides (0.25, 0.5, 1, 2) and compare the elastic drift.',
  },
  {
    title: '5. Size matters: the larger block survives',
    predict: {
      question: 'Under a 1.2 g pulse of 0.5 s, does the small block (1.5 m tall) stay up?',
      choices: ['it stays up', 'it overturns'],
      answer: (d) => (d.summary.outcome === 'overturned' ? 1 : 0),
      because: (d) => (d.summary.outcome === 'overturned'
        ? `it overturned at t = ${fmt(d.summary.t_end)} s, after ${d.summary.counts.uplifts} uplifts.`
        : `it stayed up: peak θ/α_cg ${fmt(peak(d, 'theta_over_alpha'))} (1: the tipping point at rest).`) +
        ' Now make it four times larger, as the text says.',
    },
    controls: { scene: 'rigid_block', record: '', scale: 3, extra: 'excitation.period=0.5' },
    text:
      'The rigid block under a one-sine pulse three times its default strength (1.2 g, 0.5 s): it overturns. ' +
      'Now make the block four times larger, same shape: replace the overrides with ' +
      'structure.half_width=0.8 structure.heights=[0.5,1.5,2.5,3.5,4.5,5.5] excitation.period=0.5. ' +
      'The same pulse leaves it standing: Housner\u2019s size effect.',
  },
  {
    title: '6. Self-centring: a tendon re-centres, dampers dissipate',
    predict: {
      question: 'Does the tendon make the wall\u2019s peak rotation smaller, or larger?',
      choices: ['smaller', 'larger'],
      answer: (d) => (peak(d, 'theta') < peak(d.twin, 'theta') ? 0 : 1),
      because: (d) => `peak θ: with the tendon ${fmt(1000 * peak(d, 'theta'))} mrad, without it ${fmt(1000 * peak(d.twin, 'theta'))} mrad.`,
    },
    controls: { scene: 'controlled_rocking_wall', record: '', scale: 1, compare: 'without:tendon', loops: 'moment' },
    text:
      'A post-tensioned controlled-rocking wall under a 0.9 g pulse, beside the same wall without its tendon ' +
      '(dashed). The tendon more than halves the peak rotation and pulls the wall back to theta = 0. Move ' +
      'the prestress slider, switch the dampers off, and watch the devices\u2019 moment against the rotation: ' +
      'tendon and dampers together draw the flag shape of controlled rocking (the tendon alone a bilinear ' +
      'elastic line; switch the loops to each device\u2019s force to see them apart).',
  },
  {
    title: '7. A heavier deck makes the rocking frame more stable',
    predict: {
      question: 'Under the same pulse, which stays standing: the piers carrying their 500 t deck, or the same piers with almost no deck?',
      choices: ['the piers with the heavy deck', 'the piers with almost no deck', 'both', 'neither'],
      // Without the twin (compared with none) the piers with almost no deck are not run, and the answer is the deck's alone.
      answer: (d) => {
        const [deck, bare] = [d, d.twin].map((r) => Boolean(r) && r.summary.outcome !== 'overturned');
        return deck && bare ? 2 : deck ? 0 : bare ? 1 : 3;
      },
      because: (d) => [[d, 'with the deck'], [d.twin, 'with almost no deck']].map(([r, who]) => (!r
        ? `${who} the piers were not run (compare with \u201cthe same with other overrides\u201d)`
        : r.summary.outcome === 'overturned' ? `${who} the piers overturned at t = ${fmt(r.summary.t_end)} s`
          : `${who} they stood: peak θ_c/α_c ${fmt(peak(r, 'columns.theta_over_alpha'))}, ${r.summary.counts.impacts} impacts`)).join('; ') + '.',
    },
    controls: {
      scene: 'rocking_frame', record: '', amplitude: 0.5, period: 1, scale: 1, extra: 'excitation.duration=15',
      compare: 'overrides', twinExtra: 'structure.masses=[1.0] structure.base_mass=1.0',
    },
    text:
      'A bridge bent: a 500 t deck on a 120 t cap beam, carried by two free-standing piers 1.6 m wide and 9.6 m ' +
      'tall. The piers rock together about their bottom corners; the beam slides across their tops without ' +
      'tilting, and the deck rides on it upright. Beside it (dashed) the same piers with almost no deck (1 kg: ' +
      'the twin\u2019s overrides), under the same one-sine pulse of 0.5 g and 1 s. Intuition says a heavy mass on ' +
      'top topples the piers sooner. Watch the columns\u2019 rocking angle \u03b8_c/\u03b1_c (1: the piers tip over): ' +
      'with the deck it reaches about 0.53 and the frame settles; the bare piers overturn at about 2.6 s. The ' +
      'heavy deck makes the frame rock like a larger pier, and larger blocks survive (lesson 5). Move the ' +
      'amplitude, or change the deck\u2019s mass in the twin\u2019s overrides.',
  },
  {
    title: '8. A segmental pier rocks at the joint that needs the smallest push',
    predict: {
      question: 'The pier as built rocks at its footing. Stand it on a footing twice as wide (dashed): where will it rock then?',
      choices: ['still at its footing', 'at the joint above the first segment', 'higher up', 'nowhere'],
      // The joint of the twin that opened first: the footing (0), the first joint (1), one above (2), or none (3).
      answer: (d) => {
        const opened = firstOpened(d.twin);
        return opened === null ? 3 : Math.min(opened, 2);
      },
      because: (d) => [[d, 'as built'], [d.twin, 'on the wider footing']].map(([r, who]) => {
        if (!r) return `${who} the pier was not run (compare with \u201cthe same with other overrides\u201d)`;
        const opened = firstOpened(r);
        return opened === null ? `${who} no joint opened`
          : `${who} joint ${opened} opened first, at t = ${fmt(r.summary.joints[opened].first_uplift_s)} s`;
      }).join('; ') + '.',
    },
    controls: { scene: 'segmental_pier', record: '', scale: 1, compare: 'overrides', twinExtra: 'structure.half_width=1.5' },
    text:
      'A post-tensioned segmental bridge pier: four precast segments 1.5 m square on a footing, a central ' +
      'tendon through all of them and 100 t of deck on top. Each joint can open. Under its one-sine pulse of ' +
      '0.6 g it rocks at its footing alone: watch the joints\u2019 chart, where the joints above stay at 0. ' +
      '`rocking modal` says why: the push that opens each joint, a_g/g = (B + D_0/(m g))/H, is smallest at the ' +
      'footing (0.229 g; the joints above need 0.308, 0.466 and 0.941 g). The twin (dashed) stands on a footing ' +
      'twice as wide, which then needs 0.458 g: the pier rocks at the joint above its first segment instead. ' +
      'Change the footing\u2019s half-width in the twin\u2019s overrides and find where the rocking moves back.',
  },
];

// The joint of a run that opened first (summary.joints' first_uplift_s), or null.
function firstOpened(run) {
  if (!run || !run.summary.joints) return null;
  let first = null;
  run.summary.joints.forEach((j, k) => {
    if (j.first_uplift_s !== null && (first === null || j.first_uplift_s < run.summary.joints[first].first_uplift_s)) first = k;
  });
  return first;
}
