// "Things to try": for each preset, a few prompts for a lecturer or a student. Each names one
// move of the panel's controls (by their visible labels) and what to watch; its "Try it" button
// starts again from the preset and makes exactly that move through the panel's own controls
// (trylist.js), so the scenario reruns as if the user had moved them.
//   id     the prompt's name within its preset (tests/e2e/tries.test.mjs checks each one's promise
//          by it, from what the page shows)
//   name   the move, short: the button's accessible name is "Try: <name>"
//   move   the move, in words, with the controls' visible labels
//   watch  what happens, in words (what the test checks)
//   apply  the controls the move sets: element id in the panel → value (a checkbox: true/false)
// Data only: no numbers are computed here, and nothing is judged; the prompts hold for the
// presets as shipped (their seeds), which is what the test pins.
export const TRIES = {
  // ----- SCF vs the Kalman filter (Carè, Campi, Weyer) -----
  'scf-scalar': [
    {
      id: 'alpha-down',
      name: 'lower α to 0.90',
      move: 'Lower the “Probability level α” slider from 0.99 to 0.90.',
      watch: 'Both intervals at t = 50 shrink (a smaller χ² radius); the SCF interval stays wider than the Kalman one — the price of holding x whatever value it takes.',
      apply: { alpha: 0.9 },
    },
    {
      id: 'rare',
      name: 'tick rare realization',
      move: 'Tick “rare realization”: the state is fixed at x̄ = 25 at the last step, about 10 σ of the prior.',
      watch: 'At t = 50 the Kalman interval, pulled towards the prior mean 0, misses x̄; the SCF interval, centred with that pull undone, still holds it (Fig. 1 shows how often, for every x̄).',
      apply: { rare: true },
    },
    {
      id: 'noisy-w',
      name: 'raise noise W to ×10',
      move: 'Raise “Noise W ×” to 10: the measurements are ten times noisier.',
      watch: 'The ratio UₜAₜ falls below 0.90: the Kalman filter leans more on its prior, and the SCF interval, which undoes that lean, widens more than the Kalman one.',
      apply: { sw: 1 },
    },
    {
      id: 'asymptotic',
      name: 'tick asymptotic SCF and show t = 1',
      move: 'Tick “asymptotic SCF (IV-B)” and move “Time shown t” to 1.',
      watch: 'The asymptotic SCF uses the steady ratio R̄ = 0.9 from the start: at t = 1 its interval is narrower than the recursive SCF’s; by t = 50 the two coincide (play t to see the recursion converge).',
      apply: { asym: true, time: 1 },
    },
  ],
  'scf-robots': [
    {
      id: 'alpha-up',
      name: 'raise α to 0.999',
      move: 'Raise the “Probability level α” slider to 0.999.',
      watch: 'At t = 36 the Kalman regions of the two robots, predicted for t + τ = 40, grow but still do not meet: no warning at any level. The SCF regions overlap: collision warning.',
      apply: { alpha: 0.999 },
    },
    {
      id: 'ordinary',
      name: 'untick rare realization',
      move: 'Untick “rare realization”: an ordinary run, not one drawn towards the collision.',
      watch: 'On this run the robots pass about 2 apart and neither filter warns at t = 36: the SCF’s larger regions do not warn when there is nothing to warn of.',
      apply: { rare: false },
    },
    {
      id: 'no-lookahead',
      name: 'set τ to 0 and show t = 40',
      move: 'Set “Steps ahead τ” to 0 and move “Time shown t” to 40.',
      watch: 'Without look-ahead the SCF warns only at the collision itself, t = 40 — with τ = 4 it warned at t = 36, in time to brake. The Kalman regions still do not meet.',
      apply: { tau: 0, time: 40 },
    },
  ],
  'scf-robots-literal': [
    {
      id: 'ordinary',
      name: 'untick rare realization',
      move: 'Untick “rare realization”: an ordinary run, not one drawn towards the collision.',
      watch: 'On this run the robots pass about 2 apart and neither filter warns at t = 36.',
      apply: { rare: false },
    },
    {
      id: 'no-lookahead',
      name: 'set τ to 0 and show t = 40',
      move: 'Set “Steps ahead τ” to 0 and move “Time shown t” to 40.',
      watch: 'Without look-ahead the SCF warns only at the collision itself, t = 40, four steps late; the Kalman regions, with this small process noise, stay far apart.',
      apply: { tau: 0, time: 40 },
    },
  ],

  // ----- LSCR (Weyer, Campi) -----
  'lscr-predict': [
    {
      id: 'q-up',
      name: 'raise q to 4',
      move: 'Raise “q” from 2 to 4 (M = 80 stays).',
      watch: 'The guaranteed level 1 − 2qn/M falls from 90 % to 80 %, and the region shrinks.',
      apply: { 'l-q': 4 },
    },
    {
      id: 'fewer-strings',
      name: 'set M to 40 and q to 1',
      move: 'Set “M” to 40 and “q” to 1: the same level 1 − 2qn/M = 90 % from half the sign strings.',
      watch: 'The region’s boundary is made of fewer pieces (coarser) and the region is larger: more strings buy a tighter region at the same level.',
      apply: { 'l-M': 40, 'l-q': 1 },
    },
    {
      id: 'far-state',
      name: 'fix the true state at 0.35 1.1',
      move: 'Tick “fix the true state at the estimated time” with “true state x̄” = 0.35 1.1, far from the prior mean 0.',
      watch: 'The data are drawn given this state: the Kalman ellipse (dashed), pulled towards the prior, misses it; the LSCR region still holds it (✓ inside).',
      apply: { 'l-xbar': '0.35 1.1', 'l-fix': true },
    },
    {
      id: 'noisier',
      name: 'raise σv² to 0.05',
      move: 'Raise “Noise σᵥ²” from 0.005 to 0.05.',
      watch: 'The data vary more and the LSCR region grows several-fold in area — although LSCR never reads the variance — and it still holds the true state.',
      apply: { 'l-sv': 0.05 },
    },
  ],
  'lscr-smooth': [
    {
      id: 'predict',
      name: 'predict instead of smooth',
      move: 'Set “Estimate” to “predict xₜ₊₁”.',
      watch: 'From the same 30 data the region for x₃₁ is several times larger than the smoothed region for x₁₅: data on both sides of a state pin it down.',
      apply: { 'l-estimate': 'predict' },
    },
    {
      id: 'index-end',
      name: 'smooth x₂₉',
      move: 'Set “Index i” to 29, next to the end of the record.',
      watch: 'x₂₉ has a single measurement after it: the region opens into an unbounded band (the numbers name its direction). x₁₅, with data on both sides, had a bounded one.',
      apply: { 'l-index': 29 },
    },
    {
      id: 'q-up',
      name: 'raise q to 4',
      move: 'Raise “q” from 2 to 4.',
      watch: 'The guaranteed level 1 − 2qn/M falls from 90 % to 80 %, and the region shrinks.',
      apply: { 'l-q': 4 },
    },
  ],
  'lscr-ma1': [
    {
      id: 'ordinary-state',
      name: 'untick fix the true state',
      move: 'Untick “fix the true state at the estimated time”: x₂₁ is drawn from its own law, near the prior mean 0.',
      watch: 'Now the Kalman ellipse holds the true state too: it is right on average over the states, not at a state fixed far out like (1, 1.2).',
      apply: { 'l-fix': false },
    },
    {
      id: 'along-band',
      name: 'move the true state to 3 3.2',
      move: 'Change “true state x̄” to 3 3.2: further out, along the band’s direction (1, 1).',
      watch: 'The LSCR band still holds it — the data cannot determine the state along (1, 1), and the band says so — while the Kalman ellipse misses it by more.',
      apply: { 'l-xbar': '3 3.2' },
    },
    {
      id: 'filter',
      name: 'filter instead of predict',
      move: 'Set “Estimate” to “filter xₜ”.',
      watch: 'σ_w² = 0, so y₂₀ is x₂ at t = 20 exactly: the data say far more about x₂₀ than about x₂₁, and the band narrows to a thin strip (its area drops more than tenfold), still holding the state — LSCR is never told σ_w² = 0.',
      apply: { 'l-estimate': 'filter' },
    },
  ],

  // ----- GLLS (Gubarev, Mishchenko) -----
  'glls-saturate': [
    {
      id: 'past-best',
      name: 'move the horizon s to 20',
      move: 'Move the “Horizon s” slider past the best horizon, from 8 to 20.',
      watch: 'σ₃(Γ) has saturated — it barely grows — while the noise grows like √s, so σₙ/√s falls below its peak at s = 8 (Fig. 2) and κ for x(k − s) barely improves.',
      apply: { 'g-s': 20 },
    },
    {
      id: 'short',
      name: 'move the horizon s to 3',
      move: 'Move the “Horizon s” slider down to 3.',
      watch: 'Four measurements condition x(k − s) badly: κ grows several-fold and the guaranteed ball around x̂(k) widens with it.',
      apply: { 'g-s': 3 },
    },
    {
      id: 'worst',
      name: 'worst-case noise',
      move: 'Set “Noise δ” to “worst case”: ‖δ(j)‖ = μ, aligned with the estimator’s gain.',
      watch: 'The error ‖x̂ − x‖ grows more than tenfold, yet the truth stays inside the guaranteed box, on its edge: the box is tight.',
      apply: { 'g-noise': 'worst' },
    },
    {
      id: 'gaussian',
      name: 'Gaussian noise',
      move: 'Set “Noise δ” to “Gaussian”: N(0, Ω), whose σ = 0.1 equals μ.',
      watch: 'Gaussian noise is not bounded by μ, and the guaranteed box misses the truth: the guarantee holds only while ‖δ(j)‖ ≤ μ.',
      apply: { 'g-noise': 'gaussian' },
    },
  ],
  'glls-grow': [
    {
      id: 'longer',
      name: 'move the horizon s to 20',
      move: 'Move the “Horizon s” slider from 8 to 20.',
      watch: 'Both σ’s grow without bound: κ for the past state x(k − s) falls more than tenfold, but κ for the current state x(k) hardly moves — carrying the estimate forward through the unstable Aˢ gives the gain back.',
      apply: { 'g-s': 20 },
    },
    {
      id: 'best',
      name: 'tick best horizon',
      move: 'Tick “best horizon (Fig. 2)”.',
      watch: 'σₙ/√s is still rising at the end of the curves, so the best horizon lies beyond the data: s goes to the longest the data allow, s = k = 39.',
      apply: { 'g-auto': true },
    },
    {
      id: 'rounding',
      name: 'set the data length to 80',
      move: 'Set “Data length k + 1” to 80.',
      watch: 'x(79) is so large that double precision loses what κ promises: the alarm “Rounding dominates” appears.',
      apply: { 'g-steps': 80 },
    },
  ],
  'glls-mixed': [
    {
      id: 'short',
      name: 'move the horizon s to 3',
      move: 'Move the “Horizon s” slider to 3.',
      watch: 'Over four measurements σ₃(Γ₄) is tiny: κ for x(k − s) grows more than a hundredfold and the guaranteed ball balloons.',
      apply: { 'g-s': 3 },
    },
    {
      id: 'p1',
      name: 'keep one singular value',
      move: 'Set “Kept σ’s p” to 1.',
      watch: 'Only the largest singular value is kept: the regularized κ drops — the price is that only the state’s projection on one direction is estimated.',
      apply: { 'g-p': 1 },
    },
    {
      id: 'worst',
      name: 'worst-case noise',
      move: 'Set “Noise δ” to “worst case”.',
      watch: 'The noise aligned with the gain makes the error ‖x̂ − x‖ several times larger, and the truth still lies in the guaranteed ball.',
      apply: { 'g-noise': 'worst' },
    },
  ],
  'glls-unstable5': [
    {
      id: 'too-short',
      name: 'move the horizon s to 2',
      move: 'Move the “Horizon s” slider to 2.',
      watch: 'The page refuses it and says why: Γ₃ has rank 3 < n = 5 — five states need at least five measurements, s ≥ 4. The last picture stays.',
      apply: { 'g-s': 2 },
    },
    {
      id: 'whole',
      name: 'move the horizon s to 15',
      move: 'Move the “Horizon s” slider to 15, the whole record.',
      watch: 'The unstable mode (eigenvalue 3.06) inflates σ₁(Γ) past 10⁶ and the rounding estimate grows a thousandfold: every step on an unstable system costs digits.',
      apply: { 'g-s': 15 },
    },
  ],

  // ----- Uniform innovations (Pavelková) -----
  'uniform-paper': [
    {
      id: 'theta-known',
      name: 'Θ known',
      move: 'Set “Method” to “states — Θ known”.',
      watch: 'With the true Θ, C·A = 0.5·C: the optimal face of x₁₂₀ opens into a segment (the face ranges), since the data cannot tell x₁ from x₂. Swapping’s Θ̂ had collapsed it to a point — not a better one: the RMS state error falls.',
      apply: { 'u-estimator': 'states' },
    },
    {
      id: 'window',
      name: 'set the window ∂ to 20',
      move: 'Set “Window length ∂” to 20.',
      watch: 'Θ̂ is fitted on 20 samples instead of 5: the LP’s RMS state error falls by about half — still above the Kalman filter’s, which knows Θ.',
      apply: { 'u-window': 20 },
    },
    {
      id: 'tight-bounds',
      name: 'lower the half-width bounds to 0.05',
      move: 'Lower “x̄ᵣ” and “ȳᵣ”, the bounds on the half-widths, to 0.05 — below the true 0.3.',
      watch: 'No half-widths within the bounds fit the data: the LP is infeasible and the bounds are doubled, again and again (“half-width bounds extended” counts it).',
      apply: { 'u-xrmax': '0.05', 'u-yrmax': '0.05' },
    },
    {
      id: 'wrong-bound',
      name: 'Θ known, ȳr bound 0.1',
      move: 'Set “Method” to “states — Θ known” and lower “ȳᵣ” to 0.1, below the true 0.3.',
      watch: 'The polygon is now computed with the true Θ, yet it misses the true x₁₂₀: its guarantee needs bounds at least the true half-widths.',
      apply: { 'u-estimator': 'states', 'u-yrmax': '0.1' },
    },
  ],

  // ----- Unknown-but-bounded noise (Tempo) -----
  'ubb-track': [
    {
      id: 'tau-low',
      name: 'lower τ to 0.05',
      move: 'Lower “τ” (the process-noise bound) to 0.05, below the simulated 0.1.',
      watch: 'The bounds are wrong, so the guarantee is gone: the truth leaves the set at some steps (“over the run” counts them).',
      apply: { 'b-tau': 0.05 },
    },
    {
      id: 'eps-low',
      name: 'lower ε to 0.1',
      move: 'Lower “ε” to 0.1, below the simulated measurement noise 0.2.',
      watch: 'The data contradict the bounds: no state is consistent with them, and the page says so by ε — a wrong bound can be caught by the data.',
      apply: { 'b-eps': 0.1 },
    },
    {
      id: 'all-data',
      name: 'window of all 60 steps',
      move: 'Type 60 in “Window”: all the data instead of Theorem 5’s j + 1 = 30 steps.',
      watch: 'The set at k = 40 stays the same (its radius to 3 digits) while the LP grows: the data older than the window add less than γ = 0.1 — Theorem 5.',
      apply: { 'b-window': '60' },
    },
    {
      id: 'at-bound',
      name: 'noise at the bound',
      move: 'Tick “noise at the bound”: every noise sample is ± its bound.',
      watch: 'The set still holds the truth at every step, and it is smaller at k = 40: noise at its bounds pins the state more tightly.',
      apply: { 'b-noise': true },
    },
  ],
  'ubb-series': [
    {
      id: 'more-data',
      name: 'move step k to 29',
      move: 'Move the “Step k” slider from 9 to 29.',
      watch: 'Thirty data instead of ten: the set of coefficients a shrinks (its radius falls several-fold) and still holds the true a; the prediction interval of the next value narrows.',
      apply: { 'b-time': 29 },
    },
    {
      id: 'eps-low',
      name: 'lower ε to 0.4',
      move: 'Lower “ε” to 0.4, below the bound 0.5 of the data’s noise.',
      watch: 'No coefficients fit the data within ±0.4: the page says so by ε.',
      apply: { 'b-eps': 0.4 },
    },
    {
      id: 'at-bound',
      name: 'noise at the bound',
      move: 'Tick “noise at the bound”: every |u(k)| = 0.5.',
      watch: 'The set collapses to the true a (radius 0): noise at its bounds pins the coefficients exactly.',
      apply: { 'b-noise': true },
    },
  ],
  'ubb-leontief': [
    {
      id: 'tau-low',
      name: 'lower τ to 0.05',
      move: 'Lower “τ” (the bound on the uncertain demand) to 0.05, below the simulated 0.1.',
      watch: 'The truth leaves the set at some steps (“over the run” counts them): the guarantee needs a true bound.',
      apply: { 'b-tau': 0.05 },
    },
    {
      id: 'gamma-up',
      name: 'raise γ to 0.2',
      move: 'Raise “γ” (Theorem 5’s accuracy) from 0.05 to 0.2.',
      watch: 'Theorem 5 allows a shorter window (j + 1 falls), a smaller LP; the set at k = 25 changes by less than γ.',
      apply: { 'b-gamma': 0.2 },
    },
    {
      id: 'eps-up',
      name: 'raise ε to 0.6',
      move: 'Raise “ε” to 0.6, twice the measurement error.',
      watch: 'A looser bound keeps the guarantee — the truth stays inside at every step — at the price of a larger set.',
      apply: { 'b-eps': 0.6 },
    },
  ],
  'ubb-markov': [
    {
      id: 'later',
      name: 'move step k to 10',
      move: 'Move the “Step k” slider from 2 to 10.',
      watch: 'The chain is absorbed into its first state: the set of distributions shrinks (its radius falls about threefold) — the uncertainty about x(0) is forgotten.',
      apply: { 'b-time': 10 },
    },
    {
      id: 'delta-tight',
      name: 'set δ to 0.1',
      move: 'Set “δ” to 0.1: x(0) known to ±0.1 on every component.',
      watch: 'The set shrinks — its radius about halves — and still holds the true distribution at every step.',
      apply: { 'b-delta': '0.1' },
    },
    {
      id: 'delta-wrong',
      name: 'set δ to 0.05',
      move: 'Set “δ” to 0.05: the true x(0) = (0.1, 0.5, 0.4) is then outside the assumed box (0.5 vs 0.4 ± 0.05).',
      watch: 'The truth leaves the set at some steps (“over the run” counts them): the guarantee is only as good as the bound.',
      apply: { 'b-delta': '0.05' },
    },
  ],

  // ----- Conformal prediction (Vovk et al.; Gibbs & Candès) -----
  'conformal-gaussian': [
    {
      id: 'more-calibration',
      name: 'raise N to 999',
      move: 'Raise “Calibration runs N” from 199 to 999.',
      watch: 'The promise’s upper bound α + 1/(N + 1) tightens from 90.5 % to 90.1 %, and the conformal radius² moves closer to the χ² one (4.61): under the law the filter assumes, the two agree.',
      apply: { 'cf-calibration': 999 },
    },
    {
      id: 'few-calibration',
      name: 'lower N to 19',
      move: 'Lower “Calibration runs N” to 19.',
      watch: 'The promise widens to 90 % ≤ P ≤ 95 %, and the radius² is the 18th smallest of only 19 scores: a coarse stand-in for the χ² radius.',
      apply: { 'cf-calibration': 19 },
    },
    {
      id: 'student-t',
      name: 'Student-t noise',
      move: 'Set “Noise law” to “Student-t” (ν = 3).',
      watch: 'At 90 % the heavy tails do not show yet: with the same variance, the Student-t puts more mass near the centre, and the conformal radius² falls below the χ² one.',
      apply: { 'cf-noise': 'student_t' },
    },
  ],
  'conformal-heavy': [
    {
      id: 'gaussian',
      name: 'Gaussian noise',
      move: 'Set “Noise law” to “Gaussian”.',
      watch: 'The conformal radius² falls from about 15 to about the χ² one (9.2): calibrated on the law the filter assumes, conformal finds the Kalman radius.',
      apply: { 'cf-noise': 'gaussian' },
    },
    {
      id: 'fewer',
      name: 'lower N to 199',
      move: 'Lower “Calibration runs N” from 999 to 199.',
      watch: 'At 99 % the radius² is now the 198th smallest of 199 scores — one of the two largest — and jumps several-fold: few runs sample the heavy tail thinly. The upper bound loosens to 99.5 %.',
      apply: { 'cf-calibration': 199 },
    },
    {
      id: 'nu-up',
      name: 'raise ν to 10',
      move: 'Raise “ν” from 2.5 to 10: lighter tails.',
      watch: 'The conformal radius² falls towards the χ² one but stays above it: the tails are lighter, not gone.',
      apply: { 'cf-nu': 10 },
    },
    {
      id: 'level-down',
      name: 'lower α to 0.90',
      move: 'Lower the “Probability level α” slider from 0.99 to 0.90.',
      watch: 'Now the conformal radius² is below the χ² one: the Student-t with the model’s variance is narrower in the middle and wider only in the far tail, which 99 % reaches and 90 % does not.',
      apply: { 'cf-alpha': 0.9 },
    },
  ],
  'conformal-far': [
    {
      id: 'level-up',
      name: 'raise α to 0.95',
      move: 'Raise the “Probability level α” slider from 0.90 to 0.95.',
      watch: 'Both regions now hold the far-out state (6, −2) on this record: its score lies just above both 90 % radii² and below the 95 % ones. Run the study to see how often each holds it over many records.',
      apply: { 'cf-alpha': 0.95 },
    },
    {
      id: 'seed',
      name: 'set the seed to 4',
      move: 'Set “Seed” to 4: another record through the same state (6, −2) at t = 30.',
      watch: 'On this record both regions hold it; on the preset’s, both missed. At a fixed state neither promise says how often: the study’s fixed-state counts do.',
      apply: { 'cf-seed': 4 },
    },
    {
      id: 'later',
      name: 'move t to 60',
      move: 'Move “Target time t” to 60: the record is fixed at (6, −2) at t = 30 only.',
      watch: 'At t = 60 the state is an ordinary one again, and both regions hold it.',
      apply: { 'cf-time': 60 },
    },
  ],
  'conformal-aci-drift': [
    {
      id: 'gamma-up',
      name: 'raise γ to 0.05',
      move: 'Raise “ACI step γ” from 0.01 to 0.05.',
      watch: 'ACI follows the drift faster: its worst 50-step window rises from 78 % to 84 %, its long-run coverage nears 90 %, and its bound tightens from 0.23 to 0.05. The Kalman interval stays near 66 %.',
      apply: { 'cf-gamma': 0.05 },
    },
    {
      id: 'gamma-down',
      name: 'lower γ to 0.001',
      move: 'Lower “ACI step γ” to 0.001.',
      watch: 'ACI adapts too slowly for this drift: its coverage falls to 84 % and its worst window to 68 %, and its bound, above 1, promises nothing on 400 steps.',
      apply: { 'cf-gamma': 0.001 },
    },
    {
      id: 'level-up',
      name: 'raise α to 0.95',
      move: 'Raise the “Probability level α” slider to 0.95.',
      watch: 'ACI’s interval follows to about 93 % of the steps with an interval; the Kalman interval, too narrow once the noise has grown, covers 74 %.',
      apply: { 'cf-alpha': 0.95 },
    },
  ],

  // ----- Compare every method -----
  'compare-gaussian': [
    {
      id: 'alpha-up',
      name: 'raise α to 0.99',
      move: 'Raise “α” to 0.99.',
      watch: 'The Kalman ellipse grows — and still misses the far-out state: a higher level does not fix a promise made on average. SCF and LSCR hold it.',
      apply: { 'c-alpha': 0.99 },
    },
    {
      id: 'prior-state',
      name: 'untick fix the true target state',
      move: 'Untick “fix the true target state”: the record is drawn from the model’s own law.',
      watch: 'The true x₃₁ is now an ordinary one, near the mean 0, and the Kalman ellipse holds it too: on average is all it promises.',
      apply: { 'c-fix': false },
    },
    {
      id: 'tight-bounds',
      name: 'bounds × 0.5',
      move: 'Move “Bounds given to the set-membership methods” to × 0.50.',
      watch: '“Always, while the bounds hold” fails: Tempo finds no state consistent with the data and the uniform LP’s set misses x₃₁; their rows say the bounds are 0.5× the noise’s own.',
      apply: { 'c-scale': 0.5 },
    },
  ],
  'compare-uniform': [
    {
      id: 'tight-bounds',
      name: 'bounds × 0.5',
      move: 'Move “Bounds given to the set-membership methods” to × 0.50.',
      watch: 'Tempo’s and the LP’s assumption is no longer met (✗): Tempo finds no state consistent with the data, and the LP’s set misses the truth.',
      apply: { 'c-scale': 0.5 },
    },
    {
      id: 'loose-bounds',
      name: 'bounds × 2',
      move: 'Move “Bounds given to the set-membership methods” to × 2.00.',
      watch: 'Loose but true bounds keep the guarantee: Tempo’s set still holds x₃₁, and is several times larger.',
      apply: { 'c-scale': 2 },
    },
    {
      id: 'gaussian',
      name: 'Gaussian noise',
      move: 'Set “Noise law” to “Gaussian”.',
      watch: 'The “assumes” column turns over: the Kalman filter’s and SCF’s assumption is now met (✓ met), Tempo’s bounded noise is not (Gaussian noise is unbounded).',
      apply: { 'c-noise': 'gaussian' },
    },
  ],
};
