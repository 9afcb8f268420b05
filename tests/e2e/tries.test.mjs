// "Things to try" (www/tries.js, www/trylist.js): every prompt of every preset holds. For each
// one the test opens the preset (the toolbar's "Reset to preset"), reads what the page shows —
// the report the panel keeps ("Download report (JSON)"), its numbers and its inline messages —,
// clicks the prompt's "Try it" button (found by its accessible name "Try: …"), waits for the
// run, reads again and checks the promise. The list follows the preset menu and is hidden for
// the custom model and a loaded scenario file; it does not widen a 390 px phone page (folded
// there, opened by a tap) and runs from the keyboard.
import { readFile } from 'node:fs/promises';
import { mkdtempSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { TRIES } from '../../www/tries.js';

// The view of each preset (its name's prefix) and what the test reads there.
const VIEWS = {
  scf: { prefix: '', busy: 'busy' },
  lscr: { prefix: 'l-', busy: 'lscrBusy' },
  glls: { prefix: 'g-', busy: 'gllsBusy' },
  uniform: { prefix: 'u-', busy: 'uniformBusy' },
  ubb: { prefix: 'b-', busy: 'ubbBusy' },
  conformal: { prefix: 'cf-', busy: 'conformalBusy' },
  compare: { prefix: 'c-', busy: 'compareBusy' },
};
const viewOf = (preset) => preset.split('-')[0];

// ----- what the page shows -----

const idle = (page, view) => page.waitForFunction(([busy, id]) => !document.body.dataset[busy]
  && !document.querySelector(`#${id}-section .tries[data-running]`), [VIEWS[view].busy, view], { timeout: 120_000 });

async function read(page, view) {
  const { prefix } = VIEWS[view];
  const [dl] = await Promise.all([page.waitForEvent('download'), page.click(`#${prefix}dl-report`)]);
  const report = JSON.parse(await readFile(await dl.path(), 'utf8'));
  // The numbers card (the uniform view's holds two tables: at the cursor, over the run).
  const numbers = await page.$eval(`#${prefix}numbers`, (e) => (e.closest('.card') || e).innerText.replace(/\s+/g, ' ').trim());
  const errors = await page.$eval(`#${view}`, (root) => [...root.querySelectorAll('.err[data-for]')]
    .filter((e) => !e.closest('[hidden]')).map((e) => e.textContent.trim()).filter(Boolean).join(' | '));
  return { report, numbers, errors };
}

// ----- the quantities the checks compare (from the report) -----

// Whether x (the components idx of it) lies in the ellipsoid {center, cov, radius2}, and its
// squared Mahalanobis distance.
function maha(reg, x, idx = null) {
  const xs = idx ? idx.map((i) => x[i]) : x;
  const d = xs.map((v, i) => v - reg.center[i]);
  const n = d.length;
  const a = reg.cov.map((r, i) => [...r, d[i]]);
  for (let i = 0; i < n; i++) {
    let p = i;
    for (let r = i + 1; r < n; r++) if (Math.abs(a[r][i]) > Math.abs(a[p][i])) p = r;
    [a[i], a[p]] = [a[p], a[i]];
    for (let r = 0; r < n; r++) {
      if (r === i) continue;
      const f = a[r][i] / a[i][i];
      for (let c = i; c <= n; c++) a[r][c] -= f * a[i][c];
    }
  }
  return d.reduce((s, v, i) => s + v * a[i][n] / a[i][i], 0);
}
const inside = (reg, x, idx) => maha(reg, x, idx) <= reg.radius2;

// SCF: the 1-D half-widths at the time shown; the robots' collision check made at t.
const scfAt = (r) => r.steps[r.time - 1];
const half = (reg) => Math.sqrt(reg.cov[0][0] * reg.radius2);
const collision = (r, t) => r.collision.find((c) => c.time === t);
// LSCR: the boundary's pieces.
const pieces = (l) => l.boundary.reduce((s, b) => s + b.points.length, 0);
// GLLS: the guaranteed ball's radius.
const ball = (g) => Math.sqrt(g.ball_current.cov[0][0] * g.ball_current.radius2);
// Uniform LP: the widest face range of x_t.
const face = (at) => Math.max(...at.face_lo[0].map((lo, i) => at.face_hi[0][i] - lo));
// Tempo: the hull's radius at the cursor's step, and the step itself.
const ubbStep = (u) => u.track.find((t) => t.k === u.at.k);
const radius = (u) => ubbStep(u).radius;
// Compare: a method's row and its set at t.
const method = (c, m) => {
  const i = c.rows.findIndex((r) => r.method === m);
  return { ...c.rows[i], ...c.at.sets[i] };
};

// ----- each prompt's promise: check(before, after, assert) -----

const scf = (x) => x.report;
const lscr = (x) => x.report.lscr;
const glls = (x) => x.report.glls;
const uni = (x) => x.report.uniform;
const ubb = (x) => x.report.ubb;
const cmp = (x) => x.report.compare;
const cf = (x) => x.report.conformal;
const near = (a, b, tol) => Math.abs(a - b) <= tol;

const robotsOrdinary = (b, a, ok) => {
  const [cb, ca] = [collision(scf(b), 36), collision(scf(a), 36)];
  ok(cb.scf_warning && !cb.kf_warning, 'the rare realization: SCF warns at t = 36, the Kalman filter does not');
  ok(!ca.scf_warning && !ca.kf_warning, `an ordinary run: no warning at t = 36 (${ca.scf_warning}, ${ca.kf_warning})`);
  ok(ca.true_distance > 1, `the robots pass far apart (${ca.true_distance})`);
};
const robotsNoLookahead = (b, a, ok) => {
  const r = scf(a);
  ok(r.time === 40, `the time shown is 40 (${r.time})`);
  const [c40, c36] = [collision(r, 40), collision(r, 36)];
  ok(c40.scf_warning && !c40.kf_warning, 'τ = 0: the SCF warns at t = 40, the Kalman filter does not');
  ok(!c36.scf_warning, 'τ = 0: no SCF warning at t = 36');
  ok(collision(scf(b), 36).scf_warning, 'τ = 4: the SCF warned at t = 36');
};
const qUp = (b, a, ok) => {
  ok(Math.abs(lscr(b).level - 0.9) < 1e-9 && Math.abs(lscr(a).level - 0.8) < 1e-9, `level ${lscr(b).level} → ${lscr(a).level}`);
  ok(lscr(a).area < lscr(b).area, `the region shrinks: area ${lscr(b).area} → ${lscr(a).area}`);
};
const ubbTauLow = (b, a, ok) => {
  ok(ubb(b).outside === 0, `the preset's set holds the truth at every step (${ubb(b).outside} outside)`);
  ok(ubb(a).outside > 0, `with the wrong bound the truth leaves the set (${ubb(a).outside} steps)`);
  ok(/truth outside the set [1-9]\d* \//.test(a.numbers), `"over the run" counts it: ${a.numbers.match(/over the run.*/)?.[0]}`);
};
const ubbRefused = (b, a, ok) => ok(/ubb\.eps leaves no state consistent with the data/.test(a.errors), `refused by ε: "${a.errors}"`);

const CHECKS = {
  'scf-scalar': {
    'alpha-down': (b, a, ok) => {
      const [sb, sa] = [scfAt(scf(b)), scfAt(scf(a))];
      ok(scf(a).time === 50, 't = 50 shown');
      ok(half(sa.kf) < half(sb.kf) && half(sa.scf) < half(sb.scf), 'both intervals shrink');
      ok(half(sa.scf) > half(sa.kf), 'the SCF interval stays wider');
    },
    rare: (b, a, ok) => {
      const r = scf(a);
      const x = r.x_true[r.time - 1];
      ok(r.time === 50 && x[0] === 25, `x̄ = 25 at t = 50 (${x}, t = ${r.time})`);
      ok(!inside(scfAt(r).kf, x), 'the Kalman interval misses x̄');
      ok(inside(scfAt(r).scf, x), 'the SCF interval holds x̄');
      const rb = scf(b);
      ok(inside(scfAt(rb).kf, rb.x_true[rb.time - 1]), 'before: the Kalman interval held the ordinary state');
    },
    'noisy-w': (b, a, ok) => {
      const [sb, sa] = [scfAt(scf(b)), scfAt(scf(a))];
      ok(sa.ratio[0][0] < 0.9 - 1e-6 && Math.abs(sb.ratio[0][0] - 0.9) < 1e-6, `ratio ${sb.ratio[0][0]} → ${sa.ratio[0][0]}`);
      ok(half(sa.scf) / half(sb.scf) > half(sa.kf) / half(sb.kf), 'the SCF interval widens more than the Kalman one');
    },
    asymptotic: (b, a, ok) => {
      const [rb, ra] = [scf(b), scf(a)];
      ok(ra.time === 1, `t = 1 shown (${ra.time})`);
      ok(ra.steps[0].scf.cov[0][0] < rb.steps[0].scf.cov[0][0], 'at t = 1 the asymptotic interval is narrower');
      const [lb, la] = [rb.steps[49].scf, ra.steps[49].scf];
      ok(Math.abs(la.cov[0][0] - lb.cov[0][0]) < 1e-6 && Math.abs(la.center[0] - lb.center[0]) < 1e-6, 'at t = 50 they coincide');
    },
  },
  'scf-robots': {
    'alpha-up': (b, a, ok) => {
      const [cb, ca] = [collision(scf(b), 36), collision(scf(a), 36)];
      ok(scf(a).time === 36, 't = 36 shown');
      ok(ca.kf_distance < cb.kf_distance && !ca.kf_warning && !cb.kf_warning, `the Kalman regions grow, no warning (gap ${cb.kf_distance} → ${ca.kf_distance})`);
      ok(ca.scf_warning, 'the SCF warns');
    },
    ordinary: robotsOrdinary,
    'no-lookahead': robotsNoLookahead,
  },
  'scf-robots-literal': {
    ordinary: robotsOrdinary,
    'no-lookahead': (b, a, ok) => {
      robotsNoLookahead(b, a, ok);
      ok(collision(scf(a), 40).kf_distance > 1, 'the Kalman regions stay far apart');
    },
  },
  'lscr-predict': {
    'q-up': qUp,
    'fewer-strings': (b, a, ok) => {
      const [lb, la] = [lscr(b), lscr(a)];
      ok(Math.abs(la.level - lb.level) < 1e-9 && la.M === 40 && la.q === 1, `the same level ${la.level}`);
      ok(pieces(la) < pieces(lb), `a coarser boundary: ${pieces(lb)} → ${pieces(la)} points`);
      ok(la.area > lb.area, `a larger region: ${lb.area} → ${la.area}`);
    },
    'far-state': (b, a, ok) => {
      const l = lscr(a);
      ok(l.x_true[0] === 0.35 && l.x_true[1] === 1.1, `the true state is x̄ (${l.x_true})`);
      ok(!inside(l.kf, l.x_true), 'the Kalman ellipse misses it');
      ok(l.truth_inside === true && /X̂ = ∩ X̂l ≥ 90 % ✓ inside/.test(a.numbers), 'the LSCR region holds it');
    },
    noisier: (b, a, ok) => {
      ok(lscr(a).area > 3 * lscr(b).area, `area ${lscr(b).area} → ${lscr(a).area}`);
      ok(lscr(a).truth_inside === true, 'it still holds the truth');
    },
  },
  'lscr-smooth': {
    predict: (b, a, ok) => {
      ok(lscr(b).time === 15 && lscr(a).time === 31, 'x₁₅ → x₃₁');
      ok(lscr(a).area > 3 * lscr(b).area, `area ${lscr(b).area} → ${lscr(a).area}`);
    },
    'index-end': (b, a, ok) => {
      ok(lscr(b).bounded === true && lscr(a).bounded === false, 'bounded → unbounded');
      ok(lscr(a).time === 29 && /Region unbounded along/.test(a.numbers), `the numbers say it: ${a.numbers.match(/Region.{0,60}/)?.[0]}`);
    },
    'q-up': qUp,
  },
  'lscr-ma1': {
    'ordinary-state': (b, a, ok) => {
      ok(!inside(lscr(b).kf, lscr(b).x_true), 'before: the Kalman ellipse misses (1, 1.2)');
      ok(inside(lscr(a).kf, lscr(a).x_true), 'an ordinary state: the Kalman ellipse holds it');
    },
    'along-band': (b, a, ok) => {
      const [lb, la] = [lscr(b), lscr(a)];
      ok(la.x_true[0] === 3 && la.x_true[1] === 3.2, `x̄ = ${la.x_true}`);
      ok(la.truth_inside === true && la.bounded === false, 'the band holds it');
      ok(maha(la.kf, la.x_true) > maha(lb.kf, lb.x_true) && !inside(la.kf, la.x_true), 'the Kalman ellipse misses it by more');
    },
    filter: (b, a, ok) => {
      ok(lscr(a).time === 20 && lscr(a).estimate === 'filter', 'filtering x₂₀');
      ok(lscr(a).area < lscr(b).area / 10, `area ${lscr(b).area} → ${lscr(a).area}`);
      ok(lscr(a).truth_inside === true, 'it still holds the state');
    },
  },
  'glls-saturate': {
    'past-best': (b, a, ok) => {
      const [gb, ga] = [glls(b), glls(a)];
      ok(gb.s === 8 && gb.best_horizon === 8 && ga.s === 20, `s ${gb.s} → ${ga.s}`);
      const n = ga.n - 1;
      ok(ga.sigma[n] / gb.sigma[n] < Math.sqrt(21 / 9), `σ₃ barely grows: ${gb.sigma[n]} → ${ga.sigma[n]}`);
      ok(ga.index[20] < ga.index[8], 'σₙ/√s falls below its peak');
      ok(ga.kappa_past > 0.7 * gb.kappa_past && ga.kappa_past < gb.kappa_past, `κ barely improves: ${gb.kappa_past} → ${ga.kappa_past}`);
    },
    short: (b, a, ok) => {
      ok(glls(a).s === 3 && glls(a).kappa_past > 3 * glls(b).kappa_past, `κ ${glls(b).kappa_past} → ${glls(a).kappa_past}`);
      ok(ball(glls(a)) > ball(glls(b)), 'the ball widens');
    },
    worst: (b, a, ok) => {
      ok(glls(a).error_current > 10 * glls(b).error_current, `error ${glls(b).error_current} → ${glls(a).error_current}`);
      ok(glls(a).truth_in_box === true && /guaranteed box .*✓ inside/.test(a.numbers), 'the truth stays in the box');
      // … on its edge: in some component the truth is at the box's bound.
      const g = glls(a);
      const gap = Math.min(...g.box_current.lo.map((lo, i) => {
        const [hi, x] = [g.box_current.hi[i], g.x_true_current[i]];
        return Math.min(x - lo, hi - x) / (hi - lo);
      }));
      ok(gap < 2e-4, `the truth is on an edge of the box (relative gap ${gap})`);
    },
    gaussian: (b, a, ok) => {
      ok(glls(b).truth_in_box === true && glls(a).truth_in_box === false, 'the box misses the truth');
      ok(/guaranteed box .*✗ outside/.test(a.numbers), 'the numbers say it');
    },
  },
  'glls-grow': {
    longer: (b, a, ok) => {
      const [gb, ga] = [glls(b), glls(a)];
      ok(ga.s === 20 && ga.kappa_past < gb.kappa_past / 10, `κ past ${gb.kappa_past} → ${ga.kappa_past}`);
      ok(Math.abs(ga.kappa_current / gb.kappa_current - 1) < 0.2, `κ current ${gb.kappa_current} → ${ga.kappa_current}`);
    },
    best: (b, a, ok) => {
      const g = glls(a);
      ok(g.s === 39 && g.k === 39, `s = ${g.s}, k = ${g.k}`);
      ok(g.best_horizon == null || g.best_horizon > g.k, `the best horizon lies beyond the data (${g.best_horizon})`);
    },
    rounding: (b, a, ok) => {
      ok(!glls(b).rounding_dominates && glls(a).rounding_dominates, 'rounding dominates now');
      ok(/Rounding dominates/.test(a.numbers) && !/Rounding dominates/.test(b.numbers), 'the alarm appears');
    },
  },
  'glls-mixed': {
    short: (b, a, ok) => {
      ok(glls(a).s === 3 && glls(a).kappa_past > 100 * glls(b).kappa_past, `κ ${glls(b).kappa_past} → ${glls(a).kappa_past}`);
      ok(ball(glls(a)) > 5 * ball(glls(b)), `the ball ${ball(glls(b))} → ${ball(glls(a))}`);
    },
    p1: (b, a, ok) => {
      const [rb, ra] = [glls(b).regularized, glls(a).regularized];
      ok(rb.p === 2 && ra.p === 1, `p ${rb.p} → ${ra.p}`);
      ok(ra.kappa_past < rb.kappa_past, `regularized κ ${rb.kappa_past} → ${ra.kappa_past}`);
      ok(/Regularized, p = 1 of 3/.test(a.numbers), 'the numbers say it');
    },
    worst: (b, a, ok) => {
      ok(glls(a).error_current > 5 * glls(b).error_current, `error ${glls(b).error_current} → ${glls(a).error_current}`);
      ok(glls(a).truth_in_ball === true, 'the truth stays in the ball');
    },
  },
  'glls-unstable5': {
    'too-short': (b, a, ok) => {
      ok(/glls\.horizon s = 2: Γ_\{s\+1\} has rank 3 < n = 5/.test(a.errors) || /rank 3 < n = 5/.test(a.errors), `refused: "${a.errors}"`);
      ok(glls(a).s === 8, 'the last picture stays');
    },
    whole: (b, a, ok) => {
      ok(glls(a).s === 15 && glls(a).rounding_estimate > 1000 * glls(b).rounding_estimate, `rounding ${glls(b).rounding_estimate} → ${glls(a).rounding_estimate}`);
      ok(glls(a).sigma[0] > 1e6, `σ₁ = ${glls(a).sigma[0]}`);
    },
  },
  'uniform-paper': {
    'theta-known': (b, a, ok) => {
      ok(uni(a).at.time === 120 && face(uni(b).at) < 0.01 && face(uni(a).at) > 0.3, `face ${face(uni(b).at)} → ${face(uni(a).at)}`);
      ok(uni(a).rms_lp < uni(b).rms_lp, `RMS ${uni(b).rms_lp} → ${uni(a).rms_lp}`);
    },
    window: (b, a, ok) => {
      ok(uni(a).window === 20 && uni(a).rms_lp < 0.75 * uni(b).rms_lp, `RMS ${uni(b).rms_lp} → ${uni(a).rms_lp}`);
      ok(uni(a).rms_lp > uni(a).rms_kf, 'still above the Kalman filter');
    },
    'tight-bounds': (b, a, ok) => {
      ok(uni(b).extended === 0 && uni(a).extended > 10, `extended ${uni(b).extended} → ${uni(a).extended}`);
      ok(/half-width bounds extended [1-9]\d* times/.test(a.numbers), 'the numbers count it');
    },
    'wrong-bound': (b, a, ok) => {
      ok(uni(b).at.truth_in_polygon === true, 'before: the polygon holds the truth');
      ok(uni(a).at.polygon_theta_true === true && uni(a).at.truth_in_polygon === false, 'the true-Θ polygon misses the truth');
    },
  },
  'ubb-track': {
    'tau-low': ubbTauLow,
    'eps-low': ubbRefused,
    'all-data': (b, a, ok) => {
      ok(ubb(a).window === 60 && ubb(b).window === 30 && ubb(a).at.k === 40, `window ${ubb(b).window} → ${ubb(a).window}`);
      ok(Math.abs(radius(ubb(a)) - radius(ubb(b))) < 1e-3, `the same set: ${radius(ubb(b))} → ${radius(ubb(a))}`);
      ok(ubb(a).at.size.variables > ubb(b).at.size.variables, 'a larger LP');
    },
    'at-bound': (b, a, ok) => {
      ok(ubb(a).outside === 0 && ubbStep(ubb(a)).inside, 'the set holds the truth at every step');
      ok(radius(ubb(a)) < radius(ubb(b)), `smaller: ${radius(ubb(b))} → ${radius(ubb(a))}`);
    },
  },
  'ubb-series': {
    'more-data': (b, a, ok) => {
      const [ub, ua] = [ubb(b), ubb(a)];
      ok(ub.at.k === 9 && ua.at.k === 29, `k ${ub.at.k} → ${ua.at.k}`);
      ok(radius(ua) < radius(ub) / 3 && ubbStep(ua).inside, `radius ${radius(ub)} → ${radius(ua)}, truth inside`);
      const w = (u) => u.at.prediction[0][1] - u.at.prediction[0][0];
      ok(w(ua) < w(ub), `the prediction interval narrows: ${w(ub)} → ${w(ua)}`);
    },
    'eps-low': ubbRefused,
    'at-bound': (b, a, ok) => {
      ok(radius(ubb(a)) < 1e-6 && ubbStep(ubb(a)).inside, `radius ${radius(ubb(a))}, truth inside`);
    },
  },
  'ubb-leontief': {
    'tau-low': ubbTauLow,
    'gamma-up': (b, a, ok) => {
      ok(ubb(a).window < ubb(b).window && ubb(a).at.size.variables < ubb(b).at.size.variables, `window ${ubb(b).window} → ${ubb(a).window}, a smaller LP`);
      ok(Math.abs(radius(ubb(a)) - radius(ubb(b))) <= 0.2, `radius ${radius(ubb(b))} → ${radius(ubb(a))}`);
    },
    'eps-up': (b, a, ok) => {
      ok(ubb(a).outside === 0, 'the truth stays inside at every step');
      ok(radius(ubb(a)) > radius(ubb(b)), `larger: ${radius(ubb(b))} → ${radius(ubb(a))}`);
    },
  },
  'ubb-markov': {
    later: (b, a, ok) => {
      ok(ubb(a).at.k === 10 && radius(ubb(a)) < radius(ubb(b)) / 3, `radius ${radius(ubb(b))} → ${radius(ubb(a))}`);
      ok(ubbStep(ubb(a)).inside, 'truth inside');
    },
    'delta-tight': (b, a, ok) => {
      ok(radius(ubb(a)) < 0.7 * radius(ubb(b)), `radius ${radius(ubb(b))} → ${radius(ubb(a))}`);
      ok(ubb(a).outside === 0, 'truth inside at every step');
    },
    'delta-wrong': ubbTauLow,
  },
  'conformal-gaussian': {
    'more-calibration': (b, a, ok) => {
      const [cb, ca] = [cf(b), cf(a)];
      ok(ca.calibration === 999 && near(cb.upper, 0.905, 1e-9) && near(ca.upper, 0.901, 1e-9), `upper bound ${cb.upper} → ${ca.upper}`);
      ok(/90\.5 %/.test(b.numbers) && /90\.1 %/.test(a.numbers), 'the numbers say 90.5 % → 90.1 %');
      ok(Math.abs(ca.radius2 - ca.chi2_radius2) < Math.abs(cb.radius2 - cb.chi2_radius2), `radius² ${cb.radius2} → ${ca.radius2}, χ² ${ca.chi2_radius2}`);
    },
    'few-calibration': (b, a, ok) => {
      const c = cf(a);
      ok(c.calibration === 19 && c.rank === 18 && near(c.lower, 0.9, 1e-9) && near(c.upper, 0.95, 1e-9), `N ${c.calibration}, k ${c.rank}, [${c.lower}, ${c.upper}]`);
      ok(/90 % ≤ P ≤ 95 %/.test(a.numbers), 'the numbers say 90 % ≤ P ≤ 95 %');
    },
    'student-t': (b, a, ok) => {
      ok(cf(a).noise === 'student_t' && cf(a).nu === 3, `Student-t, ν = ${cf(a).nu}`);
      ok(cf(a).radius2 < cf(a).chi2_radius2 && cf(a).radius2 < cf(b).radius2, `radius² ${cf(b).radius2} → ${cf(a).radius2} < χ² ${cf(a).chi2_radius2}`);
    },
  },
  'conformal-heavy': {
    gaussian: (b, a, ok) => {
      const [cb, ca] = [cf(b), cf(a)];
      ok(ca.noise === 'gaussian' && cb.radius2 > 14 && cb.radius2 < 16, `before: radius² ${cb.radius2} (about 15)`);
      ok(Math.abs(ca.radius2 / ca.chi2_radius2 - 1) < 0.05, `after: radius² ${ca.radius2} about χ² ${ca.chi2_radius2}`);
    },
    fewer: (b, a, ok) => {
      const [cb, ca] = [cf(b), cf(a)];
      ok(ca.calibration === 199 && ca.rank === 198, `k = ${ca.rank} of N = ${ca.calibration}`);
      ok(ca.radius2 > 3 * cb.radius2, `radius² ${cb.radius2} → ${ca.radius2}`);
      ok(near(ca.upper, 0.995, 1e-9) && /99\.5 %/.test(a.numbers), `upper bound ${ca.upper}`);
    },
    'nu-up': (b, a, ok) => {
      const [cb, ca] = [cf(b), cf(a)];
      ok(ca.nu === 10 && ca.radius2 < cb.radius2 && ca.radius2 > ca.chi2_radius2, `radius² ${cb.radius2} → ${ca.radius2}, χ² ${ca.chi2_radius2}`);
    },
    'level-down': (b, a, ok) => {
      ok(cf(b).radius2 > cf(b).chi2_radius2, 'at 99 % the conformal radius² is above the χ² one');
      ok(cf(a).level === 0.9 && cf(a).radius2 < cf(a).chi2_radius2, `at 90 %: ${cf(a).radius2} < ${cf(a).chi2_radius2}`);
    },
  },
  'conformal-far': {
    'level-up': (b, a, ok) => {
      const [cb, ca] = [cf(b), cf(a)];
      ok(cb.inside === false && cb.kf_inside === false, 'before: both regions miss (6, −2)');
      ok(ca.truth[0] === 6 && ca.truth[1] === -2 && ca.inside === true && ca.kf_inside === true, `at 95 % both hold ${ca.truth}`);
      ok(cb.truth_score > cb.radius2 && cb.truth_score > cb.chi2_radius2 && ca.truth_score < ca.radius2 && ca.truth_score < ca.chi2_radius2, 'its score lies between the 90 % and the 95 % radii²');
      ok(/truth in the regions conformal ✓ inside · Kalman ✓ inside/.test(a.numbers), 'the numbers say it');
    },
    seed: (b, a, ok) => {
      const ca = cf(a);
      ok(ca.truth[0] === 6 && ca.truth[1] === -2 && ca.time === 30, `the same state ${ca.truth} at t = ${ca.time}`);
      ok(cf(b).inside === false && cf(b).kf_inside === false && ca.inside === true && ca.kf_inside === true, 'both missed; both hold it now');
    },
    later: (b, a, ok) => {
      const ca = cf(a);
      ok(ca.time === 60 && !(ca.truth[0] === 6 && ca.truth[1] === -2), `t = ${ca.time}: x = ${ca.truth}`);
      ok(ca.inside === true && ca.kf_inside === true, 'both regions hold it');
    },
  },
  'conformal-aci-drift': {
    'gamma-up': (b, a, ok) => {
      const [ab, aa] = [cf(b).aci, cf(a).aci];
      ok(aa.gamma === 0.05 && near(ab.worst[0], 0.78, 1e-9) && near(aa.worst[0], 0.84, 1e-9), `worst window ${ab.worst[0]} → ${aa.worst[0]}`);
      // The long-run coverage (Prop. 4.1's quantity, over every scored step) nears 90 %; the
      // coverage over the steps with an interval and Kalman's over the same steps move with them.
      ok(aa.long_run_coverage > ab.long_run_coverage && Math.abs(aa.long_run_coverage - 0.9) < 0.01, `long-run coverage ${ab.long_run_coverage} → ${aa.long_run_coverage}`);
      ok(aa.bound < ab.bound && near(ab.bound, 0.23, 0.005) && near(aa.bound, 0.05, 0.005), `bound ${ab.bound} → ${aa.bound}`);
      ok(near(aa.kf_coverage, 0.66, 0.01) && near(ab.kf_coverage, 0.66, 0.01), `Kalman ${ab.kf_coverage} → ${aa.kf_coverage}`);
    },
    'gamma-down': (b, a, ok) => {
      const aa = cf(a).aci;
      ok(near(aa.coverage, 0.84, 0.005) && near(aa.worst[0], 0.68, 1e-9), `coverage ${aa.coverage}, worst window ${aa.worst[0]}`);
      ok(aa.bound > 1, `bound ${aa.bound}`);
    },
    'level-up': (b, a, ok) => {
      const aa = cf(a).aci;
      ok(cf(a).level === 0.95 && near(aa.coverage, 0.93, 0.006) && near(aa.kf_coverage, 0.74, 0.005), `ACI ${aa.coverage}, Kalman ${aa.kf_coverage}`);
      ok(/truth in the regions conformal – · Kalman – /.test(a.numbers), 'measured data: no verdict on a truth');
    },
  },
  'compare-gaussian': {
    'alpha-up': (b, a, ok) => {
      const [kb, ka] = [method(cmp(b), 'kf'), method(cmp(a), 'kf')];
      ok(ka.area > 1.5 * kb.area && ka.holds === false && kb.holds === false, `Kalman: area ${kb.area} → ${ka.area}, misses`);
      ok(method(cmp(a), 'scf').holds === true && method(cmp(a), 'lscr').holds === true, 'SCF and LSCR hold it');
    },
    'prior-state': (b, a, ok) => {
      ok(method(cmp(b), 'kf').holds === false && method(cmp(a), 'kf').holds === true, 'the Kalman ellipse now holds it');
    },
    'tight-bounds': (b, a, ok) => {
      const [t, u] = [method(cmp(a), 'ubb'), method(cmp(a), 'uniform_lp')];
      ok(!t.set && /no state consistent/.test(t.reason || ''), `Tempo: no set (${t.reason})`);
      ok(u.holds === false, 'the uniform LP set misses x₃₁');
      ok(/0\.5× the noise/.test(t.violated) && /0\.5× the noise/.test(u.violated), 'their rows say it');
    },
  },
  'compare-uniform': {
    'tight-bounds': (b, a, ok) => {
      ok(method(cmp(b), 'ubb').met === true && method(cmp(a), 'ubb').met === false, 'Tempo: ✓ → ✗');
      ok(!method(cmp(a), 'ubb').set, 'Tempo: no set');
      ok(method(cmp(b), 'uniform_lp').holds === true && method(cmp(a), 'uniform_lp').holds === false, 'the LP set misses');
    },
    'loose-bounds': (b, a, ok) => {
      const [tb, ta] = [method(cmp(b), 'ubb'), method(cmp(a), 'ubb')];
      ok(ta.holds === true && ta.met === true, 'Tempo holds it');
      ok(ta.area > 2 * tb.area, `area ${tb.area} → ${ta.area}`);
    },
    gaussian: (b, a, ok) => {
      ok(method(cmp(b), 'kf').met === false && method(cmp(a), 'kf').met === true, 'Kalman: ✗ → ✓');
      ok(method(cmp(b), 'scf').met === false && method(cmp(a), 'scf').met === true, 'SCF: ✗ → ✓');
      ok(method(cmp(b), 'ubb').met === true && method(cmp(a), 'ubb').met === false && /unbounded/.test(method(cmp(a), 'ubb').violated), 'Tempo: ✓ → ✗');
    },
  },
};

export default async function tries(env) {
  const { newPage, baseUrl, waitReady, assert } = env;
  // Every prompt has its check and every check its prompt.
  const prompts = Object.entries(TRIES).flatMap(([preset, list]) => list.map((t) => ({ preset, t })));
  const checks = Object.entries(CHECKS).flatMap(([preset, c]) => Object.keys(c).map((id) => `${preset}/${id}`));
  assert.deepEqual(checks.sort(), prompts.map(({ preset, t }) => `${preset}/${t.id}`).sort(), 'a check for every prompt');
  for (const list of Object.values(TRIES)) assert.ok(list.length >= 2 && list.length <= 4, '2–4 prompts per preset');

  const page = await newPage({ viewport: { width: 1280, height: 800 } });
  let checked = 0;
  let presetsSeen = 0;
  for (const view of Object.keys(VIEWS)) {
    const { prefix } = VIEWS[view];
    await page.goto(`${baseUrl}#${view}`);
    await waitReady(page);
    await idle(page, view);
    const section = `#${view}-section`;
    const options = await page.$$eval(`#${prefix}preset option`, (os) => os.map((o) => o.value));
    // The custom model has no prompts: the list is hidden.
    if (options.includes('custom')) {
      await page.selectOption(`#${prefix}preset`, 'custom');
      await idle(page, view);
      assert.equal(await page.$eval(`${section} .tries`, (e) => e.hidden), true, `${view}: no list for the custom model`);
    }
    for (const preset of options.filter((o) => TRIES[o])) {
      assert.equal(viewOf(preset), view, `${preset} is a preset of the ${view} view`);
      presetsSeen++;
      await page.selectOption(`#${prefix}preset`, preset);
      await idle(page, view);
      // The list follows the menu: this preset's prompts, each with its button.
      const shown = await page.$$eval(`${section} .tries li`, (lis) => lis.map((li) => li.dataset.try));
      assert.deepEqual(shown, TRIES[preset].map((t) => t.id), `${preset}: its prompts are listed`);
      assert.equal(await page.$eval(`${section} .tries`, (e) => e.hidden), false, `${preset}: the list is shown`);
      for (const t of TRIES[preset]) {
        const what = `${preset}/${t.id}`;
        for (const id of Object.keys(t.apply)) {
          assert.ok(await page.$(`#${view} form [id="${id}"]`), `${what}: the control #${id} is on the panel`);
        }
        // From the preset (a previous prompt moved the controls).
        await page.click(`${section} [data-act=reset]`);
        await idle(page, view);
        const before = await read(page, view);
        assert.equal(before.errors, '', `${what}: the preset runs without a message`);
        await page.getByRole('button', { name: `Try: ${t.name}`, exact: true }).click();
        await idle(page, view);
        const after = await read(page, view);
        assert.match(await page.$eval(`${section} .try-status`, (e) => e.textContent), new RegExp(`^Tried: ${t.name.replace(/[.*+?^${}()|[\]\\]/g, '\\$&')}\\.`), `${what}: the status says what was tried`);
        const fails = [];
        CHECKS[preset][t.id](before, after, (cond, msg) => { if (!cond) fails.push(msg); });
        assert.deepEqual(fails, [], `${what}: “${t.watch}” does not hold`);
        checked++;
      }
    }
  }
  assert.equal(presetsSeen, Object.keys(TRIES).length, 'every preset with prompts is in a menu');
  assert.equal(checked, prompts.length, `every prompt checked (${checked})`);
  console.log(`  tries: ${checked} prompts of ${presetsSeen} presets hold`);

  // Keyboard: a Try button takes the focus and Enter runs it; on a loaded preset link the list is
  // that preset's.
  await page.goto(`${baseUrl}#ubb/preset/ubb-markov`);
  await waitReady(page);
  await idle(page, 'ubb');
  assert.equal(await page.$eval('#ubb-section .tries li', (li) => li.dataset.try), 'later', 'the link\'s preset has its list');
  const button = page.getByRole('button', { name: 'Try: move step k to 10', exact: true });
  await button.focus();
  await page.keyboard.press('Enter');
  await idle(page, 'ubb');
  assert.equal(await page.$eval('#b-time', (e) => e.value), '10', 'Enter on the focused button ran the prompt');

  // A loaded scenario file is not a preset: no prompts (they would not hold); "Undo load" brings
  // the preset and its list back.
  const scenario = await page.evaluate(() => JSON.parse(window.confset.presets()).find((p) => p.name === 'ubb-track').scenario);
  const dir = mkdtempSync(join(tmpdir(), 'confset-tries-'));
  const file = join(dir, 'mine.json');
  writeFileSync(file, JSON.stringify({ ...scenario, title: 'mine' }));
  await page.setInputFiles('#ubb-section input[data-act=file]', file);
  await page.waitForFunction(() => /loaded/.test(document.querySelector('#ubb-section .share-status').textContent), null, { timeout: 30_000 });
  await idle(page, 'ubb');
  assert.match(await page.$eval('#b-preset', (e) => e.value), /^file:/);
  assert.equal(await page.$eval('#ubb-section .tries', (e) => e.hidden), true, 'no prompts for a loaded file');
  await page.click('#ubb-section [data-act=undo]');
  await idle(page, 'ubb');
  assert.equal(await page.$eval('#ubb-section .tries', (e) => e.hidden), false, 'the preset\'s prompts are back');
  assert.equal(await page.$eval('#ubb-section .tries li', (li) => li.dataset.try), 'later');

  // Phone: the list wraps within the page.
  const phone = await newPage({ viewport: { width: 390, height: 844 }, deviceScaleFactor: 2, isMobile: true, hasTouch: true });
  for (const view of ['lscr', 'glls']) {
    await phone.goto(`${baseUrl}#${view}`);
    await waitReady(phone);
    await idle(phone, view);
    // Folded on a phone (the controls stay near the top): a tap opens it.
    assert.equal(await phone.$eval(`#${view}-section .tries`, (e) => e.open), false, `${view} at 390 px: the list is folded`);
    await phone.click(`#${view}-section .tries summary`);
    assert.equal(await phone.$eval(`#${view}-section .tries`, (e) => e.open), true, `${view} at 390 px: a tap opens it`);
    const [doc, box] = await phone.evaluate((v) => {
      const b = document.querySelector(`#${v}-section .tries`).getBoundingClientRect();
      return [document.documentElement.scrollWidth, b.right];
    }, view);
    assert.ok(doc <= 390 && box <= 390, `${view} at 390 px: the page is ${doc} px wide, the list ends at ${box} px`);
  }
}
