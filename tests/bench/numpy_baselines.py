#!/usr/bin/env python3
"""NumPy (+ SciPy/HiGHS for the LPs) baselines of the five kernels that tests/bench/speed.rs
times natively (`cargo bench --bench speed -- kernels`, src/bench.rs) and in wasm, so that a
benchmark can print native vs wasm vs NumPy side by side.

Run (from the repository root):

    python3 -m venv target/bench-venv
    target/bench-venv/bin/pip install -r tests/bench/requirements.txt
    target/bench-venv/bin/python tests/bench/numpy_baselines.py             # all five, ~25 s
    target/bench-venv/bin/python tests/bench/numpy_baselines.py --only ubb_step

Each kernel prints one line `BENCH <key> <median ms> <what ran>`: the median of REPS (= 7)
timed repetitions after one untimed warm-up, in milliseconds (the Rust takes 11). The free text
starts with the same summary as src/bench.rs's line for that kernel (so the reader sees the
same work ran), then what is NumPy's own. Python 3 stdlib + numpy + scipy only. numpy's BLAS
is pinned to one thread (the Rust kernels run on one), unless OPENBLAS_NUM_THREADS etc. are set.

Vectorisation: as simdkalman runs a Kalman filter over many series, the Monte Carlo keeps all
runs side by side (runs × state arrays) and advances them together with matmul/einsum; the
Python loops are over time steps, the functions of a group, the 501 factor updates of the GLLS
curves (each depends on the last) and the LP calls. What the Rust prepares outside its timed
closure (the preset's run, the model) is prepared outside here too.

What each kernel is, and what is and is not the same as the Rust
----------------------------------------------------------------
Common: random numbers come from numpy's PCG64 (np.random.default_rng with the preset's
seed), not ChaCha8, so every simulated data set, realisation and random matrix is a different
draw from the same law as the Rust's: counts and figures agree statistically, not bit for bit.
The LPs are solved by HiGHS through scipy.optimize.linprog(method="highs"), one call per LP
(simplex or IPM with crossover: it returns a vertex); the Rust uses clarabel (interior point,
no crossover: a point near the middle of an optimal face), loaded once per feasible set and
re-solved with new objectives. Where an optimum is not unique, the point returned differs.

1. robot_mc -- SCF paper Section II-B, preset scf-robots (src/scenario/scf.rs robots(),
   src/scf/experiment.rs ConditionalExperiment). Timed like the Rust kernel: the experiment's
   setup (moments, backward innovations model, Kalman gains, the regions at t_c = 40 and the
   warning's τ = 4 prediction and regions; the Rust's conditional_experiment()) and its 10,000
   runs: per run the measurements y_40 … y_1 are drawn from their exact law given x_40 = x_c by
   the innovations form of the backward representation (45) (q = 4 normals a step, as the
   Rust), the forward Kalman filter runs t = 1..40 (n = 8), and the counts are taken: robot A's
   state x_c[0:4] inside X^KF_40 and X^SCF_40 (α = 0.95, χ²(4)), and the collision warnings
   issued at t = 36 for t = 40 (the same planar ellipse distance: 36-point grid + 32
   golden-section steps, the same disc exits). Outside the timing, as the Rust's
   prepare_scf(): the model and x_c (the most probable state with the robots 0.1 apart).
   Same: model, algorithm, work per run. Different: the random stream; the Rust splits the
   model into the two independent robots and pads each to fixed 4×2 blocks, here the full
   8×8 / 8×4 matrices multiply all runs at once. KF count: the Rust prints 0/10000 (paper 0);
   here 3/10000 (0–9 over seeds 1–6; a state-space backward sampler gives the same rate,
   ~4e-4): a tail event of a few in 10,000. SCF 9509 (Rust ~9500, paper 9498).

2. lscr_raster -- LSCR paper Fig. 1, preset lscr-predict (src/lscr.rs, src/sets/
   sign_region.rs): X = ∩_l {x : ≥ q of g_{l,i}(x) > 0 and ≥ q < 0} for n = 2 groups of
   M − 1 = 79 affine functions (h_0 = 0 is neither > 0 nor < 0), q = 2, at 512 × 512 pixel
   centres. The region is built as the Rust builds it (backward representation, Q″ by the
   chain recursion, Karhunen–Loève basis with the sign rule, thin SVD of A through QR, 79
   distinct random 30-bit strings, c and d of point 4) but from data simulated here (seed 5)
   and numpy-drawn strings (seed 1): a different draw of the same construction. The window is
   fitted like fit_window, approximately (the region's extent from 512² rasters of a growing
   search box instead of the exact boundary polygons, ∪ the BLUE ellipse box, padded 8 %).
   Timed: the raster only, with the Rust's algorithm, O(rows·(N + columns)): a root column
   per function and row, counted with difference arrays, vectorised over functions and rows
   (without the Rust's exact search near the roots, so pixels within rounding of a line could
   differ: the number that differ from the brute force is printed). The free text also times
   the brute force vectorised over pixels (every function at every pixel as c − (d0·x + d1·y),
   the Rust's eval2), which is 4× slower.

3. glls_curves -- GLLS paper Figs. 1–2 (src/glls.rs Curves::new): for s = 0..500,
   log10 σ_i(Γ_{s+1}) (rows C A^p), log10 σ_i(Γ_{s+1}A^{−s}), the floor ε·σ_1·√(m(s+1)),
   κ_LLS(s,k), κ_GLLS(s,k−s), κ_GLLS(s,k) for n = 10, m = 2, A uniform(−0.5, 0.5) scaled to
   spectral radius 1.02, C uniform(−0.5, 0.5), Ω = 0.01·I (isotropic: the GLLS κ are the LLS
   ones, the Rust's fast path; the non-isotropic branch is not ported). The same scaled-factor
   updates (R of [e^ρ R; e^β C A^s], renormalised; R' ← R'A^{−1}, then C appended; A^s kept as
   e^ρ P; κ_LLS = −log10 σ'_n unless σ'_n is lost 12 decades under σ'_1, then ‖A^s R^{−1}‖₂),
   each update one numpy QR (mode "r") of the 12×10 stack where the Rust folds rows in by
   Givens rotations, and the 2 × 501 SVDs of the 10×10 factors (and the direct κ) batched.
   Different: the random A and C (numpy stream).

4. ubb_step -- Tempo Section IV, preset ubb-track (src/ubb.rs StateProblem::step,
   StateStep::hull_and_polygon, src/sets/support_polygon.rs): x(k+1) = A x + B u,
   y = C x + η, |u| ≤ 0.1, |η| ≤ 0.2, |x_i(0)| ≤ 2, α = β = 50, window j + 1 = 30 (Theorem 5,
   γ = 0.1), step k = 40 of a 60-step simulation. Timed as the Rust: building the step's LP
   (stage-wise unknowns e(11..41), u(11..40): 92 variables; 184 rows = 60 equalities of the
   dynamics + 124 inequalities: the smoothed l∞ measurement and noise bounds and the Theorem 4
   box of the window's first state -- the Rust's sizes), then the interval hull of x(41)
   (2r = 4 LPs) and the exact polygon of (x1, x2)(41) by the same support-point refinement
   (budget 64, relative tolerance 1e-7). Different: the simulated data (numpy stream), hence
   the LP data and the number of polygon LPs; HiGHS from scratch per LP.

5. uniform_report -- Pavelková's example, preset uniform-paper (src/uniform.rs,
   src/scenario/uniform.rs), the FULL report as the Rust times it (s.run()): simulate 120
   samples; the on-line swapping estimator, window ∂ = 5 (per step the state LP (6)–(10), 15
   variables, 30 rows + bounds, then the parameter LP (11)–(12), 12 variables, 30 rows, both
   doubling the half-width bounds while infeasible); then the window at t = 120: its state LP,
   the ranges of its 12 states and 3 half-widths over the optimal face (30 LPs), the polygon of
   x_120 consistent with the window at the half-width bounds (budget 64) and the Kalman filter
   with the uniform variances. Same algorithm and LP sizes. Different: the data (numpy stream),
   and the optimum picked on the non-unique optimal faces (the example is not observable,
   C·A = 0.5·C): HiGHS returns a vertex (far along x1 − x2, in the ±5 box) where clarabel
   returns a central point, and the swapping feeds that point to the parameter LP, so the Θ̂
   track and the RMS state error differ from the Rust's (here LP 0.86 vs KF 0.22). Variable
   bounds go to HiGHS as bounds; the Rust turns the finite ones into rows. The free text also
   gives one window LP (∂ = 5, t = 116..120, the true Θ), like speed.rs.

Measured (target/bench-venv: numpy 2.4.6, scipy 1.17.1, OpenBLAS 0.3.31 on one thread,
Python 3.11.7; 2-core machine while another process kept both cores busy, so the times are
noisy: the previous full run in brackets), medians in ms, total run time 18 s:
    robot_mc        139.5 [155.5]  (setup ~11 of it; KF 3, SCF 9509; warnings KF 0, SCF 10000)
    lscr_raster     153.7 [210.0]  (25135 of 262144 pixels inside; root/diff-array 40.0 [41.7])
    glls_curves      96.7 [100.1]  (log10 σ_n(Γ_501) = −0.578)
    ubb_step        200.8 [225.0]  (92 variables, 184 rows; 4 + 32 LPs)
    uniform_report 1156.9 [1502.4] (283 LPs per report; one window LP 2.9 [3.1])
"""

