// The panel registry: one descriptor per view of the explorer, in menu order. The router, the
// landing view, share links and scenario import are written once against these fields:
// (the shell renders the menu and each view's section from them: index.html holds only the frame)
//   id        the route (#id) and the prefix of share links (#id/v1/…)
//   title     the name on the landing view and in the window's title
//   nav       the name in the menu
//   label     the accessible name of the view's section
//   heading   the view's heading (HTML: the name, then a <span> with what it does)
//   sub       the paragraph under the heading (HTML): the paper and what the view shows
//   methods   the scenario methods the panel shows (a scenario file of one of them opens here)
//   names     what the compare table calls each of them (its row of the method)
//   promise   what the method guarantees, in two lines, for the landing view
//   module    the panel's module, loaded on the first visit, and its `mount(root, presets)`
//   view      the panel's markup (views/<id>.html), put into its root before the mount
//   section   the view's element (#<id>-section); root: the panel inside it (#<id>)
//   busy      the document.body.dataset key the panel holds while it computes
//   thumb     the landing view's picture, thumbs/<id>.png: the core's figure of that preset's
//             panel, drawn by .ci/thumbs (`confset figure`), with its text alternative
export const PANELS = [
  {
    id: 'scf',
    title: 'SCF vs Kalman filter',
    nav: 'SCF vs KF',
    label: 'SCF vs Kalman filter',
    heading: 'State Conditional Filter <span>vs the Kalman filter</span>',
    sub: 'Carè, Campi, Weyer: a region that holds the state with probability α <em>whatever value the state takes</em>, '
      + 'beside the Kalman region that holds it only on average over the states.',
    methods: ['scf', 'kf'],
    names: { scf: 'SCF', kf: 'Kalman' },
    promise: 'The State Conditional Filter region holds the state with probability α whatever value the state takes; '
      + 'the Kalman region holds it with probability α only on average over the states.',
    module: './scf.js',
    view: './views/scf.html',
    mount: 'mountScf',
    busy: 'busy',
    thumb: { preset: 'scf-robots', panel: 'state', alt: 'Two robots near a collision: the SCF region holds the state, the Kalman ellipse misses it' },
  },
  {
    id: 'lscr',
    title: 'LSCR regions',
    nav: 'LSCR',
    label: 'LSCR',
    heading: 'LSCR <span>confidence regions for prediction, filtering and smoothing</span>',
    sub: 'Weyer &amp; Campi: a region that holds the true state with a guaranteed probability 1 − 2qn/M '
      + '<em>whatever the state is</em>, without knowing the noise variances. Click the figure to place the true state.',
    methods: ['lscr'],
    names: { lscr: 'LSCR' },
    promise: 'A region for a past, present or future state that holds it with probability at least 1 − 2qn/M '
      + 'for every value of the state, without knowing the noise variances.',
    module: './lscr.js',
    view: './views/lscr.html',
    mount: 'mountLscr',
    busy: 'lscrBusy',
    thumb: { preset: 'lscr-predict', panel: 'region', alt: 'The LSCR region for x₃₁, hatched where each X̂ₗ excludes, beside the BLUE ellipse' },
  },
  {
    id: 'glls',
    title: 'GLLS horizon',
    nav: 'GLLS',
    label: 'GLLS',
    heading: 'GLLS <span>state estimation on a limited horizon</span>',
    sub: 'Gubarev &amp; Mishchenko: estimate x(k) by least squares from the last s + 1 measurements. The singular '
      + 'values of Γ<sub>s+1</sub> set the condition number κ — a hard limit on the precision and a bound on the expected '
      + 'error — and σ<sub>n</sub>/√s picks the horizon. Move s and watch every figure follow.',
    methods: ['glls'],
    names: { glls: 'GLLS' },
    promise: 'A least-squares estimate over a horizon of s outputs whose error is bounded through the singular values '
      + 'of the observability matrix: a guaranteed ball and box for bounded noise, and a best horizon.',
    module: './glls.js',
    view: './views/glls.html',
    mount: 'mountGlls',
    busy: 'gllsBusy',
    thumb: { preset: 'glls-saturate', panel: 'singular', alt: 'Singular values of the observability matrix against the horizon s' },
  },
  {
    id: 'uniform',
    title: 'Uniform innovations (LP)',
    nav: 'Uniform LP',
    label: 'Uniform innovations',
    heading: 'Uniform innovations <span>states, parameters and noise bounds by linear programming</span>',
    sub: 'Pavelková: with innovations uniform on boxes of half-widths x<sub>r</sub>, y<sub>r</sub>, the MAP estimate of a '
      + 'window\'s states is a linear program — minimize the half-widths subject to hard bounds. A sliding window of ∂ samples runs on line; '
      + 'Θ = (A, B, C, D) is estimated with it by swapping (4.1) or expansion (4.2). Move the time cursor and watch every figure follow.',
    methods: ['uniform_lp'],
    names: { uniform_lp: 'uniform LP' },
    promise: 'With innovations uniform on boxes, the MAP estimate of a window of states, the parameters Θ and the '
      + 'half-widths is a linear program; every state consistent with the data lies in an exact polygon.',
    module: './uniform.js',
    view: './views/uniform.html',
    mount: 'mountUniform',
    busy: 'uniformBusy',
    thumb: { preset: 'uniform-paper', panel: 'ustates', alt: 'The estimated states of the LU model with their true values, on line' },
  },
  {
    id: 'ubb',
    title: 'Unknown-but-bounded noise',
    nav: 'Bounded noise',
    label: 'Set-membership estimation',
    heading: 'Unknown-but-bounded noise <span>guaranteed sets by linear programming</span>',
    sub: 'Tempo: when the noise is only known to be bounded (|u| ≤ τ, |η| ≤ ε, |x(0)| ≤ δ), the states consistent with the data '
      + 'form a polytope. Support LPs draw it exactly; its interval hull gives the central estimate and a <b>guaranteed</b> error bound. '
      + 'Exponential smoothing (α, β) and Theorem 5’s window (γ) keep the LP a constant size. Move k and watch the set follow the truth.',
    methods: ['ubb'],
    names: { ubb: 'Tempo' },
    promise: 'When the noise is only known to be bounded, the states consistent with the data form a polytope: '
      + 'it holds the true state every time, and its interval hull gives a guaranteed error bound.',
    module: './ubb.js',
    view: './views/ubb.html',
    mount: 'mountUbb',
    busy: 'ubbBusy',
    thumb: { preset: 'ubb-track', panel: 'ubbset', alt: 'The exact feasible polygon of the state with its interval hull and central estimate' },
  },
  {
    id: 'conformal',
    title: 'Conformal prediction',
    nav: 'Conformal',
    label: 'Conformal prediction',
    heading: 'Conformal prediction <span>on the Kalman filter\'s score</span>',
    sub: 'Split conformal (Vovk et al.) calibrates the radius of the Kalman ellipse on N simulated runs of the true noise law: '
      + 'the region holds the state with probability level ≤ P ≤ level + 1/(N + 1) <em>on average over runs</em>, not for every state. '
      + 'Adaptive conformal inference (Gibbs &amp; Candès) widens or narrows the output interval step by step and keeps the '
      + 'long-run miss rate near 1 − level on any record, drifting or not.',
    methods: ['conformal'],
    names: { conformal: 'conformal' },
    promise: 'A region calibrated on N simulated runs that holds the state with probability between the level and level + 1/(N + 1) '
      + 'on average over runs, whatever the noise law; and an output interval whose long-run miss rate stays near 1 − level on any record.',
    module: './conformal.js',
    view: './views/conformal.html',
    mount: 'mountConformal',
    busy: 'conformalBusy',
    thumb: { preset: 'conformal-heavy', panel: 'conformalset', alt: 'Under heavy-tailed noise the conformal ellipse, calibrated on 999 runs, is larger than the Kalman χ² ellipse of the same filter' },
  },
  {
    id: 'compare',
    title: 'Compare every method',
    nav: 'Compare',
    label: 'Compare every method',
    heading: 'Compare <span>every method on one record</span>',
    sub: 'The same system and the same data for all six: the Kalman and SCF ellipses, the LSCR region, GLLS\'s ball, Tempo\'s '
      + 'feasible set and Pavelková\'s consistent polygon for the same state, each with the parameters its paper needs derived from one '
      + 'noise law. The table says what each one assumes, whether the noise meets it, and what it promises. Click the figure to place '
      + 'a true state and count how often each set holds it.',
    methods: ['compare'],
    promise: 'One system, one record, every method\'s set for the same state in one picture — and, counted at a state '
      + 'you place, what each promise means: on average, for every state, always (while the bounds hold), or nothing.',
    module: './compare.js',
    view: './views/compare.html',
    mount: 'mountCompare',
    busy: 'compareBusy',
    thumb: { preset: 'compare-gaussian', panel: 'compare', alt: 'Every method’s set for the same state on equal axes' },
  },
];

for (const d of PANELS) {
  d.section = () => document.getElementById(`${d.id}-section`);
  d.root = () => document.getElementById(d.id);
}

export const panelOf = (method) => PANELS.find((d) => d.methods.includes(method));
export const panelById = (id) => PANELS.find((d) => d.id === id);
