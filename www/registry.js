// The panel registry: one descriptor per view of the explorer, in menu order. The router, the
// landing view, share links and scenario import are written once against these fields:
//   id        the route (#id) and the prefix of share links (#id/v1/…)
//   title     the name in the menu and on the landing view
//   methods   the scenario methods the panel shows (a scenario file of one of them opens here)
//   promise   what the method guarantees, in two lines, for the landing view
//   module    the panel's module, loaded on the first visit, and its `mount(root, presets)`
//   view      the panel's markup (views/<id>.html), put into its root before the mount
//   section   the view's element; root: the panel inside it
//   busy      the document.body.dataset key the panel holds while it computes
export const PANELS = [
  {
    id: 'scf',
    title: 'SCF vs Kalman filter',
    methods: ['scf', 'kf'],
    promise: 'The State Conditional Filter region holds the state with probability α whatever value the state takes; '
      + 'the Kalman region holds it with probability α only on average over the states.',
    module: './scf.js',
    view: './views/scf.html',
    mount: 'mountScf',
    busy: 'busy',
  },
  {
    id: 'lscr',
    title: 'LSCR regions',
    methods: ['lscr'],
    promise: 'A region for a past, present or future state that holds it with probability at least 1 − 2qn/M '
      + 'for every value of the state, without knowing the noise variances.',
    module: './lscr.js',
    view: './views/lscr.html',
    mount: 'mountLscr',
    busy: 'lscrBusy',
  },
  {
    id: 'glls',
    title: 'GLLS horizon',
    methods: ['glls'],
    promise: 'A least-squares estimate over a horizon of s outputs whose error is bounded through the singular values '
      + 'of the observability matrix: a guaranteed ball and box for bounded noise, and a best horizon.',
    module: './glls.js',
    view: './views/glls.html',
    mount: 'mountGlls',
    busy: 'gllsBusy',
  },
  {
    id: 'uniform',
    title: 'Uniform innovations (LP)',
    methods: ['uniform_lp'],
    promise: 'With innovations uniform on boxes, the MAP estimate of a window of states, the parameters Θ and the '
      + 'half-widths is a linear program; every state consistent with the data lies in an exact polygon.',
    module: './uniform.js',
    view: './views/uniform.html',
    mount: 'mountUniform',
    busy: 'uniformBusy',
  },
  {
    id: 'ubb',
    title: 'Unknown-but-bounded noise',
    methods: ['ubb'],
    promise: 'When the noise is only known to be bounded, the states consistent with the data form a polytope: '
      + 'it holds the true state every time, and its interval hull gives a guaranteed error bound.',
    module: './ubb.js',
    view: './views/ubb.html',
    mount: 'mountUbb',
    busy: 'ubbBusy',
  },
  {
    id: 'compare',
    title: 'Compare every method',
    methods: ['compare'],
    promise: 'One system, one record, every method\'s set for the same state in one picture — and, counted at a state '
      + 'you place, what each promise means: on average, for every state, always (while the bounds hold), or nothing.',
    module: './compare.js',
    view: './views/compare.html',
    mount: 'mountCompare',
    busy: 'compareBusy',
  },
];

for (const d of PANELS) {
  d.section = () => document.getElementById(`${d.id}-section`);
  d.root = () => document.getElementById(d.id);
}

export const panelOf = (method) => PANELS.find((d) => d.methods.includes(method));
export const panelById = (id) => PANELS.find((d) => d.id === id);