import argparse
import math
import os
import sys
import time

# The Rust kernels run on one thread; pin numpy's BLAS to one thread too (like for like, and on
# a loaded 2-core machine OpenBLAS's spinning threads made the Monte Carlo 8x slower). Set
# OPENBLAS_NUM_THREADS yourself to override.
for _v in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import numpy as np  # noqa: E402
import scipy.linalg as sla  # noqa: E402
from scipy.optimize import linprog  # noqa: E402
from scipy.stats import chi2  # noqa: E402

REPS = 7
EPS = np.finfo(float).eps


def median_ms(fn, reps=REPS):
    """One untimed warm-up, then the median of `reps` timed calls, in ms; returns (ms, last)."""
    out = fn()
    ts = []
    for _ in range(reps):
        t0 = time.perf_counter()
        out = fn()
        ts.append((time.perf_counter() - t0) * 1e3)
    ts.sort()
    return ts[len(ts) // 2], out


def sym(m):
    return 0.5 * (m + m.swapaxes(-1, -2))


def lyapunov(f, v):
    """Γ = F Γ Fᵀ + V (stable F)."""
    return sym(sla.solve_discrete_lyapunov(f, v))


def block_diag(a, b):
    return sla.block_diag(a, b)


# ---------------------------------------------------------------------------------------------
# 1. robot_mc


DELTA, KP, KU, D_MIN, T_C = 1.0 / 20.0, 5.0, 5.0, 0.2, 40


def robot_model():
    """src/scenario/scf.rs robot_model(NoiseReading::Unscaled)."""
    f1 = np.array([[1, 0, DELTA, 0], [0, 1, 0, DELTA],
                   [-KP * DELTA, 0, 1 - KU * DELTA, 0], [0, -KP * DELTA, 0, 1 - KU * DELTA]])
    f = block_diag(f1, f1)
    va = np.diag([0.01**2, 0.01**2, 0.04**2, 0.04**2])
    vb = np.diag([0.01**2, 0.01**2, 0.1**2, 0.04**2])
    v = block_diag(va, vb)
    h1 = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
    h = block_diag(h1, h1)
    w = np.eye(4) * 0.05**2
    u = np.array([0, 0, KP * -1.0 * DELTA, 0, 0, 0, KP * 1.0 * DELTA, 0])  # B = I
    x1 = np.array([-1.0, 20, 0, 0, 1, 20, 0, 0])
    return f, h, v, w, u, x1, np.zeros((8, 8))


def moments(f, v, bu, x1, g1, steps):
    """m_t, Γ_t for t = 1..steps (index t−1)."""
    n = len(x1)
    mean, cov = np.empty((steps, n)), np.empty((steps, n, n))
    m, g = x1.copy(), g1.copy()
    for t in range(steps):
        mean[t], cov[t] = m, g
        m = f @ m + bu
        g = sym(f @ g @ f.T + v)
    return mean, cov


def kalman_gains(f, h, v, w, p1, steps):
    """K_t, P_t (Joseph form), t = 1..steps."""
    n = f.shape[0]
    ks, ps = [], []
    pp = p1.copy()
    for _ in range(steps):
        s = sym(w + h @ pp @ h.T)
        k = np.linalg.solve(s, h @ pp).T
        ikh = np.eye(n) - k @ h
        p = sym(ikh @ pp @ ikh.T + k @ w @ k.T)
        ks.append(k)
        ps.append(p)
        pp = sym(f @ p @ f.T + v)
    return np.array(ks), np.array(ps)


def collision_state(mean, cov, t, a, b, dist):
    """most_probable_collision_state: 3600-point grid on the circle of radius `dist`."""
    n = mean.shape[1]
    c = np.zeros((2, n))
    for k in range(2):
        c[k, a[k]] += 1
        c[k, b[k]] -= 1
    m, g = mean[t - 1], cov[t - 1]
    mu, sig = c @ m, c @ g @ c.T
    si = np.linalg.inv(sig)
    th = 2 * np.pi * np.arange(3600) / 3600
    d = np.stack([dist * np.cos(th), dist * np.sin(th)], 1) - mu
    best = th[np.argmin(np.einsum("ki,ij,kj->k", d, si, d))]
    delta = np.array([dist * np.cos(best), dist * np.sin(best)])
    return m + g @ c.T @ si @ (delta - mu)


class Region:
    """MovingRegion: centre m + A(x̂[idx] − m), inside iff eᵀ S e ≤ 1 (S = shape⁻¹/r²)."""

    def __init__(self, idx, m, a, shape, r2):
        self.idx, self.m, self.a = list(idx), m[list(idx)], a
        self.s_inv = np.linalg.inv(shape) / r2
        self.s = r2 * sym(shape)  # planar: radius2·cov
        ev = np.linalg.eigvalsh(sym(shape))
        self.axes = (math.sqrt(r2 * ev.max()), math.sqrt(r2 * max(ev.min(), 0.0)))

    def centres(self, xhat):  # xhat: runs × n
        return self.m + (xhat[:, self.idx] - self.m) @ self.a.T


def support(c, s, cs, sn):
    """Planar ellipse support at (cos θ, sin θ); c: runs × 2, cs/sn broadcastable."""
    q = s[0, 0] * cs * cs + 2 * s[0, 1] * cs * sn + s[1, 1] * sn * sn
    return c[..., 0] * cs + c[..., 1] * sn + np.sqrt(np.maximum(q, 0.0))


def ellipse_distance(ca, sa, cb, sb):
    """PlanarEllipse::distance for runs of centre pairs (runs × 2) and fixed shapes: the
    largest separating gap over directions θ, a 36-point grid then 32 golden-section steps on
    the bracket, all runs at once."""
    def gap(th):
        cs, sn = np.cos(th), np.sin(th)
        if th.ndim == 2:
            return -support(ca[:, None, :], sa, cs, sn) - support(cb[:, None, :], sb, -cs, -sn)
        return -support(ca, sa, cs, sn) - support(cb, sb, -cs, -sn)
    grid = 36
    step = 2 * np.pi / grid
    ths = np.arange(grid) * step
    g = gap(np.broadcast_to(ths, (ca.shape[0], grid)))  # runs × grid
    arg = ths[np.argmax(g, 1)]
    best = g.max(1)
    a, b = arg - step, arg + step
    r = 0.5 * (math.sqrt(5) - 1)
    x1, x2 = b - r * (b - a), a + r * (b - a)
    g1, g2 = gap(x1), gap(x2)
    for _ in range(32):
        left = g1 > g2
        # left: b = x2, x2 = x1, g2 = g1, x1 = b − r(b − a), g1 = gap(x1);
        # else: a = x1, x1 = x2, g1 = g2, x2 = a + r(b − a), g2 = gap(x2).
        b = np.where(left, x2, b)
        a = np.where(left, a, x1)
        nx1 = np.where(left, b - r * (b - a), x2)
        nx2 = np.where(left, x1, a + r * (b - a))
        gp = gap(np.where(left, nx1, nx2))
        g1, g2 = np.where(left, gp, g2), np.where(left, g1, gp)
        x1, x2 = nx1, nx2
    return np.maximum(np.maximum(np.maximum(best, g1), g2), 0.0)


def warns(ra, rb, xp, d):
    ca, cb = ra.centres(xp), rb.centres(xp)
    dc = np.hypot(ca[:, 0] - cb[:, 0], ca[:, 1] - cb[:, 1])
    out = dc - ra.axes[1] - rb.axes[1] < d  # inscribed discs closer than d: warn
    far = dc - ra.axes[0] - rb.axes[0] >= d  # circumscribed discs d apart: no warning
    todo = ~out & ~far
    if todo.any():
        out[todo] = ellipse_distance(ca[todo], ra.s, cb[todo], rb.s) < d
    return out


def robot_preset():
    """The preset (robots()): the model and the conditioning state x_c at t = 40."""
    model = robot_model()
    f, h, v, w, bu, x1, g1 = model
    mean, cov = moments(f, v, bu, x1, g1, T_C)
    return model, collision_state(mean, cov, T_C, [0, 1], [4, 5], D_MIN / 2)


def robot_setup(preset, runs=10_000):
    """ConditionalExperiment::new: moments, backward innovations model, Kalman gains, the
    regions at t_c and the warning's affine prediction and regions."""
    (f, h, v, w, bu, x1, g1), x_c = preset
    n, q = 8, 4
    alpha, tau, tw, comps = 0.95, 4, 36, [0, 1, 2, 3]
    steps = T_C
    mean, cov = moments(f, v, bu, x1, g1, steps + tau)
    # Backward innovations model (backward_innovations): t = t_c..1 from Σ = 0.
    sigma = np.zeros((n, n))
    innov = [None] * T_C
    for t in range(T_C, 0, -1):
        s = sym(h @ sigma @ h.T + w)
        ls = np.linalg.cholesky(s)
        g = np.linalg.solve(s, h @ sigma).T
        plus = sym(sigma - g @ s @ g.T)
        if t >= 2:
            gp, gt = cov[t - 2], cov[t - 1]
            fb = gp @ f.T @ np.linalg.inv(gt)
            vb = sym(gp - fb @ gt @ fb.T)
            sigma = sym(fb @ plus @ fb.T + vb)
        else:
            fb = np.zeros((n, n))
        innov[t - 1] = (h, h @ mean[t - 1], ls, g, fb)
    ks, ps = kalman_gains(f, h, v, w, g1, steps + tau)
    r2c = chi2.ppf(alpha, len(comps))

    def region_pair(idx, t, m, pcov, r2):
        pk, gk = pcov[np.ix_(idx, idx)], cov[t - 1][np.ix_(idx, idx)]
        ratio = np.eye(len(idx)) - pk @ np.linalg.inv(gk)
        r_inv = np.linalg.inv(ratio)
        pi = sym(r_inv @ pk)
        return (Region(idx, m, np.eye(len(idx)), pk, r2), Region(idx, m, r_inv, pi, r2))

    cover = region_pair(comps, T_C, mean[T_C - 1], ps[T_C - 1], r2c)
    # Warning at t_w: x̂_{tw+τ|tw} = Φ x̂_tw + c; P predicted τ steps.
    phi, cst, pp = np.eye(n), np.zeros(n), ps[tw - 1]
    for _ in range(tau):
        phi, cst, pp = f @ phi, f @ cst + bu, sym(f @ pp @ f.T + v)
    tt = tw + tau
    r2 = chi2.ppf(alpha, 2)
    ka, sa = region_pair([0, 1], tt, mean[tt - 1], pp, r2)
    kb, sb = region_pair([4, 5], tt, mean[tt - 1], pp, r2)
    return dict(runs=runs, n=n, q=q, innov=innov, ks=ks, f=f, h=h, bu=bu, x1=x1, x_c=x_c,
                x_c_dev=x_c - mean[T_C - 1], cover=cover, tw=tw, phi=phi, cst=cst,
                warn=(ka, kb, sa, sb), seed=2021)


def robot_runs(S, rng):
    runs, n, q = S["runs"], S["n"], S["q"]
    z = rng.standard_normal((T_C, runs, q))
    # y_{t_c} … y_1 given x_{t_c} = x_c: the backward innovations filter, all runs at once.
    y = np.empty((T_C, runs, q))
    zhat = np.broadcast_to(S["x_c_dev"], (runs, n)).copy()
    for t in range(T_C, 0, -1):
        h, hm, ls, g, fb = S["innov"][t - 1]
        e = z[t - 1] @ ls.T
        y[t - 1] = hm + zhat @ h.T + e
        zhat = (zhat + e @ g.T) @ fb.T
    # Forward KF over the drawn measurements.
    f, h, bu, ks = S["f"], S["h"], S["bu"], S["ks"]
    xpred = np.broadcast_to(S["x1"], (runs, n)).copy()
    for t in range(1, T_C + 1):
        xhat = xpred + (y[t - 1] - xpred @ h.T) @ ks[t - 1].T
        if t == S["tw"]:
            at_tw = xhat
        xpred = xhat @ f.T + bu
    kf, scf = S["cover"]
    x_c = S["x_c"]
    inside = []
    for reg in (kf, scf):
        e = x_c[reg.idx] - reg.centres(xhat)
        inside.append(int(np.count_nonzero(np.einsum("ri,ij,rj->r", e, reg.s_inv, e) <= 1.0)))
    xp = at_tw @ S["phi"].T + S["cst"]
    ka, kb, sa, sb = S["warn"]
    kw = int(np.count_nonzero(warns(ka, kb, xp, D_MIN)))
    sw = int(np.count_nonzero(warns(sa, sb, xp, D_MIN)))
    return inside[0], inside[1], kw, sw


def bench_robot_mc():
    preset = robot_preset()  # outside the timing, like the Rust's prepare_scf()
    setup_ms, S = median_ms(lambda: robot_setup(preset))
    rng_seed = S["seed"]

    def experiment():
        # Timed like the Rust kernel: the experiment's setup (conditional_experiment()) and
        # its runs, a fresh stream of the same seed per repetition.
        E = robot_setup(preset)
        return robot_runs(E, np.random.default_rng(rng_seed))
    ms, (ki, si, kw, sw) = median_ms(experiment)
    r = S["runs"]
    return ms, (f"{r} runs x {T_C} steps; inside X^KF {ki}, X^SCF {si} (NumPy, batched over "
                f"runs; of which setup {setup_ms:.2f} ms; Rust/paper: KF 0, SCF ~9500 of 10000); "
                f"warnings at t=36: KF {kw} SCF {sw} (paper 2 and 10000)")


# ---------------------------------------------------------------------------------------------
# 2. lscr_raster


def lscr_region(t=30, m_strings=80, q=2, data_seed=5, string_seed=1):
    """The LSCR prediction region of lscr-predict, built as src/lscr.rs builds it."""
    f = np.array([[0.5, 0.0], [1.0, 0.7]])
    h = np.array([[0.0, 1.0]])
    g = np.array([[1.0], [0.0]])
    sv2 = sw2 = 0.005
    shape = g @ g.T
    n = 2
    # Simulated data y_1..y_t from the stationary process (numpy stream).
    rng = np.random.default_rng(data_seed)
    gam = lyapunov(f, shape * sv2)
    x = np.linalg.cholesky(gam + 1e-300 * np.eye(n)) @ rng.standard_normal(n)
    y = np.empty(t)
    lv = np.sqrt(sv2) * g[:, 0]
    for k in range(t):
        y[k] = h[0] @ x + math.sqrt(sw2) * rng.standard_normal()
        x = f @ x + lv * rng.standard_normal()
    # Backward representation with σ_v² = 1: F^b = Π′FᵀΠ′⁻¹, Q′ = Π′ − F^bΠ′F^bᵀ.
    pi = lyapunov(f, shape)
    fb = pi @ f.T @ np.linalg.inv(pi)
    qb = sym(pi - fb @ pi @ fb.T)
    # chain(h, F^b, offset 1, len t, P0 = Q′, S = Q′): Φ rows H F^b^{k+1}, Q″.
    phi = np.empty((t, n))
    row = h @ fb
    for k in range(t):
        phi[k] = row[0]
        row = row @ fb
    q2 = np.empty((t, t))
    p = qb.copy()
    for j in range(t):
        z = p @ h.T
        for k in range(j, t):
            v = (h @ z)[0, 0]
            q2[k, j] = q2[j, k] = v
            z = fb @ z
        p = sym(fb @ p @ fb.T + qb)
    # Karhunen–Loève: decreasing eigenvalues, each vector's largest entry positive.
    dv, u = np.linalg.eigh(sym(q2))
    order = np.argsort(-dv, kind="stable")
    dv, u = np.maximum(dv[order], 0.0), u[:, order]
    big = np.abs(u).argmax(0)
    u = u * np.where(u[big, np.arange(t)] < 0, -1.0, 1.0)
    a = u.T @ phi
    qq, rr = np.linalg.qr(a)
    ur, sing, _ = np.linalg.svd(rr)
    u_a = qq @ ur  # decreasing singular values
    # M − 1 distinct non-zero random strings of t bits.
    srng = np.random.default_rng(string_seed)
    seen, rows = set(), []
    while len(rows) < m_strings - 1:
        b = srng.integers(0, 2, t)
        key = b.tobytes()
        if b.any() and key not in seen:
            seen.add(key)
            rows.append(b)
    hs = np.array(rows, dtype=float)
    s = u.T @ y[::-1]
    cs = np.stack([hs @ (u_a[:, l] * s) for l in range(n)])  # groups × (M−1)
    ds = np.stack([hs @ (u_a[:, l, None] * a) for l in range(n)])  # groups × (M−1) × 2
    # BLUE ellipse at the joint level 1 − 2qn/M (for the window).
    lam = sv2 * dv + sw2
    info = a.T @ (a / lam[:, None])
    bcov = np.linalg.inv(info)
    bx = bcov @ (a.T @ (s / lam))
    level = 1 - 2 * q * n / m_strings
    half = np.sqrt(chi2.ppf(level, n) * np.diag(bcov))
    return cs, ds, q, (bx - half, bx + half)


def raster_brute(cs, ds, q, lo, hi, width, height, rows_per_block=16):
    """Bit l of excluded[r, j] set when pixel centre (r, j) is outside X_l (row 0 on top):
    every function of every group at every pixel, in blocks of rows (functions × rows ×
    columns, preallocated buffers), counted as uint8 sums of the sign masks."""
    dx, dy = (hi[0] - lo[0]) / width, (hi[1] - lo[1]) / height
    xs = lo[0] + (np.arange(width) + 0.5) * dx
    ys = hi[1] - (np.arange(height) + 0.5) * dy
    excluded = np.zeros((height, width), dtype=np.uint32)
    nf = cs.shape[1]
    vals = np.empty((nf, rows_per_block, width))
    mask = np.empty(vals.shape, dtype=bool)
    for l in range(cs.shape[0]):
        c = cs[l][:, None, None]
        dxs = ds[l, :, 0, None] * xs[None, :]  # functions × columns: d0·x
        for r0 in range(0, height, rows_per_block):
            rb = min(rows_per_block, height - r0)
            v, mk = vals[:, :rb], mask[:, :rb]
            dys = ds[l, :, 1, None] * ys[None, r0:r0 + rb]  # functions × rows: d1·y
            np.add(dxs[:, None, :], dys[:, :, None], out=v)
            np.subtract(c, v, out=v)  # c − (d0·x + d1·y), like the Rust's eval2
            np.greater(v, 0.0, out=mk)
            pos = mk.view(np.uint8).sum(0, dtype=np.uint8)
            np.less(v, 0.0, out=mk)
            neg = mk.view(np.uint8).sum(0, dtype=np.uint8)
            bad = (pos < q) | (neg < q)
            excluded[r0:r0 + rb] |= bad.astype(np.uint32) << np.uint32(min(l, 31))
    return excluded


def raster_roots(cs, ds, q, lo, hi, width, height):
    """The Rust raster's idea vectorised: per function and row the first column where g changes
    sign (from the root), counts by difference arrays. No exact search near the roots."""
    dx, dy = (hi[0] - lo[0]) / width, (hi[1] - lo[1]) / height
    x0 = lo[0]
    rows = np.arange(height)
    ys = hi[1] - (rows + 0.5) * dy
    excluded = np.zeros((height, width), dtype=np.uint32)
    for l in range(cs.shape[0]):
        c, d0, d1 = cs[l][:, None], ds[l, :, 0][:, None], ds[l, :, 1][:, None]
        with np.errstate(divide="ignore", invalid="ignore"):
            root = ((c - d1 * ys[None, :]) / d0 - x0) / dx - 0.5  # functions × rows
        k = np.clip(np.ceil(root), 0, width).astype(np.int64)
        k = np.where(np.isfinite(root), k, 0)
        pos = np.zeros((height, width + 1), dtype=np.int32)
        neg = np.zeros((height, width + 1), dtype=np.int32)
        rr = np.broadcast_to(rows[None, :], k.shape)
        dec = np.broadcast_to(d0 > 0, k.shape)  # decreasing along the row: + then −
        # d0 > 0: pos on [0, k), neg on [k, width); d0 < 0: neg on [0, k), pos on [k, width).
        np.add.at(pos, (rr[dec], k[dec]), -1)
        np.add.at(neg, (rr[dec], k[dec]), 1)
        np.add.at(neg, (rr[~dec], k[~dec]), -1)
        np.add.at(pos, (rr[~dec], k[~dec]), 1)
        pos[:, 0] += np.count_nonzero(d0 > 0)
        neg[:, 0] += np.count_nonzero(d0 < 0)
        pc = np.cumsum(pos[:, :width], 1)
        nc = np.cumsum(neg[:, :width], 1)
        bad = (pc < q) | (nc < q)
        excluded |= np.where(bad, np.uint32(1 << min(l, 31)), np.uint32(0))
    return excluded


def lscr_window(cs, ds, q, blue_box):
    """fit_window, approximately: the region's extent (the Rust takes it from the exact
    boundary polygons inside the box of every vertex of the arrangement; here from 512²
    rasters of a search box around the BLUE ellipse, grown until the region does not touch
    its border, within the vertex box) ∪ the BLUE box, padded 8 %."""
    c = cs.reshape(-1)
    d = ds.reshape(-1, 2)
    i, j = np.triu_indices(len(c), 1)
    det = d[i, 0] * d[j, 1] - d[i, 1] * d[j, 0]
    ok = np.abs(det) > 1e-12 * np.hypot(*d[i].T) * np.hypot(*d[j].T)
    i, j, det = i[ok], j[ok], det[ok]
    vx = (c[i] * d[j, 1] - c[j] * d[i, 1]) / det
    vy = (d[i, 0] * c[j] - d[j, 0] * c[i]) / det
    vlo, vhi = np.array([vx.min(), vy.min()]), np.array([vx.max(), vy.max()])
    w = np.maximum(vhi - vlo, 1e-12) * 0.01
    vlo, vhi = vlo - w, vhi + w
    mid, side = 0.5 * (blue_box[0] + blue_box[1]), blue_box[1] - blue_box[0]
    for grow in range(40):
        lo = np.maximum(mid - side * 2.0 ** grow, vlo)
        hi = np.minimum(mid + side * 2.0 ** grow, vhi)
        ex = raster_brute(cs, ds, q, lo, hi, 512, 512)
        inside = ex == 0
        touches = inside[0].any() or inside[-1].any() or inside[:, 0].any() or inside[:, -1].any()
        if inside.any() and not touches:
            break
    rr, cc = np.nonzero(inside)
    px = (hi - lo) / 512
    blo = np.array([lo[0] + cc.min() * px[0], hi[1] - (rr.max() + 1) * px[1]])
    bhi = np.array([lo[0] + (cc.max() + 1) * px[0], hi[1] - rr.min() * px[1]])
    blo, bhi = np.minimum(blo, blue_box[0]), np.maximum(bhi, blue_box[1])
    w = np.maximum(bhi - blo, 1e-12) * 0.08
    return blo - w, bhi + w


def bench_lscr_raster():
    cs, ds, q, blue_box = lscr_region()
    lo, hi = lscr_window(cs, ds, q, blue_box)
    ms, ex = median_ms(lambda: raster_brute(cs, ds, q, lo, hi, 512, 512))
    alt_ms, ex2 = median_ms(lambda: raster_roots(cs, ds, q, lo, hi, 512, 512))
    inside = int(np.count_nonzero(ex == 0))
    differ = int(np.count_nonzero((ex == 0) != (ex2 == 0)))
    # The faster of the two NumPy algorithms is the baseline (the Rust's row sweep too).
    return alt_ms, (f"512 x 512 pixels, {inside} inside (NumPy row sweep of roots and difference arrays, "
                    f"like the Rust's; lscr-predict's construction, t = 30, M = 80, q = 2, n = 2 groups x 79 "
                    f"functions, on numpy-simulated data; window x [{lo[0]:.3f}, {hi[0]:.3f}] y "
                    f"[{lo[1]:.3f}, {hi[1]:.3f}]); brute force vectorised over pixels {ms:.1f} ms, "
                    f"{differ} pixels differ between the two)")


# ---------------------------------------------------------------------------------------------
# 3. glls_curves


def glls_model(seed=1, n=10, m=2):
    rng = np.random.default_rng(seed)
    a = rng.random((n, n)) - 0.5
    a = a / np.abs(np.linalg.eigvals(a)).max() * 1.02
    c = rng.random((m, n)) - 0.5
    return a, c, np.eye(m) * 0.01


def _append(r, ls, block, lb):
    """ScaledFactor::append: the R of [e^ls R; e^lb block], renormalised (e^ls' R')."""
    c = max(ls, lb)
    top = r * math.exp(ls - c) if np.isfinite(ls) else r
    rn = np.linalg.qr(np.vstack([top, block * math.exp(lb - c)]), mode="r")
    big = np.abs(rn).max()
    if big > 0 and np.isfinite(big):
        return rn / big, c + math.log(big)
    return rn, c


def glls_curves(a, c, omega, s_max=500):
    n, m = a.shape[0], c.shape[0]
    ainv = np.linalg.inv(a) if 1.0 / np.linalg.cond(a, 1) > 1e-14 else None
    oc = omega[0, 0]
    isotropic = oc > 0 and np.abs(omega - np.eye(m) * oc).max() <= 1e-15 * oc
    assert isotropic, "the benchmark's Ω is isotropic (the Rust's fast path); other Ω not ported"
    S = s_max + 1
    Rs, ls_g = np.empty((S, n, n)), np.empty(S)
    Ps, ls_p = np.empty((S, n, n)), np.empty(S)
    Rp, ls_pr = np.empty((S, n, n)), np.empty(S)
    r, lr = np.zeros((n, n)), -np.inf
    rp, lrp = np.zeros((n, n)), -np.inf
    p, lp = np.eye(n), 0.0
    for s in range(S):
        r, lr = _append(r, lr, c @ p, lp)  # new rows C A^s = e^lp C P
        Rs[s], ls_g[s], Ps[s], ls_p[s] = r, lr, p, lp
        if ainv is not None:
            if np.isfinite(lrp):  # Γ_{s+1}A^{−s} = [Γ_s A^{−(s−1)} A^{−1}; C]
                rp = rp @ ainv
                big = np.abs(rp).max()
                if big > 0 and np.isfinite(big):
                    rp, lrp = rp / big, lrp + math.log(big)
            rp, lrp = _append(rp, lrp, c, 0.0)
            Rp[s], ls_pr[s] = rp, lrp
        p = p @ a
        big = np.abs(p).max()
        if big > 0 and np.isfinite(big):
            p, lp = p / big, lp + math.log(big)
    ln10 = math.log(10)

    def log10_of_ln(v):
        out = v / ln10
        return np.where(np.isfinite(out), out, -400.0)

    with np.errstate(divide="ignore"):
        ln_sv = np.log(np.linalg.svd(Rs, compute_uv=False)) + ls_g[:, None]
    log10_sigma = log10_of_ln(ln_sv)
    log10_floor = log10_of_ln(ln_sv[:, 0] + np.log(EPS * np.sqrt(m * np.arange(1, S + 1))))

    def direct(idx):  # ln ‖P R⁻¹‖₂ + ρ_p − ρ_R, batched: X = P R⁻¹ ⇔ Rᵀ Xᵀ = Pᵀ
        # A singular R gives +∞, i.e. the −400 floor (the Rust's triangular solve fails on
        # the exact zeros its Givens rotations leave while Γ has fewer rows than n; a
        # Householder QR leaves rounding-size entries there, hence the relative test).
        diag = np.abs(np.diagonal(Rs[idx], axis1=1, axis2=2))
        singular = diag.min(1) <= n * EPS * diag.max(1)
        out = np.full(len(idx), -400.0)
        ok = np.asarray(idx)[~singular]
        if len(ok):
            xt = np.linalg.solve(Rs[ok].swapaxes(1, 2), Ps[ok].swapaxes(1, 2))
            nrm = np.linalg.svd(xt, compute_uv=False)[:, 0]
            out[~singular] = log10_of_ln(np.log(nrm) + ls_p[ok] - ls_g[ok])
        return out

    if ainv is not None:
        with np.errstate(divide="ignore"):
            ln_svp = np.log(np.linalg.svd(Rp, compute_uv=False)) + ls_pr[:, None]
        log10_sigma_prime = log10_of_ln(ln_svp)
        kappa = -log10_sigma_prime[:, n - 1]
        lost = ~(log10_sigma_prime[:, n - 1] > log10_sigma_prime[:, 0] - 12.0)
        if lost.any():
            kappa[lost] = direct(np.nonzero(lost)[0])
    else:
        log10_sigma_prime, lost = None, np.ones(S, bool)
        kappa = direct(np.arange(S))
    return dict(sigma=log10_sigma, sigma_prime=log10_sigma_prime, floor=log10_floor,
                kappa_lls_current=kappa, kappa_glls_past=-log10_sigma[:, n - 1],
                kappa_glls_current=kappa.copy(), direct=int(lost.sum()))


def bench_glls_curves():
    a, c, omega = glls_model()
    ms, cv = median_ms(lambda: glls_curves(a, c, omega))
    sg, sp = cv["sigma"], cv["sigma_prime"]
    return ms, (f"s = 0..500, n = 10, m = 2; log10 sigma_n(Gamma_501) = {sg[-1, -1]:.3f} (NumPy: "
                f"one QR per step and factor, batched SVDs; numpy-drawn A (rho 1.02), C, Omega = "
                f"0.01 I; at s = 500 log10 sigma_1 {sg[-1, 0]:.3f}, sigma'_n {sp[-1, -1]:.3f}, "
                f"kappa_LLS(s,k) {cv['kappa_lls_current'][-1]:.3f}; direct kappa route at "
                f"{cv['direct']} of 501 s)")


# ---------------------------------------------------------------------------------------------
# LP helpers: support LPs with HiGHS, the exact polygon from support points


class LpCount:
    calls = 0


def lp_solve(c, a_ub=None, b_ub=None, a_eq=None, b_eq=None, bounds=(None, None)):
    LpCount.calls += 1
    return linprog(c, A_ub=a_ub, b_ub=b_ub, A_eq=a_eq, b_eq=b_eq, bounds=bounds, method="highs")


def polygon_from_support(support, budget, rel_tol):
    """src/sets/support_polygon.rs polygon_from_support, line for line."""
    calls = 0
    probes = []  # [angle, dir, value, point]

    def probe(angle):
        nonlocal calls
        d = (math.cos(angle), math.sin(angle))
        value, point = support(d)
        calls += 1
        return [angle, d, value, point]
    quarter = math.pi / 2
    for i in range(4):
        probes.append(probe(i * quarter))
    hull = [-probes[2][2], probes[0][2], -probes[3][2], probes[1][2]]
    tol = rel_tol * (1 + max(abs(v) for v in hull))

    def dot(d, p):
        return d[0] * p[0] + d[1] * p[1]
    confirmed = [False] * 4
    while True:
        best, bi = -1.0, None
        for i in range(len(probes)):
            if confirmed[i]:
                continue
            a, b = probes[i][3], probes[(i + 1) % len(probes)][3]
            dist = math.hypot(a[0] - b[0], a[1] - b[1])
            if dist > best:
                best, bi = dist, i
        if bi is None:
            break
        i = bi
        j = (i + 1) % len(probes)
        a, b = probes[i][3], probes[j][3]
        if math.hypot(a[0] - b[0], a[1] - b[1]) <= tol:
            confirmed[i] = True
            continue
        if calls >= budget:
            break
        lo, hi = probes[i][0], probes[j][0]
        if hi <= lo:
            hi += 2 * math.pi
        angle = math.atan2(b[1] - a[1], b[0] - a[0]) - quarter
        while angle < lo:
            angle += 2 * math.pi
        if angle > hi:
            angle = 0.5 * (lo + hi)
        p = probe(angle)
        if p[2] <= max(dot(p[1], a), dot(p[1], b)) + tol:
            confirmed[i] = True
        else:
            probes.insert(i + 1, p)
            confirmed.insert(i + 1, False)
    exact = all(confirmed)
    return dict(vertices=[p[3] for p in probes], exact=exact, calls=calls, hull=hull)


# ---------------------------------------------------------------------------------------------
# 4. ubb_step


def ubb_truncation(a_norm, b_norm, tau, alpha, gamma):
    """Theorem 5 (src/ubb.rs Smoothing::truncation): the smallest j with tail(j) ≤ γ."""
    ratio = a_norm * math.exp(1 / alpha)

    def tail(j):
        return tau * b_norm * ratio ** (j + 1) / (1 - ratio)
    rhs = math.log(1 - ratio) + math.log(gamma) - math.log(tau) - math.log(b_norm)
    if rhs >= 0:
        return 0
    j = max(math.ceil(rhs / math.log(ratio)) - 1, 0)
    while tail(j) > gamma:
        j += 1
    while j > 0 and tail(j - 1) <= gamma:
        j -= 1
    return j


def ubb_setup(steps=60, seed=1, k=40):
    A = np.array([[0.7, 0.2], [-0.2, 0.7]])
    B = np.array([[0.5], [1.0]])
    C = np.array([[1.0, 0.0]])
    eps, tau, delta, alpha, beta, gamma = 0.2, 0.1, np.array([2.0, 2.0]), 50.0, 50.0, 0.1
    j = ubb_truncation(np.abs(A).sum(1).max(), np.abs(B).sum(1).max(), tau, alpha, gamma)
    window = j + 1
    rng = np.random.default_rng(seed)
    x = delta * (rng.random(2) * 2 - 1)  # x(0) in its box (x0_center = 0)
    y = []
    for _ in range(steps):
        y.append(C @ x + eps * (rng.random(1) * 2 - 1))
        x = A @ x + B @ (tau * (rng.random(1) * 2 - 1))
    return dict(A=A, B=B, C=C, eps=eps, tau=tau, delta=delta, alpha=alpha, beta=beta,
                window=window, y=np.array(y), k=k)


def ubb_step_lp(P):
    """StateProblem::step (stage-wise unknowns), as dense ≤ and = blocks."""
    A, B, C, y, k = P["A"], P["B"], P["C"], P["y"], P["k"]
    r, p = A.shape[0], B.shape[1]
    ln = min(max(P["window"], 1), k + 1)
    s = k + 1 - ln
    dim = r * (ln + 1) + p * ln
    pow_ = [np.eye(r)]
    for _ in range(k + 1):
        pow_.append(A @ pow_[-1])

    def xcol(t):
        return r * (t - s)

    def ucol(t):
        return r * (ln + 1) + p * (t - s)
    E = np.zeros((r * ln, dim))
    for t in range(s, k + 1):
        row = r * (t - s)
        E[row:row + r, xcol(t + 1):xcol(t + 1) + r] = np.eye(r)
        E[row:row + r, xcol(t):xcol(t) + r] = -A
        E[row:row + r, ucol(t):ucol(t) + p] = -B
    rows_a, rows_b = [], []

    def linf(map_, centre, weights, bound):
        wm = weights[:, None] * map_
        wc = weights * centre
        rows_a.extend([wm, -wm])
        rows_b.extend([bound + wc, bound - wc])
    q = C.shape[0]
    nop = np.zeros((q * ln, dim))
    hvec = np.zeros(q * ln)
    w = np.zeros(q * ln)
    for t in range(s, k + 1):
        row = q * (t - s)
        nop[row:row + q, xcol(t):xcol(t) + r] = C  # nominal x̄ = 0 (x0_center 0, no input)
        hvec[row:row + q] = y[t]
        w[row:row + q] = math.exp(-(k - t) / P["beta"])
    linf(nop, hvec, w, P["eps"])
    umap = np.zeros((p * ln, dim))
    umap[:, ucol(s):ucol(s) + p * ln] = np.eye(p * ln)
    uw = np.array([math.exp(-(k - (s + i // p)) / P["alpha"]) for i in range(p * ln)])
    linf(umap, np.zeros(p * ln), uw, P["tau"])
    half = np.abs(pow_[s]) @ P["delta"]
    for l in range(s):
        m = pow_[s - 1 - l] @ B
        half = half + np.abs(m).sum(1) * P["tau"] / math.exp(-(k - l) / P["alpha"])
    smap = np.zeros((r, dim))
    smap[:, xcol(s):xcol(s) + r] = np.eye(r)
    linf(smap, np.zeros(r), np.where(half > 0, 1 / half, 1e12), 1.0)
    S = np.zeros((r, dim))
    S[:, xcol(k + 1):xcol(k + 1) + r] = np.eye(r)
    return dict(a_ub=np.vstack(rows_a), b_ub=np.concatenate(rows_b), a_eq=E,
                b_eq=np.zeros(r * ln), S=S, dim=dim)


def ubb_hull_and_polygon(P, budget=64):
    L = ubb_step_lp(P)
    S = L["S"]

    def sup(d):  # sup dᵀf over T(h), and the maximiser
        res = lp_solve(-d, L["a_ub"], L["b_ub"], L["a_eq"], L["b_eq"])
        if res.status != 0:
            raise RuntimeError(res.message)
        return -res.fun, res.x
    lo, hi = [], []
    for i in range(S.shape[0]):
        hi.append(sup(S[i])[0])
        lo.append(-sup(-S[i])[0])

    def probe(d):
        x = sup(S[0] * d[0] + S[1] * d[1])[1]
        pt = S @ x
        return d[0] * pt[0] + d[1] * pt[1], (pt[0], pt[1])
    poly = polygon_from_support(probe, budget, 1e-7)
    return (lo, hi), poly, L


def bench_ubb_step():
    P = ubb_setup()
    ms, (hull, poly, L) = median_ms(lambda: ubb_hull_and_polygon(P))
    nv = L["dim"]
    nle, neq = L["a_ub"].shape[0], L["a_eq"].shape[0]
    rad = max(0.5 * (h - l) for l, h in zip(*hull))
    return ms, (f"k = 40, window {P['window']}: {nv} variables, {nle + neq} rows; {poly['calls']} "
                f"LPs for the polygon (NumPy + linprog(highs), one call per LP: build + hull "
                f"({2 * len(hull[0])} LPs) + exact polygon ({len(poly['vertices'])} boundary "
                f"points, exact {poly['exact']}); {nle} <= and {neq} = rows; hull radius {rad:.3f}; "
                f"numpy-simulated data)")


# ---------------------------------------------------------------------------------------------
# 5. uniform_report

MAX_EXT = 20


def theta_vec(th):
    return np.concatenate([th[k].reshape(-1) for k in "ABCD"])


def theta_from(v, like):
    out, at = {}, 0
    for k in "ABCD":
        sz = like[k].size
        out[k] = v[at:at + sz].reshape(like[k].shape)
        at += sz
    return out


def pad_right(m, col):
    return np.hstack([m, np.zeros((m.shape[0], col))])


def pad_left(m, col):
    return np.hstack([np.zeros((m.shape[0], col)), m])


def state_lp(th, u, y, first, last, prior):
    """state_lp (6)–(10): X = [x_last; …; x_{first−1}; x_r; y_r]."""
    A, B, Cm, D = th["A"], th["B"], th["C"], th["D"]
    n, m = A.shape[0], Cm.shape[0]
    t = last + 1 - first
    K = np.array([[-1.0], [1.0]])
    ik = np.kron(np.eye(t), K)
    a11 = pad_right(np.kron(ik, np.eye(n)), n) - pad_left(np.kron(ik, A), n)
    ones = np.ones((2 * t, 1))
    a12 = -np.kron(ones, pad_right(np.eye(n), m))
    a21 = pad_right(np.kron(ik, Cm), n)
    a22 = -np.kron(ones, pad_left(np.eye(m), n))
    uu = u[first:last + 1][::-1].reshape(-1)
    yy = y[first:last + 1][::-1].reshape(-1)
    b1 = np.kron(ik, B) @ uu
    b2 = -(np.kron(ik, D) @ uu) + np.kron(ik, np.eye(m)) @ yy
    nx = (t + 1) * n
    nv = nx + n + m
    a = np.vstack([np.hstack([a11, a12]), np.hstack([a21, a22])])
    b = np.concatenate([b1, b2])
    lo = np.full(nv, prior["x_lo"])
    hi = np.full(nv, prior["x_hi"])
    lo[nx:] = 0.0
    hi[nx:nx + n] = prior["xr_max"]
    hi[nx + n:] = prior["yr_max"]
    c = np.zeros(nv)
    c[nx:] = 1.0
    return dict(c=c, a=a, b=b, lo=lo, hi=hi)


def parameter_lp(like, x, u, y, first, last, prior):
    """parameter_lp (11)–(12): X = [col(A); col(B); col(C); col(D); x_r; y_r]."""
    n, r, m = like["A"].shape[0], like["B"].shape[1], like["C"].shape[0]
    na, nb, nc, nd = n * n, n * r, m * n, m * r
    nth = na + nb + nc + nd
    nv = nth + n + m
    K = np.array([[-1.0], [1.0]])
    t = last + 1 - first
    a = np.zeros((2 * t * (n + m), nv))
    b = np.zeros(2 * t * (n + m))
    row = 0
    for tau in range(last, first - 1, -1):
        rows = 2 * n
        a[row:row + rows, :na] = np.kron(K, np.kron(np.eye(n), x[tau - 1][None, :]))
        if nb:
            a[row:row + rows, na:na + nb] = np.kron(K, np.kron(np.eye(n), u[tau][None, :]))
        a[row:row + rows, nth:nth + n] = -np.kron(np.ones((2, 1)), np.eye(n))
        b[row:row + rows] = np.kron(K, x[tau][:, None])[:, 0]
        row += rows
        rows = 2 * m
        a[row:row + rows, na + nb:na + nb + nc] = np.kron(K, np.kron(np.eye(m), x[tau][None, :]))
        if nd:
            a[row:row + rows, na + nb + nc:nth] = np.kron(K, np.kron(np.eye(m), u[tau][None, :]))
        a[row:row + rows, nth + n:] = -np.kron(np.ones((2, 1)), np.eye(m))
        b[row:row + rows] = np.kron(K, y[tau][:, None])[:, 0]
        row += rows
    lo = np.zeros(nv)
    hi = np.zeros(nv)
    lo[:nth], hi[:nth] = prior["lo"], prior["hi"]
    hi[nth:nth + n] = prior["xr_max"]
    hi[nth + n:] = prior["yr_max"]
    c = np.zeros(nv)
    c[nth:] = 1.0
    return dict(c=c, a=a, b=b, lo=lo, hi=hi)


def lp_min(lp, c=None, extra=None):
    a, b = lp["a"], lp["b"]
    if extra is not None:
        a, b = np.vstack([a, extra[0][None, :]]), np.append(b, extra[1])
    return lp_solve(lp["c"] if c is None else c, a, b, bounds=np.stack([lp["lo"], lp["hi"]], 1))


def solve_extending(lp, nhw):
    for ext in range(MAX_EXT + 1):
        res = lp_min(lp)
        if res.status == 0:
            return res, ext
        if res.status != 2:
            raise RuntimeError(res.message)
        if ext < MAX_EXT:
            lp["hi"][-nhw:] *= 2.0
    return None, MAX_EXT


def face_ranges(lp, objective, indices):
    tol = 1e-7 * max(abs(objective), 1.0)
    out = []
    for i in indices:
        e = np.zeros(len(lp["c"]))
        e[i] = 1.0
        lo = lp_min(lp, e, (lp["c"], objective + tol)).fun
        hi = -lp_min(lp, -e, (lp["c"], objective + tol)).fun
        out.append((lo, hi))
    return out


def uniform_setup():
    th = dict(A=np.array([[1.0, 0.5], [-0.5, 0.0]]), B=np.array([[1.0], [3.0]]),
              C=np.array([[1.0, 1.0]]), D=np.zeros((1, 1)))
    xr, yr = np.full(2, 0.3), np.full(1, 0.3)
    tv = theta_vec(th)
    lo, hi = tv - 0.3 * np.abs(tv), tv + 0.3 * np.abs(tv)
    lo[3], hi[3] = -0.3, 0.3  # prior override A(1, 1) ∈ [−0.3, 0.3]
    return dict(theta=th, xr=xr, yr=yr, u_half=0.5, steps=120, seed=1, window=5,
                theta_prior=dict(lo=lo, hi=hi, xr_max=np.ones(2), yr_max=np.ones(1)),
                state_prior=dict(x_lo=-5.0, x_hi=5.0, xr_max=np.ones(2), yr_max=np.ones(1)),
                theta0=theta_from(0.5 * (lo + hi), th), directions=64)


def uniform_simulate(U):
    th, n, m, r = U["theta"], 2, 1, 1
    rng = np.random.default_rng(U["seed"])
    T = U["steps"]
    x, u, y = np.zeros((T + 1, n)), np.zeros((T + 1, r)), np.zeros((T + 1, m))
    for k in range(1, T + 1):
        u[k] = (rng.random(r) * 2 - 1) * U["u_half"]
        x[k] = th["A"] @ x[k - 1] + th["B"] @ u[k] + (rng.random(n) * 2 - 1) * U["xr"]
        y[k] = th["C"] @ x[k] + th["D"] @ u[k] + (rng.random(m) * 2 - 1) * U["yr"]
    assert np.abs(x).max() <= 5.0
    return x, u, y


def kalman_uniform(th, xr, yr, x0, u, y):
    Q, R = np.diag(xr**2 / 3), np.diag(yr**2 / 3)
    A, B, Cm, D = th["A"], th["B"], th["C"], th["D"]
    T = len(y) - 1
    xp, pp = A @ x0 + B @ u[1], Q.copy()
    out = np.empty((T, len(x0)))
    for t in range(1, T + 1):
        s = sym(R + Cm @ pp @ Cm.T)
        k = np.linalg.solve(s, Cm @ pp).T
        ikh = np.eye(len(x0)) - k @ Cm
        p = sym(ikh @ pp @ ikh.T + k @ R @ k.T)
        xh = xp + k @ (y[t] - D @ u[t] - Cm @ xp)
        out[t - 1] = xh
        xp = A @ xh + B @ u[min(t + 1, T)]
        pp = sym(A @ p @ A.T + Q)
    return out


def uniform_report(U):
    n, m = 2, 1
    x, u, y = uniform_simulate(U)
    th = {k: v.copy() for k, v in U["theta0"].items()}
    sp, tp = U["state_prior"], U["theta_prior"]
    steps, thetas, ext_total = [], [], 0
    for t in range(1, U["steps"] + 1):
        first, last = max(t - U["window"] + 1, 1), t
        lp = state_lp(th, u, y, first, last, sp)
        sol, ext = solve_extending(lp, n + m)
        if sol is None:
            raise RuntimeError("state LP infeasible")
        ext_total += ext
        ns = last + 2 - first
        xs = sol.x[:ns * n].reshape(ns, n)  # newest first
        x_full = np.zeros((last + 1, n))
        x_full[first - 1:] = xs[::-1]
        plp = parameter_lp(th, x_full, u, y, first, last, tp)
        psol, _ = solve_extending(plp, n + m)
        if psol is not None:
            th = theta_from(psol.x, th)
        x_prev = steps[-1] if steps else (xs[1] if ns > 1 else np.zeros(n))
        _y_pred = th["C"] @ (th["A"] @ x_prev + th["B"] @ u[t]) + th["D"] @ u[t]
        steps.append(xs[0])
        thetas.append(th)
    # The window at t = 120: state LP, optimal face, half-width ranges, polygon.
    T = U["steps"]
    first = max(T - U["window"] + 1, 1)
    th = thetas[-1]
    lp = state_lp(th, u, y, first, T, sp)
    sol, _ = solve_extending(lp, n + m)
    ns = T + 2 - first
    nx = ns * n
    face = face_ranges(lp, sol.fun, range(nx))
    hw = face_ranges(lp, sol.fun, range(nx, nx + n + m))
    hwv = lp["hi"][nx:]
    states = dict(c=np.zeros(nx), a=lp["a"][:, :nx], b=lp["b"] - lp["a"][:, nx:] @ hwv,
                  lo=lp["lo"][:nx], hi=lp["hi"][:nx])

    def probe(d):
        c = np.zeros(nx)
        c[0], c[1] = -d[0], -d[1]
        res = lp_min(states, c)
        if res.status != 0:
            raise RuntimeError(res.message)
        return d[0] * res.x[0] + d[1] * res.x[1], (res.x[0], res.x[1])
    poly = polygon_from_support(probe, U["directions"], 1e-7)
    kf = kalman_uniform(U["theta"], U["xr"], U["yr"], np.zeros(n), u, y)
    est = np.array(steps)
    frm = min(U["window"], T)
    rms_lp = math.sqrt(((est[frm - 1:] - x[frm:]) ** 2).sum(1).mean())
    rms_kf = math.sqrt(((kf[frm - 1:] - x[frm:]) ** 2).sum(1).mean())
    return dict(ext=ext_total, objective=sol.fun, face=face, hw=hw, poly=poly, steps=len(steps),
                rms_lp=rms_lp, rms_kf=rms_kf, theta=th)


def bench_uniform_report():
    U = uniform_setup()
    # One window LP like speed.rs (∂ = 5, t = 116..120, the true Θ) on the same kind of data.
    x, u, y = uniform_simulate(U)

    def window_lp():
        lp = state_lp(U["theta"], u, y, 116, 120, U["state_prior"])
        return solve_extending(lp, 3), lp
    win_ms, (_, wlp) = median_ms(window_lp, reps=21)
    LpCount.calls = 0
    uniform_report(U)
    per_report = LpCount.calls
    ms, R = median_ms(lambda: uniform_report(U))
    return ms, (f"{R['steps']} steps, window {U['window']} (NumPy + linprog(highs), the full "
                f"report: swapping, per step state LP {len(wlp['c'])} variables/"
                f"{wlp['a'].shape[0]} rows + bounds and parameter LP 12/30; at t = 120 the face "
                f"ranges of 12 states + 3 half-widths and the exact polygon ({R['poly']['calls']} "
                f"LPs, exact {R['poly']['exact']}), KF; {per_report} LPs per report, {R['ext']} "
                f"bound doublings; RMS state error LP {R['rms_lp']:.3f} KF {R['rms_kf']:.3f}; "
                f"numpy-simulated data; one window LP {win_ms:.3f} ms)")


# ---------------------------------------------------------------------------------------------

KERNELS = {
    "robot_mc": bench_robot_mc,
    "lscr_raster": bench_lscr_raster,
    "glls_curves": bench_glls_curves,
    "ubb_step": bench_ubb_step,
    "uniform_report": bench_uniform_report,
}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--only", choices=sorted(KERNELS), help="run one kernel")
    args = ap.parse_args()
    keys = [args.only] if args.only else list(KERNELS)
    for key in keys:
        ms, text = KERNELS[key]()
        print(f"BENCH {key} {ms:.3f} {text}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
