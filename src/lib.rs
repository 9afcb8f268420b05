//! # confset — state estimation with guaranteed sets
//!
//! One estimation core, compiled natively (the `confset` command line, SVG figures) and to
//! WebAssembly (the explorer page in `www/`). This page is the map of the code: read it first.
//!
//! ## One flow of data
//!
//! ```text
//! Scenario (JSON) ──prepare/validate──▶ method (pure Rust) ──▶ Report (JSON)
//!                                                              │
//!               plot::draw (plotters, any DrawingBackend) ◀────┘
//!                  ├─ SVG backend   (CLI: `confset figure`, `confset figures`)
//!                  └─ canvas backend (browser, through `web`)
//! ```
//!
//! ## Modules
//!
//! * [`error`]: the one [`Error`]: the offending field (`model.V`, `alpha`, …) and why;
//!   [`error::quoted`], the one way a message repeats a user's string (cut at
//!   [`error::ECHO_CHARS`]); [`error::displayed`], the one way a figure shows one (control
//!   characters dropped, cut at [`error::DISPLAY_CHARS`], before any layout)
//! * [`method`]: the one [`Method`] enum (`scf`, `kf`, `lscr`, `glls`, `uniform_lp`, `ubb`, and
//!   `compare`: all of them on one record), parsed once from the scenario; its names, its option
//!   block and its study block. The only `match`es on `Method` outside this file are the one
//!   `make_*` of each layer (`scenario::make_method`, `plot::make_figures`)
//! * [`precision`]: where double precision stops resolving a method's sets: the one bound
//!   0.8·√N·δ(Y)/σ·T on the probability that rounding flips a verdict (δ(Y) the spacing of doubles
//!   at the data's magnitude, σ the noise scale), checked by each method's scenario file before any
//!   work ([`precision::Resolution`]); refused past 10⁻⁴ naming the field
//! * [`stats`]: χ² quantiles (round-trip checked) and the one exact binomial band every study
//!   compares its counts with
//! * [`bench`](mod@bench): the speed comparison's kernels ([`bench::Kernel`]: robot Monte Carlo,
//!   LSCR raster, GLLS curves, one set-membership step, the uniform report), written once for the
//!   native benchmark (`cargo bench --bench speed -- kernels`), the wasm `BenchKernel` and
//!   `.ci/bench`'s table beside NumPy
//! * [`study`]: the [`Study`] trait every Monte Carlo is driven through (step, runs, total,
//!   finished, result; restrict to a shard, partial counts, merge, complete) by the CLI (`confset
//!   experiment`, `--shard i/N`, `confset merge`), the wasm `Study` class and the tests; written
//!   once in [`study::Chunked`] over each study's [`study::Runs`] (what a range of runs gives) and
//!   [`study::Tally`] (how two ranges' counts add, by checked sums, and which of them are counts of
//!   runs, none above its runs: what a merge checks on every part); [`study::shard_range`], the one
//!   split of runs into shards; [`study::run_sharded`], the shards on rayon's threads (one on
//!   wasm32), merged
//! * [`linalg`]: small dense helpers: JSON rows ↔ matrices, covariance checks, PSD square roots,
//!   the induced norms ‖·‖₁, ‖·‖₂, ‖·‖∞, the one sort of numbers ([`linalg::sort_increasing`],
//!   [`linalg::sort_decreasing`], [`linalg::decreasing_order`])
//! * [`model`]: the scenario's `model` block ([`model::ModelSpec::constant`]: the one matrix of a
//!   field for the methods that need a time-invariant model, [`model::MatrixSpec::of`] the reverse)
//!   and the linear Gaussian state-space model: validation, stationary Γ (Lyapunov), prior moments
//!   m_t, Γ_t, backward representation F^b, V^b ((30), (45)), seeded forward simulation and
//!   state-conditioned backward simulation, the same model with its noise scaled (the true
//!   noise of a simulation, `simulate.true_noise`)
//! * [`sets`]: set types shared by all methods and plots: [`sets::Ellipsoid`] (χ² radius,
//!   membership, box, volume, projection, slice, distance), [`sets::BoxSet`]; in
//!   [`sets::sign_region`] the LSCR region [`sets::SignRegion`] (x is in when, in every group, ≥ q
//!   affine functions are > 0 and ≥ q are < 0) with its exact pixel raster [`sets::GridRegion`],
//!   line pieces, boundary polygons, 2-D slices and recession directions; in
//!   [`sets::support_polygon`] the exact polygon of a planar convex set known only through its
//!   support function (one LP per call: each unsettled stretch between two boundary points is
//!   closed by a support call normal to it; used by `ubb` and `uniform` where an LP remains), and
//!   [`sets::point_in_convex`]; in [`sets::convex_polygon`] the exact planar set engine
//!   [`sets::ConvexPolygon`] (bounded convex polygons, segments and points: clip by a half-plane
//!   or a strip, 2×2 maps, Minkowski sums with boxes, segments and polygons by an edge merge,
//!   hull, area, support, interval hull; predicates to 2⁻⁴⁰ of the extent, any scale 10^±150):
//!   the ubb state set and the uniform consistent polygon of a 2-D state without an LP; in
//!   [`sets::plane`] the plane geometry every method and compare shares (shoelace area, convex
//!   hull, box corners, 2×2 maps of points and ellipses, Minkowski sums)
//! * [`kalman`]: Kalman filter (35a–c), its data-independent gains, τ-step prediction, steady state
//! * [`scf`]: State Conditional Filter: ratio matrix by (38) and (41), SCF regions (33)–(34), (40),
//!   asymptotic filter, components ζ, prediction, inputs; closed-form conditional coverage; in
//!   [`scf::experiment`] the conditional-coverage studies: the Fig. 1 curve and the chunked robot
//!   Monte Carlo (on domain values: model, inputs, options, the conditioning state)
//! * [`lscr`]: LSCR (Weyer & Campi): the data as a regression on x_{t+1}, x_t or x_i ((11), (20),
//!   (21)), the block-wise Karhunen–Loève basis (12)–(15), the SVD of A (16), random/group/explicit
//!   strings (points 4, 4a), the region (17) as a `SignRegion`, Theorem 3.2 levels, BLUE and Kalman
//!   comparisons, the chunked coverage experiment
//! * [`glls`]: GLLS moving-horizon estimation (Gubarev & Mishchenko): Γ_{s+1}, Φ_{s+1} (6), the
//!   GLLS gain in SVD form (21), fast-forward (41), κ (17), (19), (45), truncated-SVD
//!   regularization (29)–(32), (47)–(49), guaranteed ball (35) with √(s+1) and the exact interval
//!   hull, the expected bound (39), singular-value curves by scaled QR updates, the state-noise
//!   estimator (60)–(64), the chunked Monte Carlo of Section 5
//! * [`uniform`]: linear models with uniform innovations (Pavelková): the state LP (6)–(10) in the
//!   Kronecker layout of (8), the parameter LP (11)–(12) with the half-width block derived from
//!   (4) (both by the dense simplex of [`solve::simplex`]), the optimal face (its ranges from
//!   one loaded LP, warm-started per objective), the exact consistent-state polygon
//!   (for n = 2 exactly by [`sets::ConvexPolygon`] clips of the per-sample boxes and strips;
//!   otherwise [`uniform::consistent_polygon_lp`]: [`sets::polygon_from_support`] on one loaded
//!   state LP with the half-widths eliminated), the
//!   sliding window with swapping (4.1) and expansion (4.2, (13)) joint estimation, automatic
//!   extension of infeasible half-width bounds
//! * [`ubb`]: unknown-but-bounded noise (Tempo): the feasible set T(h) (3) as weighted l∞/l1/l2
//!   [`ubb::NormBound`]s (l1 either as the paper's 2^{m−1} rows (30)–(34) or lifted with slacks; l2
//!   as second-order cones), its interval hull and central estimate (31) with the local error (5),
//!   the exact 2-D polygon (a 2-D state with l∞ bounds: by the planar recursion of
//!   [`ubb::planar`], clip by the measurement strips, map by A, add the noise zonotope, with no
//!   LP; a 1-D state the same on intervals, [`ubb::interval`]; otherwise by support LPs), the
//!   filtered set X(k | y(0 … k)) beside the predicted X(k+1 | y(0 … k)) of every step, a
//!   record's gaps (a missing measurement drops its strip), boundedness with δ = ∞ by
//!   reconstructibility over the window, Theorem 1 (Hilbert norms: Gauss–Markov or zero), Theorem 2 (linear
//!   optimal algorithm from the active constraints of (22), by the certified simplex's vertex; on
//!   the state problem [`ubb::StateProblem::theorem_2`]: each plotted component's estimate (25),
//!   error E(φ₀) and active rows named by time and bound, the report's `at.linear`), Theorems 4
//!   and 5 ((47), (55), (58)), and Section IV's state estimator on a window of j + 1 steps with
//!   smoothed bounds (45)–(46); the simulation's true noise (`ubb.sim_eps`, `ubb.sim_tau`) apart
//!   from the assumed bounds, the guarantee study counting runs whose data contradict them as
//!   misses
//! * [`conformal`]: conformal prediction beside the Kalman filter: split conformal's rank
//!   ⌈(N + 1)α⌉ and order statistic of the filter's Mahalanobis scores (Vovk, Gammerman & Shafer
//!   2005; Lei et al. 2018), the promise α ≤ P ≤ α + 1/(N + 1) *on average over runs* (no
//!   finite-sample method promises it for every state without assumptions: Vovk 2012, Lei &
//!   Wasserman 2014, Barber et al. 2021), adaptive conformal inference (Gibbs & Candès 2021,
//!   their (2) and Proposition 4.1's bound), the multivariate Student-t law scaled to a
//!   covariance, and a simulator with the square roots computed once. With the others it fills
//!   the table "model-based / distribution-free × on average / for every state": Kalman, SCF,
//!   conformal, LSCR
//! * [`solve`]: the one place that talks to the LP/QP solver (clarabel): dense LP/QP/SOCP in, a
//!   solution (with duals) or an error in words out, naming the field its [`solve::Blame`] holds
//!   (infeasible with the caller's hint, unbounded, stopped before converging with the
//!   coefficients' span); every solve capped at [`solve::MAX_ITERATIONS`] and
//!   [`solve::TIME_LIMIT_SECONDS`]; a [`solve::Family`] keeps one loaded problem for many
//!   objectives (support functions); in [`solve::simplex`] a small dense simplex (dual simplex
//!   from the slack basis or Phase I, Dantzig's rule turning to Bland's, warm starts across
//!   objectives) whose every answer is certified on the data (a primal feasible vertex within
//!   10⁻⁹ of its duals' Lagrangian bound, a Farkas bound for infeasible, a ray for unbounded),
//!   clarabel taking over whatever it cannot certify: the uniform method's state, parameter and
//!   face-range LPs go through it ([`solve::simplex::with_engine`] selects clarabel alone, the
//!   tests' oracle)
//! * [`scenario`]: Scenario and Report JSON, and the one dispatch from a method to its file.
//!   - parsing with field paths ([`scenario::parse`]: the text read once into a JSON value, a
//!     key given twice refused; every type read from that value with serde_path_to_error, then
//!     serde's messages in JSON words at the path of the offending value);
//!   - [`scenario::Scenario::new`] and its setters: a builder names only its own block; one
//!     generic check that a scenario carries no other method's block (the blocks are
//!     [`Method::block`] and [`Method::study_block`], looped over);
//!   - keys an older version wrote elsewhere are moved into their block before parsing (SCF's
//!     top-level `tau`, `components`, `asymptotic`, `collision`, `coverage_curve` into `scf`),
//!     and the report says so ([`scenario::Report::notices`]);
//!   - the time [`scenario::Cursor`] of a scenario whose report keeps one step's detail (ubb,
//!     uniform_lp, compare: `at(t)` on demand; [`scenario::Report::set_at`],
//!     [`scenario::Report::cursor_steps`]); a study's result put into a report by one path
//!     ([`scenario::Report::set_study`]: GLLS's precision panel);
//!   - the report's [`scenario::FigureContext`] (title, axis names, measured components,
//!     collision check: what a figure takes from the scenario);
//!   - a user's record ([`scenario::DataSpec`]): a gap (a missing measurement: JSON `null`, a
//!     CSV cell that is empty, `NA`, `nan`, `#N/A`) is held as NaN in `data.y` and keeps its
//!     row; `data.t` the record's own times ([`scenario::RecordTime`]: numbers or ISO dates,
//!     checked increasing). What a method does with a gap is a required descriptor item
//!     (`MethodScenario::gaps`, [`scenario::Gaps`]), and one gate in `Scenario::source`
//!     refuses a gap for a method that cannot take one, naming the row, its time and the
//!     reason, before any work; how its CSV table counts time is another
//!     (`MethodScenario::time_index`, [`scenario::TimeIndex`]), so [`scenario::Report::table`]
//!     adds the `record_time` column in one place; the report's
//!     [`scenario::FigureContext::times`] carry the record's times to the figures and the page;
//!     [`scenario::Report::warnings`] are the sentences a user must read with the answer (an
//!     assumption not met, an estimate on an artificial bound, the gaps and what was done),
//!     printed by the CLI, written above the CSV table and shown by the page
//!     (`tests/suite/record_gates.rs` loops over every method);
//!   - the one observations step ([`scenario::Source`]: `data` or `simulate`, one step-count
//!     check per method, and `simulate.true_noise` ([`scenario::TrueNoise`]: the simulation's
//!     noise as scales of the model's V, W, which the filters still assume) checked against
//!     what the method honours, `MethodScenario::true_noise`; the simulation draws from
//!     [`model::LinearModel::with_noise_scaled`]);
//!   - [`scenario::Scenario::explain`] ([`scenario::explain`]): one step of the report step by
//!     step, rows of (quantity, equation number, TeX formula, value, note) from the method's
//!     own `MethodScenario::explain` (SCF/KF: (35a–c), (38), (33)–(34), (40) at time t; LSCR:
//!     the sign-perturbed sums, ranks and verdicts (17)–(19) at a point; ubb: the window,
//!     hull (31), local error (5), Theorem 2's (25), (22) and active constraints at k); the page's
//!     step-through card (`www/stepcard.js`) only lays them out;
//!   - [`scenario::Scenario::first_accepted`]: the smallest value of the quantity a view animates
//!     by rerunning (LSCR's t, GLLS's s) that the method's own validation accepts;
//!   - `MethodScenario`, the descriptor each method's scenario file implements (steps, data
//!     shape, work estimate, run, CSV table, study, cursor, state limit, truth keys, moved keys,
//!     its compare member, presets), reached through the one `scenario::make_method`;
//!   - one file per method, each ending with its presets (`// Presets`) above which stands
//!     what a compare asks of it (`// Compare`, [`scenario::compare`]'s `CompareMember`: its
//!     assumption under a noise law, its scenario derived from the record, its set for the
//!     target state read from its report, and the verdict a study's run counts, `holds_at`:
//!     by default read from that report; for ubb and uniform_lp computed from the target
//!     time's window alone, the uniform LP's with Θ known by the exact planar polygon with no
//!     LP ([`uniform::consistent_polygon_extending`]); for LSCR its sums at the state alone):
//!     [`scenario::scf`] (the `scf` block; KF and SCF are
//!     two descriptors of this file), [`scenario::lscr`], [`scenario::glls`],
//!     [`scenario::uniform`], [`scenario::ubb`], [`scenario::conformal`] (the sixth method,
//!     added through these descriptors: its own four files, one arm or line in each of
//!     `method.rs`, `scenario/mod.rs`, `plot/mod.rs`, `www/registry.js`, and `pub mod` here);
//!   - [`scenario::compare`] (method `compare`): one record under one noise law (Gaussian,
//!     uniform or truncated), every member's scenario derived from it and run through
//!     [`scenario::Scenario::run`] as its panel would, its set read into a
//!     [`scenario::compare::PlaneSet`], each assumption checked against the law, a time cursor
//!     over t, and the study at a fixed true state counting every member's hits beside its
//!     promise's band. It loops over the members and never asks a method's kind;
//!   - [`scenario::preset`]: the [`presets::Preset`] type the files build their presets with
//! * [`scenario::csv`]: measured data from CSV text, the one reader of the page (wasm
//!   `withCsvData`, `csvColumns`, `dataShape`), the CLI (`confset run --data FILE.csv
//!   [--columns NAME,…]`) and the tests: [`scenario::data_from_csv`],
//!   [`scenario::data_from_csv_columns`], [`scenario::csv::read_csv`] (with its notes) and
//!   [`scenario::Scenario::with_csv_file_columns`]. It never drops or shifts a row: every line
//!   after the header is a row (a blank line a row of gaps), comments only above it. Columns
//!   y₁ … y_q then optionally u₁ … u_r, by position or by a header's names (`y1`, `u2`; a time
//!   column `t`/`time`/`year`/`date`/`index` or a data frame's unnamed index into `data.t`;
//!   for q = 1 the one column besides the time whatever its name; other names chosen by
//!   name); empty, `NA`, `nan`, `null`, `#N/A` and spreadsheet error cells are gaps (NaN) in y,
//!   refused in u and the time; tab, semicolon, comma or space delimited; CRLF, BOM; at most
//!   [`scenario::csv::MAX_CSV_BYTES`] and [`scenario::csv::MAX_CSV_ROWS`] rows, checked before
//!   any cell is read; every cell in the scenario's number range, by the same
//!   [`scenario::magnitude_problem`] as JSON; errors name `data`, `data.y`, `data.u`, `data.t`
//!   or `columns` with the file's line number and the column)
//! * [`presets`]: the menu of the papers' examples as scenarios (used by page, CLI and tests):
//!   [`presets::all`] (every method of [`Method::ALL`] in turn, from its scenario file's presets;
//!   no names listed), [`presets::get`], and re-exports of the builders that live in the scenario
//!   files (`presets::scalar()`, `presets::ubb_preset(…)`, …)
//! * [`plot`]: figures on any plotters backend from the report and a [`plot::View`] (panel,
//!   time, zoom, hidden methods) alone, so page and CLI draw the same figure.
//!   - `plot/figures.rs`: the `Figures` trait each method's folder implements (its panels, each
//!     a [`plot::Panel`] name with its alternative text declared in the file that draws it; the
//!     words for its reports; `useful`; `draw`; its look in compare: colour, label, fill,
//!     layer), reached through the one `plot::make_figures`;
//!   - `plot/view.rs`: the shared view types ([`plot::View`], [`plot::Panel`], `Zoom`,
//!     [`plot::Frame`]);
//!   - one folder per method: `scf/` (state plane, series, SCF Fig. 1 coverage; KF shares it),
//!     `lscr/` (Figs. 1–3: exact hatching of what each X̂_l excludes, tinted X̂ from its
//!     boundary loops, BLUE and Kalman ellipses), `glls/` (Figs. 1–4: singular values against s
//!     with the floating-point floor, the best horizon, the state plane with the guaranteed
//!     ball and box, error box plots with the bound), `uniform/` (Pavelková Figs. 1–3 and the
//!     consistent-state polygon), `ubb/` (Tempo: the exact feasible polygon with its interval
//!     hull, central estimate, Theorem 2's linear optimal estimate with its error box, truth and
//!     Kalman ellipse; hull widths against Theorem 4),
//!     `compare/` (every member's set on equal axes in its own look, hidden ones left out);
//!   - `plot/style/` in layers, each importing only those below: `palette` and `number`, then
//!     `text` (the one title helper), `axes`, `marks`, `legend`, `notes`; `geom.rs` (clipping)
//!     and `erase.rs` (one backend type) beside them
//! * [`gallery`]: (native only) the papers as a static site (`confset gallery`; the papers'
//!   plain-text notation as HTML scripts by `gallery/notation.rs`): `printed.json`,
//!   the catalogue of every figure and table a preset reproduces with the paper's printed numbers
//!   and where ours are in the report or study JSON; [`gallery::printed::verdict`] (reproduced at
//!   the printed digits, within a 99.9 % two-proportion band for Monte Carlo counts, or differs,
//!   with the erratum quoted from `src/errata.md`, the list below); [`gallery::build`] writes
//!   index, entries, SVG figures and JSON downloads with relative links and no script
//! * `web`: (wasm32 only) thin wasm-bindgen bindings: JSON in, JSON out, errors as JS
//!   exceptions; `presets`, `limits`, `methodPanels` (a method's figures with their text
//!   alternatives), `withCsvData` (CSV data for a scenario, titled after its file, its columns optionally chosen by name: [`scenario::Scenario::with_csv_file_columns`]), `csvColumns` (a header's names and time column, for the page's column picker) and `dataShape`, `firstAccepted`, `ellipsoidLevel`;
//!   `Session` (run, `setReport` (a report computed in the page's worker), `setAt` (a step's
//!   detail from the worker's cursor into the kept report), `setStudy` (a study's result into
//!   the report), `cursorSteps`, `usefulPanels`, draw, svg, LSCR raster), `Cursor` (a
//!   scenario's [`scenario::Cursor`] for the worker), `testOnlyAbort` (the page tests' crash),
//!   `timeCompare` (the worker's clock for a compare's per-method times) and one chunked `Study`
//!   for every method's Monte Carlo
//!
//! The command line lives in `src/bin/confset/` (clap arguments in `cli.rs`); the page in `www/` (no numerics there):
//! `app.js` is the shell (routes `#scf` … `#ubb` and the landing view, share links
//! `#panel/v1/<deflate-raw base64url of {preset, fields, scenario?}>` in `share.js`, scenario
//! files and CSV data through the core's `withCsvData`), `registry.js` the one list of panels
//! (the shell renders the menu and each view's section from it), `index.html` only the frame,
//! `format.js` the one number format, each panel's markup in `views/<id>.html` (fetched on the
//! first visit; ids are looked up under the panel's root, so a view can be mounted twice),
//! `panel.js` the one skeleton (`mountPanel`: session, figure cards, inline errors, frame
//! scheduling, downloads) that each panel module (`scf.js`, `lscr.js`, `glls.js`, `uniform.js`,
//! `ubb.js`, `compare.js`) fills with its controls ⇄ scenario mapping and its numbers. A panel's scenarios run
//! in its own Web Worker (`worker.js`, its own wasm instance, driven by the one client
//! `compute.js`): the report comes back as JSON, the panel's main-thread `Session` keeps it
//! (`setReport`) and draws it. A time cursor (ubb's step k, uniform's time t: `cursor.js`) only
//! redraws: the report keeps one step's detail (`at`), the worker computes every step's once
//! from the scenario's [`scenario::Cursor`] (prefetched after each report, nearest to the
//! cursor first, and sent to the page's cache), `Session::setAt` puts the detail of the step
//! shown into the kept report, and the animation (◀ ▶ play/pause, 0.5–20 steps/s) waits for a
//! step's detail rather than skipping it. A long run never blocks input (Cancel after 1 s; a newer scenario
//! replaces it), and a crash (a panic aborts the instance) takes only the worker down: it is
//! replaced, the panel keeps its last picture and offers the scenario to report. The page runs
//! under a strict Content-Security-Policy (`index.html`: own files only, `'wasm-unsafe-eval'`,
//! no inline script, no eval). Every study runs on all cores (`studypool.js`): one worker per
//! logical core runs its shard (`Study.restrict`), sends its `partial` after each slice, and the
//! main thread's `Study` of the same scenario `merge`s the newest partials once per frame (the
//! counts never depend on the number of workers; Cancel terminates them); a job with no answer
//! for 60 s is stopped by a watchdog and reported as a bug, like a crash. The number boxes and
//! their sliders take their ranges from [`scenario::limits`]. The figure cards are made from the
//! core's list ([`plot::method_panels`], with [`plot::Panel::alt_text`]) and shown as
//! [`plot::useful_panels`] says for each report; a view's markup only places them
//! (`<figure class="card" data-panel="state">`).
//!
//! ## Layers
//!
//! `error` → `linalg`, `stats`, `solve`, `study`, `parse` → `model`, `sets` → the method files
//! (`kalman`, `scf`, `lscr`, `glls`, `uniform`, `ubb`; none imports `scenario`) → `scenario`
//! (JSON, one dispatch, each method's descriptor, compare, presets) → `presets` (the menu over
//! them), `plot` → the CLI and `web`. No import circle, no arrow back up between these; inside
//! `scenario/` the only upward imports are `mod.rs`'s: the blocks' types in `Scenario` and
//! `Report`, and `make_method`.
//!
//! ### What a new method touches
//!
//! Its own files:
//! * `src/<method>.rs` (or a folder): the numerics, knowing nothing of JSON;
//! * `src/scenario/<method>.rs`: its block, `impl MethodScenario` (rustc asks for every
//!   required item: steps, data shape, work, run, table, study, state limit, truth keys, the true noise it honours,
//!   compare member, presets) and, to join compare, `impl CompareMember`;
//! * `src/plot/<method>/`: `impl Figures` and its panels (and its compare look);
//! * `www/<id>.js` and `www/views/<id>.html`: its controls ⇄ scenario mapping and markup.
//!
//! Shared files, each edit asked for by the compiler or a registry test:
//! * `src/method.rs`: the variant, [`Method::ALL`], `name`, `block`, `study_block`;
//! * `src/scenario/mod.rs`: `pub mod`, the block field in `Scenario` (and its line in
//!   `Scenario::new`), the result field in `Report` (and in `Report::of`), the arm of
//!   `make_method`;
//! * `src/plot/mod.rs`: `mod`, the arm of `plot::make_figures`;
//! * `www/registry.js`: its descriptor (route, nav, heading, module, names).
//!
//! A colour of its own for compare may be added to `plot/style/palette.rs`. Tests with a
//! deliberate exhaustive `match` over [`Method`] (`tests/suite/registry.rs`,
//! `tests/suite/compare.rs`) stop compiling until they name it; every other test loops over
//! the registries, and `registry::every_method_is_in_every_registry` fails for a method
//! missing from any of them. Its presets need golden digests (`tests/golden/presets.json`).
//!
//! ## Invariants
//!
//! * The core never imports wasm-bindgen, web-sys or `std::time`; timings come from the page
//!   (`performance.now()`) or the native benchmark. The one timing inside a report, each
//!   compare method's `seconds`, uses a clock the caller hands over
//!   ([`scenario::compare::set_clock`]: the CLI's `Instant`, the worker's `performance.now`);
//!   without one (the tests, the gallery) the field is absent, so reports stay deterministic.
//! * A compare set is its method's own: [`scenario::compare`] writes the method's scenario and
//!   runs it through [`scenario::Scenario::run`]; no method's numerics are repeated there.
//! * The page never computes an estimate: it builds a Scenario, calls wasm, draws.
//! * User text reaches a figure only through the report's [`scenario::FigureContext`], made by
//!   [`error::displayed`]: no control character (the SVG stays well-formed XML) and at most
//!   [`error::DISPLAY_CHARS`] characters, so no figure's cost grows with a text's length. A PNG
//!   is held to [`plot::MAX_PNG_PIXELS`] before its pixels are allocated.
//! * A figure is a function of the report and the view (panel, time, zoom, hidden methods) alone: what it takes
//!   from the scenario (title, axis names, …) is the report's `figure`, so the page and the CLI
//!   draw the same figure from the same scenario (`tests/suite/registry.rs`, `plot` tests).
//!   A report whose method keeps one step's detail (its `at`: ubb's polygon, uniform's window)
//!   draws that detail at that step only: at another view time a figure draws what the report
//!   holds for every step and says the detail is not in the report, never another step's.
//!   [`scenario::Cursor`] gives any step's detail, bit for bit the `at` of a run at that time
//!   (`tests/suite/registry.rs`), and [`scenario::Report::set_at`] puts it in.
//! * Every public function that takes user input returns [`Result`]; no panic is reachable from
//!   input, valid or not (a panic aborts the wasm instance: in the compute worker the page
//!   contains it, but it is a bug). `web::test_only_abort` is the one deliberate abort, for the
//!   page's crash test, and no scenario reaches it. Three defences, written once: sizes
//!   and magnitudes are checked on the JSON before it is read (the text's bytes,
//!   [`scenario::MAX_SCENARIO_BYTES`]; `scenario::MAX_COUNT`, `MAX_MAGNITUDE`/`MIN_MAGNITUDE`
//!   through [`scenario::magnitude_problem`], which CSV cells share, `MAX_MODEL_DIM`,
//!   [`scenario::MAX_TEXT_CHARS`], [`scenario::LIST_LIMITS`], naming the path; the command
//!   line reads every file through one bounded reader that stops a byte past its limit); every SVD and
//!   symmetric eigendecomposition goes through [`linalg::try_svd`] /
//!   [`linalg::try_symmetric_eigen`] (non-finite input refused, sweeps capped: nalgebra panics
//!   on NaN and never converges on ∞); [`scenario::check_finite`], the one finiteness check of every
//!   output, turns a non-finite number of a report, a cursor's detail or a study's result
//!   (plain or merged) into an error naming its field (`report.…`, `study.…`), and the CSV
//!   table refuses a non-finite cell as `csv.<column> at t=…`; no output holds a `null` that
//!   stands for a number or an absent comparison (an absent count is an absent key). A merge
//!   checks every part before adding: no count above its runs ([`study::Tally::counts`]),
//!   every sum checked ([`study::add_count`]), ranges in the study, disjoint and, to complete,
//!   tiling it. The fuzzer (`tests/suite/fuzz.rs`)
//!   holds all three to account, and at length the campaign (`cargo run --profile bench
//!   --example campaign`, `tests/fuzz/`: every method, CSV files, merge parts, shard edges,
//!   garbage and the binary itself; README "Long fuzz campaign"); the README's Limits table gives each limit's reason. Past the
//!   per-field limits, one work budget ([`scenario::budget`]) bounds what fields multiply into:
//!   each method's scenario file estimates a report's (or a study's preparation and one run's)
//!   operations and bytes from the sizes alone, and [`scenario::Scenario::run`] and
//!   [`scenario::Scenario::study`] refuse past [`scenario::budget::MAX_OPERATIONS`] (about 2 s
//!   natively) or [`scenario::budget::MAX_BYTES`] before any work, naming the field of the
//!   largest term, its formula and the limit. Ranges read in words ("a whole number from 1 to
//!   80"), never Rust's `1..=80`.
//! * Every error names a field of the scenario schema, by its JSON path (`model.F[1][1]`,
//!   `glls.monte_carlo.runs`), and says in JSON words what belongs there: parse errors never
//!   show a Rust type ([`scenario::parse`]; `tests/suite/messages.rs` replaces every leaf of
//!   every preset by a string and checks the path and the words), unknown keys and names list
//!   the accepted ones, and user strings are cut at [`error::ECHO_CHARS`] by
//!   [`error::quoted`]. Solver failures name the field most likely responsible with a hint
//!   ([`solve::Blame`]), and every solve is capped in iterations and time
//!   ([`solve::MAX_ITERATIONS`], [`solve::TIME_LIMIT_SECONDS`]).
//! * Every random stream takes a seed and is a named generator (ChaCha8; the SCF Monte Carlo's
//!   `experiment.rng` may name xoshiro256++ instead, [`scf::Generator`]), so a scenario with a
//!   seed gives the same report natively and in the browser; given explicit `data`, a report is
//!   deterministic and native = wasm to 1e-9 relative (`tests/suite/determinism.rs`; every
//!   preset's report against a native golden digest in `tests/suite/registry.rs`). Exceptions:
//!   the GLLS Monte Carlo's error quartiles (up to 1.5e-4 relative; held to 1e-3) and the small
//!   singular values of an ill-conditioned Γ_{s+1} (held to 1e-6), because the last bit of a
//!   libm call (glibc natively, Rust's libm in wasm) is amplified there.
//! * A study's run i draws its randomness from a stream fixed by the study's seed and i
//!   ([`study::run_stream`]: ChaCha8 stream i of the seed; the set-membership guarantee: seed
//!   base + i), or by the seed and i's batch for a study that draws [`study::Runs::batch`] runs
//!   side by side (SCF: one stream per independent block of the model, of the generator
//!   `experiment.rng` names (ChaCha8 when absent, so older scenarios keep their counts), read in batches of 8
//!   runs; a shard that starts at run a draws and drops what runs 0 … a − 1 drew). Never from
//!   what ran before it in the same process: so the counts of any run range are the same
//!   whatever the chunking, the sharding or the number of workers, and merged parts give the
//!   unsharded result bit for bit (`tests/suite/shards.rs`). JSON text keeps every f64
//!   (serde_json's `float_roundtrip`), so parts passed as files or between workers merge
//!   exactly too.
//! * Time is 1-based as in the papers (Tempo's and Gubarev & Mishchenko's y(0) is the first row);
//!   which set each method gives at which time from which data is one table, README "Your own
//!   record"; a record's own times are read out beside the index, never instead of it. A
//!   report has one step per record row, gaps included; a `null` in a report's `y` is a gap and
//!   the only null that stands where a number could; JSON matrices are lists of rows; every number in a report
//!   is a JSON number; an ellipsoid is `{"center", "cov", "radius2"}` meaning
//!   (x − c)ᵀ cov⁻¹ (x − c) ≤ radius2.
//!
#![doc = include_str!("errata.md")]
//!
//! ## How the LSCR region is exact and fast
//!
//! Every g_{i,l}(x) = c − d·x is affine, so X̂ is a union of cells of a line arrangement. The
//! raster finds, per pixel row and function, the one column where g changes sign (starting
//! from the analytic root and checking with the same floating-point expression the brute force
//! uses, so both agree bit for bit) and counts signs with difference arrays; hatching and
//! boundaries are exact pieces of lines ([`sets::SignRegion::spans`],
//! [`sets::SignRegion::boundary`]).
//!
//! ## How the robot Monte Carlo is fast
//!
//! [`scf::ConditionalExperiment`] draws, per run, the measurements y_1..y_{t_c} from
//! their exact law given x_{t_c} = x_c by a Kalman filter run backwards on the backward
//! representation (innovations form: q normals per step instead of n + q), then runs the KF
//! forward; SCF regions are affine in the KF estimate with data-independent shapes. The model is
//! split into independent blocks (the robots' four axes), each on fixed-size arrays, eight runs
//! side by side.
//!
//! ## How the module stays small
//!
//! About a third of the wasm module is serde's code, one copy per type and per reader or
//! writer, so each type has one reader: text is read once into a `serde_json::Value`
//! ([`scenario::parse::read_json`]) and every scenario, view, report and precision study is
//! read from a `&Value` ([`scenario::parse::from_value`]; the reports without paths), never
//! straight from text. Presets are scenario JSON text or Rust values, never
//! `serde_json::json!` (its expansion of the four Tempo presets was ~75 KB). Numbers are
//! sorted through [`linalg`]'s three sorts: each distinct comparison closure is another ~5 KB
//! copy of the standard library's sort. The README's "Module size" gives the measurements.
//!
//! ## Toolchain facts the build relies on
//!
//! Measured on the Debian machines this is built on; `.ci/`, `Cargo.toml`, `webdriver.json`
//! and the tests depend on them.
//!
//! * `wasm-bindgen` is pinned exactly (`"=X.Y.Z"` in `Cargo.toml`) and `.ci/setup` installs
//!   `wasm-bindgen-cli` at the version in `Cargo.lock`: otherwise wasm-pack silently installs its own copy
//!   (`--mode no-install` makes a mismatch an error). `cargo install wasm-bindgen-cli --locked`
//!   fails (a pinned transitive crate is missing from the registry), so setup installs without
//!   `--locked`.
//! * Debian's wasm-opt (binaryen 108) silently corrupts the module (the page dies with
//!   "WebAssembly.Table.set(): Argument 1 is invalid"), and with no wasm-opt on `PATH`
//!   `wasm-pack build --release` tries to download one and fails: every wasm-pack profile in
//!   `Cargo.toml` sets `wasm-opt = false`. npm's binaryen 132 (`www/package.json`, an exact
//!   version; a wasm-opt compiled to JavaScript, run by Node) reads the module correctly:
//!   `.ci/build` runs it after wasm-pack, `-Os --one-caller-inline-max-function-size 100`
//!   (binaryen's default inlines every function with one caller, and V8's first runs of the
//!   bigger functions were 1.5× slower), taking the features from the module's
//!   `target_features` section. `wasm-pack test` never runs wasm-opt, so only a page load
//!   catches a bad module: the end-to-end layer of `.ci/test` loads the *release* build.
//! * wasm32-unknown-unknown already aborts on panic (`panic-strategy: abort` in the target
//!   spec), so `panic = "abort"` in a profile changes nothing there; the panic hook
//!   (`console_error_panic_hook`) still prints the message before the trap.
//! * Always pass `--chromedriver /usr/bin/chromedriver` (Debian's `chromium-driver`) to
//!   `wasm-pack test`: without it wasm-pack tries to download a chromedriver.
//! * `webdriver.json` in the crate root gives Chromium the flags that stop its background
//!   network calls (`--disable-background-networking`, `--disable-component-update`, …) next
//!   to `--headless=new` and `--no-sandbox`, and sets the WebDriver script timeout to 300 s.
//!   The suite's synchronous tests hold the page for about 40 s in one stretch; the runner reads
//!   their output with `execute/sync`, which otherwise fails after the default 30 s ("Timed out
//!   receiving message from renderer: 30.000", then "missing field `chunk`").
//! * Firefox (the fourth test layer): pass `--geckodriver "$(command -v geckodriver)"` (a
//!   `cargo install`ed geckodriver 0.37.1) or wasm-pack downloads one. Debian's `firefox-esr`
//!   runs headless as root with no extra settings (no `MOZ_HEADLESS`, no profile, no
//!   `moz:firefoxOptions` in `webdriver.json`: the runner passes `-headless` itself). The smoke
//!   test gives selenium-webdriver the geckodriver and firefox paths, so selenium's driver
//!   manager (which would go online) never runs; selenium-webdriver 4.46.0 is the last release
//!   that supports Node 20. Firefox measures text wider than Chromium (DejaVu Sans "Xg" at
//!   14 px: 18.5 px against 17.1 px), so a figure near its size limit in one browser may refuse
//!   in the other.
//! * statrs 0.19 (0.19.1): 0.18.0 returns NaN from `ChiSquared::inverse_cdf` in the lower tail
//!   for small degrees of freedom (p = 0.01, k = 1). [`stats::chi2_quantile`] still round-trips
//!   every quantile and turns a failure into an error, never a NaN ellipse.
//! * clarabel 0.11 keeps its default features (with `default-features = false` it does not
//!   compile); it times itself with `web-time`, so its `solve()` runs in Chromium — the wasm
//!   runs of `tests/suite/ubb.rs` and `tests/suite/uniform.rs` call it.
//! * `std::time::Instant` panics on wasm32-unknown-unknown: the core never reads the clock
//!   (see Invariants); only native-only code (the figure tests, `cargo bench`) uses it.
//! * rand 0.10 with `default-features = false, features = ["std"]` and seeded ChaCha8 or
//!   xoshiro256++ (`rand::rngs::Xoshiro256PlusPlus`, built without a feature) only: no
//!   getrandom is built on either target (OS entropy would need getrandom 0.4 with `wasm_js` in
//!   the browser). nalgebra and statrs are built without rand, so there is one rand line
//!   (`cargo tree -d`). Never `StdRng` or `thread_rng` (not portable across versions);
//!   `tests/suite/determinism.rs` pins the first draws of a seed.
//! * plotters' text layout panics inside a Web Worker: the page draws on the main thread (a
//!   worker may compute, never draw): the panels' compute workers send reports back as JSON and
//!   `Session::set_report` keeps them for drawing. Static hosts cannot send COOP/COEP, so no
//!   wasm threads (each worker has its own instance and memory).
//! * A figure's legend lies beside or below its charts, never over them, unless the figure is
//!   too small for that (below would leave the chart under 60 % of the height or under 150 px):
//!   then it overlays the emptiest corner. [`plot::Frame::legends`] gives the boxes, and the
//!   tests check them against the plotting areas at the page's sizes (a phone's figures are
//!   4:5, so none overlays there). Notes under a title that do not fit end in "…".
//! * plotters leaves the device-pixel ratio to the caller: `www/figure.js` sizes each canvas's
//!   backing store by `devicePixelRatio`; the e2e tests check it at DPR 1 and 2.
//! * A headless `chromium --screenshot` may fire before the wasm has loaded: the e2e harness
//!   drives Debian's Chromium through playwright-core (`executablePath: '/usr/bin/chromium'`)
//!   and waits for `document.body.dataset.ready === "1"`.
//! * An SVD is accurate to about ε·σ_max in absolute terms, whatever the library: the smallest
//!   singular values of an ill-conditioned Γ_{s+1} lose relative accuracy. [`glls::Curves`]
//!   never forms a tall SVD (QR updates of an n×n factor) and reports the floor
//!   ε·σ₁·√(m(s+1)) below which σ's are not resolved ([`glls::Curves::log10_floor`]).

pub mod bench;
pub mod conformal;
pub mod error;
#[cfg(not(target_arch = "wasm32"))]
pub mod gallery;
pub mod glls;
pub mod kalman;
pub mod linalg;
pub mod lscr;
pub mod method;
pub mod model;
pub mod parse;
pub mod plot;
pub mod precision;
pub mod presets;
pub mod scenario;
pub mod scf;
pub mod sets;
pub mod solve;
pub mod stats;
pub mod study;
pub mod ubb;
pub mod uniform;
#[cfg(target_arch = "wasm32")]
pub mod web;

pub use error::{Error, Result};
pub use method::Method;
pub use study::Study;

// The unit tests (`#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test)]` in the modules) run in
// Chromium under `wasm-pack test --chrome`; without this line wasm-bindgen-test skips them
// ("only configured to run in node.js").
#[cfg(all(test, target_arch = "wasm32"))]
wasm_bindgen_test::wasm_bindgen_test_configure!(run_in_browser);
