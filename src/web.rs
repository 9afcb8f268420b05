//! WebAssembly bindings of the explorer page (`www/`): JSON in, JSON out, nothing computed here.
//!
//! ```js
//! import init, { presets, dataShape, withCsvData, Session, Study } from './pkg/confset.js';
//! await init();
//! const list = JSON.parse(presets());            // [{name, label, menu, description, scenario}, …]
//! const shape = JSON.parse(dataShape(json));     // {outputs: q, inputs: r}: the CSV columns
//! const withData = withCsvData(json, csvText, 'real.csv'); // the scenario with the file's data
//! const header = JSON.parse(csvColumns(csvText)); // {columns: [names], time: k or null}
//! const chosen = withCsvData(json, csvText, 'real.csv', ['flow']); // y1 = the column 'flow'
//! const first = JSON.parse(firstAccepted(json)); // {field, value}: an animation's first step
//! const s = new Session();
//! const report = JSON.parse(s.run(JSON.stringify(list[0].scenario)));
//! // The page runs scenarios in a Web Worker (its own instance: `www/worker.js`) and draws the
//! // report it sends back on the main thread: `s.setReport(reportJson)` keeps it for `draw`.
//! const frame = JSON.parse(s.draw(canvas, '{"panel":"state","time":20}', devicePixelRatio));
//! const svg = s.svg('{"panel":"coverage"}', 800, 500);
//! const csv = s.csv();                          // what `confset run --format csv` prints
//!
//! // A time cursor (ubb's step k, uniform's t): the worker prepares the scenario once and
//! // computes any step's detail; the page puts it into the kept report and draws that step.
//! const c = new Cursor(JSON.stringify(ubbScenario));   // throws for a method without one
//! const at = c.at(12);                                  // JSON of report.ubb.at at k = 12
//! s.setAt(at);                                          // the kept report now shows k = 12
//! s.draw(canvas, '{"panel":"ubbset","time":12}', devicePixelRatio);
//!
//! // Every method's Monte Carlo through one class (0: the scenario's own run count):
//! // SCF `experiment`, LSCR `lscr.coverage`, GLLS `glls.monte_carlo`, ubb `ubb.guarantee`.
//! const e = new Study(JSON.stringify(scenario), 0);
//! while (!e.finished()) result = JSON.parse(e.step(500));  // what `confset experiment` prints
//!
//! // The same study spread over Web Workers: worker i of N runs its shard and posts partials;
//! // the main thread merges the latest ones (each merge replaces the counts).
//! const w = new Study(JSON.stringify(scenario), 0); w.restrict(i, N);
//! while (!w.finished()) { w.step(500); postMessage(w.partial()); }      // in worker i
//! const all = new Study(JSON.stringify(scenario), 0);                   // main thread
//! result = JSON.parse(all.merge('[' + latestPartials.join(',') + ']')); // after every slice
//!
//! // LSCR (method "lscr"): the kept report's 2-D region as a membership raster over its window,
//! // and the chunked coverage experiment at a fixed true state.
//! const r = JSON.parse(s.run(JSON.stringify(lscrScenario)));
//! const mask = s.raster(512, 512);        // Uint32Array, row 0 on top: 0 = in X̂, bit l = outside X̂_l
//!
//! // A study's result enters the kept report through one path for every method
//! // (`Report::set_study`; a method whose report holds none refuses). GLLS: the page runs its
//! // scenario without glls.monte_carlo (fast) and the Monte Carlo of Section 5 apart, in
//! // chunks; its result becomes the report's glls.precision, which the "precision" panel draws.
//! const g = new Study(JSON.stringify(withMonteCarlo), 0);     // needs glls.monte_carlo
//! while (!g.finished()) study = JSON.parse(g.step(100));     // PrecisionReport so far
//! s.setStudy(JSON.stringify(study));                          // report.glls.precision = study
//!
//! // The kept report's time cursor (ubb, uniform_lp, compare): the steps it moves over, from
//! // the core (a slider value outside them shows the nearest); undefined without one.
//! const [first, last] = s.cursorSteps();
//! // The probability an ellipsoid of the report holds (its χ² level): ubb's Kalman ellipse.
//! const level = ellipsoidLevel(JSON.stringify(report.ubb.at.kf));   // 0.99
//!
//! // Set-membership (method "ubb"): fresh simulations checked at the scenario's step k, in
//! // chunks — the truth must never leave the set, the Kalman ellipsoid may.
//! const u = new Study(JSON.stringify(ubbScenario), 2000);
//! while (!u.finished()) c = JSON.parse(u.step(50));  // {runs, total, outside, kf_outside, …}
//! ```
//!
//! Every error is thrown as a JS `Error` whose `message` is the crate [`Error`]'s text (it
//! starts with the offending field, e.g. "model.V must be symmetric …") and whose `field`
//! property is that field alone (`""` when the error is not about one field).
//!
//! Canvas and device pixels: [`Session::draw`] takes the canvas whose backing store the page
//! sized as CSS size × devicePixelRatio, and the ratio. It scales the 2-D context by the ratio
//! and hands the figure code a backend of the CSS size, so a figure has the same layout (font
//! sizes, line widths in CSS pixels) at every ratio, only sharper. The returned [`Frame`]'s
//! `plot_area` is therefore in CSS pixels of the canvas, like `MouseEvent.offsetX/Y`.

use crate::error::Error;
use crate::plot::{self, Frame, View};
use crate::presets;
use crate::scenario::lscr::plane_region;
use crate::scenario::{Report, Scenario};
use plotters::prelude::DrawingBackend;
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind,
};
use plotters_canvas::CanvasBackend;
use serde::{Deserialize, Serialize};
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;
use web_sys::{CanvasRenderingContext2d, HtmlCanvasElement};

/// A JS `Error` with the crate error's message and a `field` property.
fn js_error(e: &Error) -> JsValue {
    let err = js_sys::Error::new(&e.to_string());
    // Setting a property on a fresh Error object cannot fail; if it ever did, the message
    // (which starts with the field) is still there.
    let _ = js_sys::Reflect::set(
        &err,
        &JsValue::from_str("field"),
        &JsValue::from_str(&e.field),
    );
    err.into()
}

fn to_json<T: Serialize>(what: &str, v: &T) -> Result<String, JsValue> {
    serde_json::to_string(v).map_err(|e| {
        js_error(&Error::field(
            "",
            format!("{what} could not be written as JSON: {e}"),
        ))
    })
}

fn parse_view(view_json: &str) -> Result<View, JsValue> {
    crate::scenario::parse::from_json(view_json, "view").map_err(|e| js_error(&e))
}

/// Install the panic hook (diagnostics only: no panic is reachable from any input).
#[wasm_bindgen(start)]
pub fn start() {
    console_error_panic_hook::set_once();
}

/// Time each method of a compare (`sets[i].seconds`) by the worker's clock (`performance.now`):
/// the compute worker calls it once; the core never reads a clock itself.
#[wasm_bindgen(js_name = timeCompare)]
pub fn time_compare() {
    crate::scenario::compare::set_clock(now_seconds);
}

/// `performance.now()` of the global scope (window or worker) in seconds; `Date.now()` without it.
fn now_seconds() -> f64 {
    use wasm_bindgen::JsCast;
    let global = js_sys::global();
    js_sys::Reflect::get(&global, &JsValue::from_str("performance"))
        .ok()
        .and_then(|perf| {
            let now = js_sys::Reflect::get(&perf, &JsValue::from_str("now")).ok()?;
            let now: js_sys::Function = now.dyn_into().ok()?;
            now.call0(&perf).ok()?.as_f64()
        })
        .unwrap_or_else(js_sys::Date::now)
        / 1000.0
}

/// Test only: aborts the module's instance (a wasm trap, as a panic or an allocation failure
/// does here), so the page's tests can check that a failed computation is contained: the
/// compute worker is replaced and the panel keeps its picture. No scenario, link or file
/// reaches it: only the worker's test message (`www/worker.js`) calls it.
#[wasm_bindgen(js_name = testOnlyAbort)]
pub fn test_only_abort() {
    std::process::abort()
}

/// Every preset as JSON: `[{"name", "description", "scenario"}, …]` in menu order.
#[wasm_bindgen]
pub fn presets() -> Result<String, JsValue> {
    to_json("the preset list", &presets::all())
}

/// The core's limits on the page's fields (`scenario::limits`): `{"simulate.steps": {method:
/// [min, max]}, "runs": [1, max], "uniform.window": [1, max]}`.
#[wasm_bindgen]
pub fn limits() -> String {
    crate::scenario::limits().to_string()
}

/// Every figure of a method's reports, in the order worth showing (`plot::method_panels`):
/// JSON `[{"panel": "state", "alt": "state plane at …"}, …]`; the page builds its figure cards
/// from it. An unknown method is a `method` error.
#[wasm_bindgen(js_name = methodPanels)]
pub fn method_panels(method: &str) -> Result<String, JsValue> {
    let m: crate::method::Method =
        crate::scenario::parse::from_value(&serde_json::Value::from(method), "method")
            .map_err(|e| js_error(&e))?;
    let list: Vec<_> = plot::method_panels(m)
        .iter()
        .map(|p| serde_json::json!({"panel": p.name(), "alt": p.alt_text()}))
        .collect();
    to_json("the panel list", &list)
}

/// The scenario (JSON) with `data` read from the CSV text of the file `name`, no `simulate`
/// block and titled after the file (the core's `Scenario::with_csv_file_columns`: the same
/// reader as `confset run --data`). `columns` (optional, a JS array of strings) names the
/// header's columns to read as y1 … yq, then u1 … ur (`--columns`); without it the header's
/// own names decide. Errors name `data`, `data.y`, `data.u`, `data.t`, `columns` (a name
/// chosen) or the model field the data's shape cannot be read from. The page calls it in the
/// panel's worker: a 20 MB file takes a fifth of a second to read.
#[wasm_bindgen(js_name = withCsvData)]
pub fn with_csv_data(
    scenario_json: &str,
    csv: &str,
    name: &str,
    columns: Option<Vec<String>>,
) -> Result<String, JsValue> {
    let s = Scenario::from_json(scenario_json)
        .and_then(|s| s.with_csv_file_columns(csv, name, columns.as_deref().unwrap_or(&[])))
        .map_err(|e| js_error(&e))?;
    to_json("the scenario", &s)
}

/// The CSV text's header for the page's column picker (JSON `{"columns": [names], "time": k}`):
/// the header's names (`[]` when the file has none; an unnamed column is `""`) and the index
/// of the column read as the record's time when no column is chosen (`null`: none). Only the
/// lines up to the header are read (`scenario::csv::csv_columns`, `csv_time_column`).
#[wasm_bindgen(js_name = csvColumns)]
pub fn csv_columns(csv: &str) -> Result<String, JsValue> {
    use crate::scenario::csv;
    let columns = csv::csv_columns(csv).map_err(|e| js_error(&e))?;
    let time = csv::csv_time_column(&columns);
    to_json(
        "the CSV header",
        &serde_json::json!({"columns": columns, "time": time}),
    )
}

/// The shape of the scenario's `data` (JSON `{"outputs": q, "inputs": r}`): the columns a CSV
/// file needs (y1 … yq, then optionally u1 … ur), for the page's hint.
#[wasm_bindgen(js_name = dataShape)]
pub fn data_shape(scenario_json: &str) -> Result<String, JsValue> {
    let (outputs, inputs) = Scenario::from_json(scenario_json)
        .and_then(|s| s.data_shape())
        .map_err(|e| js_error(&e))?;
    to_json(
        "the data shape",
        &serde_json::json!({"outputs": outputs, "inputs": inputs}),
    )
}

/// The quantity the scenario's view animates by rerunning (LSCR's `simulate.steps`, GLLS's
/// `glls.horizon`) and its smallest value the method accepts (JSON `{"field", "value"}`:
/// [`Scenario::first_accepted`]); throws for a method that animates nothing by rerunning.
/// The page's worker asks it once per scenario, when an animation first needs its start.
#[wasm_bindgen(js_name = firstAccepted)]
pub fn first_accepted(scenario_json: &str) -> Result<String, JsValue> {
    let first = Scenario::from_json(scenario_json)
        .and_then(|s| s.first_accepted())
        .map_err(|e| js_error(&e))?;
    to_json("the first accepted value", &first)
}

/// Runs scenarios and draws the last good report.
#[wasm_bindgen]
#[derive(Default)]
pub struct Session {
    report: Option<Report>,
}

#[wasm_bindgen]
impl Session {
    #[wasm_bindgen(constructor)]
    pub fn new() -> Session {
        Session::default()
    }

    /// Validate and run a scenario (JSON); returns the report (JSON) and keeps it for drawing.
    /// On error the previous report stays and the error is thrown.
    pub fn run(&mut self, scenario_json: &str) -> Result<String, JsValue> {
        let report = Scenario::from_json(scenario_json)
            .and_then(|s| s.run())
            .map_err(|e| js_error(&e))?;
        let json = to_json("the report", &report)?;
        self.report = Some(report);
        Ok(json)
    }

    /// Keep a report computed elsewhere (its JSON, as [`Session::run`] returns it) for drawing,
    /// in place of the kept one: the page runs its scenarios in a Web Worker (a fault there
    /// cannot take the page down) and draws here, on the main thread, because plotters' text
    /// layout panics inside a worker. JSON that is not a report is a `report` error, and the
    /// kept report stays. The report is read through a `Value`, like scenarios
    /// (`scenario::parse`): serde's code for reading a `Report` from text would be another
    /// ~200 KB of the module.
    #[wasm_bindgen(js_name = setReport)]
    pub fn set_report(&mut self, report_json: &str) -> Result<(), JsValue> {
        let invalid = |why: &str| {
            js_error(&Error::field(
                "report",
                format!("is not a valid report: {why}"),
            ))
        };
        let value = crate::scenario::parse::read_json(report_json, "report")
            .map_err(|e| invalid(&e.message))?;
        let report = Report::deserialize(&value).map_err(|e| invalid(&e.to_string()))?;
        self.report = Some(report);
        Ok(())
    }

    /// Put a detail of the report's time cursor (the JSON text [`Cursor::at`] returns, computed
    /// in the worker) into the kept report: its `at` block and `time` become those of the
    /// report run at that step, so `draw` draws that step (`Report::set_at`). JSON that is not
    /// a detail of the kept report's method is an `at` error, and the kept report stays.
    #[wasm_bindgen(js_name = setAt)]
    pub fn set_at(&mut self, at_json: &str) -> Result<(), JsValue> {
        let at: serde_json::Value = serde_json::from_str(at_json)
            .map_err(|e| js_error(&Error::field("at", format!("is not JSON: {e}"))))?;
        self.report
            .as_mut()
            .ok_or_else(|| js_error(&Error::field("", "no report yet: run a scenario first")))?
            .set_at(at)
            .map_err(|e| js_error(&e))
    }

    /// The panels worth drawing for the kept report (`plot::useful_panels`), JSON `["state",
    /// "series", …]`: `[]` before the first good run.
    #[wasm_bindgen(js_name = usefulPanels)]
    pub fn useful_panels(&self) -> String {
        let names: Vec<&str> = self
            .report
            .as_ref()
            .map(|r| plot::useful_panels(r).iter().map(|p| p.name()).collect())
            .unwrap_or_default();
        serde_json::Value::from(names).to_string()
    }

    /// The time the kept report shows (its `time`: the step of its `at` for a method with a
    /// time cursor), or undefined before the first good run.
    #[wasm_bindgen(js_name = shownTime)]
    pub fn shown_time(&self) -> Option<usize> {
        self.report.as_ref().map(|r| r.time)
    }

    /// Whether a report is kept (a `run` has succeeded).
    #[wasm_bindgen(js_name = hasReport)]
    pub fn has_report(&self) -> bool {
        self.report.is_some()
    }

    /// Draw a view (JSON `{"panel": "state"|"series"|"coverage"|"region"|…, "time": t, "zoom":
    /// "auto"|"regions"|"full"}`, every field optional) of the kept report on `canvas`, whose
    /// backing store is `dpr` × its CSS size. The title and axis names come with the report
    /// (`Report::figure`), as for `confset figure`. Returns the frame (JSON) with `plot_area` in
    /// CSS pixels.
    pub fn draw(
        &self,
        canvas: HtmlCanvasElement,
        view_json: &str,
        dpr: f64,
    ) -> Result<String, JsValue> {
        let report = self.kept()?;
        let view = parse_view(view_json)?;
        let dpr = if dpr.is_finite() && dpr >= 0.25 {
            dpr
        } else {
            1.0
        };
        let ctx: CanvasRenderingContext2d = canvas
            .get_context("2d")
            .ok()
            .flatten()
            .and_then(|c| c.dyn_into().ok())
            .ok_or_else(|| js_error(&Error::field("canvas", "has no 2-D context")))?;
        ctx.set_transform(dpr, 0.0, 0.0, dpr, 0.0, 0.0)
            .map_err(|_| js_error(&Error::field("canvas", "refused the pixel-ratio transform")))?;
        let size = (
            ((canvas.width() as f64) / dpr).round().max(1.0) as u32,
            ((canvas.height() as f64) / dpr).round().max(1.0) as u32,
        );
        ctx.clear_rect(0.0, 0.0, size.0 as f64, size.1 as f64);
        let inner = CanvasBackend::with_canvas_object(canvas)
            .ok_or_else(|| js_error(&Error::field("canvas", "has no 2-D context")))?;
        let frame: Frame =
            plot::draw(Scaled::new(inner, ctx, size), report, &view).map_err(|e| js_error(&e))?;
        to_json("the frame", &frame)
    }

    /// A view of the kept report as SVG text, `w` × `h` pixels.
    pub fn svg(&self, view_json: &str, w: u32, h: u32) -> Result<String, JsValue> {
        let report = self.kept()?;
        let view = parse_view(view_json)?;
        if !(16..=8192).contains(&w) || !(16..=8192).contains(&h) {
            return Err(js_error(&Error::field(
                "size",
                "must be a whole number from 16 to 8192 pixels",
            )));
        }
        plot::report_svg(report, &view, w, h).map_err(|e| js_error(&e))
    }

    /// The kept report's table as CSV text (`Report::table`, one row per time step): the same
    /// text `confset run --format csv` prints for its scenario. A cell that is not a finite
    /// number is a `csv.<column>` error, as for the CLI.
    pub fn csv(&self) -> Result<String, JsValue> {
        let table = self.kept()?.table().map_err(|e| js_error(&e))?;
        Ok(table.to_csv())
    }
}

#[wasm_bindgen]
impl Session {
    /// Membership raster of the kept LSCR report's drawn region (X̂, or its 2-D slice for
    /// n > 2) over the report's window, `width` × `height` pixel centres, row 0 on top:
    /// entry 0 when the pixel centre is in X̂, else bit l set when it is outside X̂_l (bit 31
    /// for every l ≥ 31). Exact, like the figure (`SignRegion::raster`).
    pub fn raster(&self, width: u32, height: u32) -> Result<Vec<u32>, JsValue> {
        let l = self.kept()?.lscr.as_ref().ok_or_else(|| {
            js_error(&Error::field(
                "method",
                "the kept report is not an LSCR report: run a scenario with \"method\": \"lscr\" first",
            ))
        })?;
        if !(1..=4096).contains(&width) || !(1..=4096).contains(&height) {
            return Err(js_error(&Error::field(
                "size",
                format!("{width} × {height}: the raster must have 1 to 4096 pixels each way"),
            )));
        }
        plane_region(&l.region, l.plot, l.slice_at.as_deref())
            .and_then(|p| p.raster(&l.window, width as usize, height as usize))
            .map(|g| g.excluded)
            .map_err(|e| js_error(&e))
    }
}

#[wasm_bindgen]
impl Session {
    /// Put a study's result (its JSON, as [`Study::step`] returns it; `"null"` removes it) into
    /// the kept report where a run with the study would hold it (`Report::set_study`: GLLS's
    /// `glls.precision`, which the `"precision"` panel draws), one path for every method; a
    /// method whose report holds no study result refuses, and the kept report stays. The next
    /// `run` or `setReport` replaces the kept report (and so drops the study).
    #[wasm_bindgen(js_name = setStudy)]
    pub fn set_study(&mut self, result_json: &str) -> Result<(), JsValue> {
        let result =
            crate::scenario::parse::read_json(result_json, "study").map_err(|e| js_error(&e))?;
        self.report
            .as_mut()
            .ok_or_else(|| js_error(&Error::field("", "no report yet: run a scenario first")))?
            .set_study(result)
            .map_err(|e| js_error(&e))
    }

    /// One step of the kept report, step by step (`Scenario::explain`, JSON
    /// `{method, paper, t, point?, title, rows: [{name, equation, tex, value, note}]}`):
    /// `scenario_json` is the scenario the kept report was run from, `t` the step (the
    /// report's time when undefined), `x`, `y` a point of the figure's plane (LSCR's sums are
    /// evaluated there; the report's estimate when undefined). A method without a
    /// step-through, a step out of range or a point that is not finite is an error in words.
    pub fn explain(
        &self,
        scenario_json: &str,
        t: Option<u32>,
        x: Option<f64>,
        y: Option<f64>,
    ) -> Result<String, JsValue> {
        let report = self.kept()?;
        let scenario = Scenario::from_json(scenario_json).map_err(|e| js_error(&e))?;
        let point = match (x, y) {
            (Some(x), Some(y)) => Some([x, y]),
            (None, None) => None,
            _ => {
                return Err(js_error(&Error::field(
                    "explain.x",
                    "needs both coordinates of the point, or neither",
                )))
            }
        };
        let e = scenario
            .explain(
                report,
                t.map(|t| t as usize),
                point.as_ref().map(|p| &p[..]),
            )
            .map_err(|e| js_error(&e))?;
        to_json("the step", &e)
    }

    /// The steps the kept report's time cursor moves over, `[first, last]`
    /// (`Report::cursor_steps`: ubb's first step with a bounded set, uniform_lp's times,
    /// compare's); undefined before the first good run or for a method without a cursor.
    #[wasm_bindgen(js_name = cursorSteps)]
    pub fn cursor_steps(&self) -> Option<Vec<u32>> {
        let steps = self.report.as_ref()?.cursor_steps()?;
        Some(vec![*steps.start() as u32, *steps.end() as u32])
    }
}

/// The level of an ellipsoid of a report (JSON `{"center", "cov", "radius2"}`, e.g. ubb's
/// Kalman ellipse `report.ubb.at.kf`): the probability its Gaussian gives it, the χ² CDF at
/// radius² in its dimension (`stats::ellipsoid_level`, the inverse of the quantile the method
/// made radius² with). JSON that is not an ellipsoid is an `ellipsoid` error.
#[wasm_bindgen(js_name = ellipsoidLevel)]
pub fn ellipsoid_level(ellipsoid_json: &str) -> Result<f64, JsValue> {
    let e: crate::sets::Ellipsoid =
        crate::scenario::parse::from_json(ellipsoid_json, "ellipsoid").map_err(|e| js_error(&e))?;
    crate::stats::ellipsoid_level(e.radius2, e.center.len()).ok_or_else(|| {
        js_error(&Error::field(
            "ellipsoid",
            format!(
                "has no level: radius² {} in {} dimensions",
                e.radius2,
                e.center.len()
            ),
        ))
    })
}

impl Session {
    fn kept(&self) -> Result<&Report, JsValue> {
        self.report
            .as_ref()
            .ok_or_else(|| js_error(&Error::field("", "no report yet: run a scenario first")))
    }
}

/// The Monte Carlo study of any method's scenario (the SCF conditional experiment, the LSCR
/// coverage experiment, the GLLS Section 5 study, the set-membership guarantee), run in chunks
/// so the page stays responsive and can cancel (by dropping it). `runs` (0: the scenario's own)
/// overrides the run count. Its result is the same JSON `confset experiment` prints.
#[wasm_bindgen]
pub struct Study {
    inner: Box<dyn crate::study::Study>,
}

#[wasm_bindgen]
impl Study {
    #[wasm_bindgen(constructor)]
    pub fn new(scenario_json: &str, runs: u32) -> Result<Study, JsValue> {
        let runs = (runs > 0).then_some(runs as usize);
        let inner = Scenario::from_json(scenario_json)
            .and_then(|s| s.study(runs))
            .map_err(|e| js_error(&e))?;
        Ok(Study { inner })
    }

    /// Run up to `runs` more runs (never past the total); returns the result so far (JSON).
    pub fn step(&mut self, runs: u32) -> Result<String, JsValue> {
        self.inner.step(runs as usize).map_err(|e| js_error(&e))?;
        self.result()
    }

    /// The result so far (JSON, as [`Study::step`]).
    pub fn result(&self) -> Result<String, JsValue> {
        let v = self.inner.result().map_err(|e| js_error(&e))?;
        to_json("the study result", &v)
    }

    /// Runs done so far.
    pub fn runs(&self) -> usize {
        self.inner.runs()
    }

    /// Runs asked for.
    pub fn total(&self) -> usize {
        self.inner.total()
    }

    pub fn finished(&self) -> bool {
        self.inner.finished()
    }

    /// Do only shard `shard_index` of `shard_count` (0-based), before the first step: one Web
    /// Worker's share of the runs.
    pub fn restrict(&mut self, shard_index: usize, shard_count: usize) -> Result<(), JsValue> {
        self.inner
            .restrict(shard_index, shard_count)
            .map_err(|e| js_error(&e))
    }

    /// The counts so far with the runs they cover (JSON text), for `merge` on another `Study`
    /// of the same scenario.
    pub fn partial(&self) -> Result<String, JsValue> {
        let v = self.inner.partial().map_err(|e| js_error(&e))?;
        to_json("the partial counts", &v)
    }

    /// Replace the counts by the sum of the parts (a JSON array of `partial()` texts' values,
    /// e.g. `'[' + parts.join(',') + ']'`) and return the result so far (JSON, as `step`).
    /// Each call replaces the counts, so the page can merge the workers' latest partials after
    /// every slice; the study then only reports.
    pub fn merge(&mut self, parts_json: &str) -> Result<String, JsValue> {
        let parts: Vec<serde_json::Value> =
            crate::scenario::parse::from_json(parts_json, "parts").map_err(|e| js_error(&e))?;
        self.inner.merge(&parts).map_err(|e| js_error(&e))?;
        self.result()
    }
}

/// The time cursor of a scenario (`Scenario::cursor`): the run prepared once (simulation,
/// filters, the on-line estimator), then the detail of any step on demand, the JSON of the
/// report's `at` at that step, bit for bit as a run with the time field there would hold it.
/// The page's worker keeps one per scenario and answers cursor moves from it; a method whose
/// reports hold every step (SCF, KF) or have no time (LSCR, GLLS) has none: the constructor
/// throws a `method` error.
#[wasm_bindgen]
pub struct Cursor {
    inner: Box<dyn crate::scenario::Cursor>,
}

#[wasm_bindgen]
impl Cursor {
    #[wasm_bindgen(constructor)]
    pub fn new(scenario_json: &str) -> Result<Cursor, JsValue> {
        let s = Scenario::from_json(scenario_json).map_err(|e| js_error(&e))?;
        match s.cursor().map_err(|e| js_error(&e))? {
            Some(inner) => Ok(Cursor { inner }),
            None => Err(js_error(&Error::field(
                "method",
                format!(
                    "\"{}\" has no time cursor: its reports hold every step, or have none",
                    s.method
                ),
            ))),
        }
    }

    /// The first step with a detail of its own.
    pub fn first(&self) -> usize {
        *self.inner.steps().start()
    }

    /// The last step.
    pub fn last(&self) -> usize {
        *self.inner.steps().end()
    }

    /// The detail at step t (JSON text of the report's `at`); a time the run refuses throws
    /// the run's error.
    pub fn at(&mut self, t: u32) -> Result<String, JsValue> {
        let v = self.inner.at(t as usize).map_err(|e| js_error(&e))?;
        to_json("the detail", &v)
    }
}

/// A canvas backend seen at CSS size: the context is scaled by the pixel ratio, so every
/// coordinate, width and font size the figure code uses is in CSS pixels.
///
/// Text is measured with the context's `measureText` in the very font string plotters-canvas
/// draws with: plotters' own browser measurement appends a `<span>` to the page and reads its
/// size, a forced layout of the whole document per label (most of a figure's drawing time).
///
/// Lines and paths are stroked in batches: consecutive ones of the same colour and width
/// become subpaths of one canvas path, stroked once before anything else is drawn (and when
/// the figure is done), so the drawing order stays. A dashed curve is hundreds of dashes and a
/// chart's grid dozens of lines: one `stroke()` each instead of one per piece (most of the
/// canvas calls of a time figure; a cursor move redraws every figure).
struct Scaled {
    inner: CanvasBackend,
    ctx: CanvasRenderingContext2d,
    size: (u32, u32),
    /// The style of the path being built and not yet stroked: (r, g, b, alpha bits, width).
    batch: Option<(u8, u8, u8, u64, u32)>,
}

impl Scaled {
    fn new(inner: CanvasBackend, ctx: CanvasRenderingContext2d, size: (u32, u32)) -> Scaled {
        Scaled {
            inner,
            ctx,
            size,
            batch: None,
        }
    }

    /// Stroke the batch, if any.
    fn flush(&mut self) {
        if self.batch.take().is_some() {
            self.ctx.stroke();
        }
    }

    /// Add one stroked piece (`points` in canvas coordinates) to the batch of its style,
    /// starting a new batch when the style differs.
    fn stroke_piece<S: BackendStyle>(&mut self, style: &S, points: &[(f64, f64)]) {
        let c = style.color();
        let key = (
            c.rgb.0,
            c.rgb.1,
            c.rgb.2,
            c.alpha.to_bits(),
            style.stroke_width(),
        );
        if self.batch != Some(key) {
            self.flush();
            self.ctx.begin_path();
            let (r, g, b) = c.rgb;
            self.ctx
                .set_stroke_style_str(&format!("rgba({r},{g},{b},{})", c.alpha));
            self.ctx.set_line_width(style.stroke_width() as f64);
            self.batch = Some(key);
        }
        if let Some((first, rest)) = points.split_first() {
            self.ctx.move_to(first.0, first.1);
            for p in rest {
                self.ctx.line_to(p.0, p.1);
            }
        }
    }

    /// The size of `text` in the style's font: measured once per font and text (a figure's
    /// labels repeat from one draw to the next: a cursor move redraws the same axes and
    /// legends), then remembered.
    fn measure<S: BackendTextStyle>(&self, text: &str, s: &S) -> Option<(u32, u32)> {
        let font = format!(
            "{} {}px {}",
            s.style().as_str(),
            s.size(),
            s.family().as_str()
        );
        let key = (font, text.to_string());
        if let Some(size) = MEASURED.with(|m| m.borrow().get(&key).copied()) {
            return Some(size);
        }
        let size = self.measure_now(&key.0, text, s.size())?;
        MEASURED.with(|m| {
            let mut m = m.borrow_mut();
            if m.len() >= MEASURED_MAX {
                m.clear();
            }
            m.insert(key, size);
        });
        Some(size)
    }

    fn measure_now(&self, font: &str, text: &str, font_size: f64) -> Option<(u32, u32)> {
        use js_sys::{Function, Reflect};
        self.ctx.set_font(font);
        let get = |o: &JsValue, k: &str| Reflect::get(o, &JsValue::from_str(k)).ok();
        let f: Function = get(&self.ctx, "measureText")?.dyn_into().ok()?;
        let m = f.call1(&self.ctx, &JsValue::from_str(text)).ok()?;
        let num = |k: &str| {
            get(&m, k)
                .and_then(|v| v.as_f64())
                .filter(|v| v.is_finite())
        };
        let w = num("width")?;
        // The font's line box, like the height of plotters' measuring span.
        let h = match (num("fontBoundingBoxAscent"), num("fontBoundingBoxDescent")) {
            (Some(a), Some(d)) => a + d,
            _ => 1.15 * font_size,
        };
        Some((w.ceil().max(0.0) as u32, h.ceil().max(0.0) as u32))
    }
}

/// Most text sizes remembered (then they are forgotten all at once).
const MEASURED_MAX: usize = 4096;

thread_local! {
    /// Text sizes measured by the canvas, by font and text ([`Scaled::measure`]).
    static MEASURED: std::cell::RefCell<std::collections::HashMap<(String, String), (u32, u32)>> =
        std::cell::RefCell::new(std::collections::HashMap::new());
}

type Err = DrawingErrorKind<<CanvasBackend as DrawingBackend>::ErrorType>;

/// The last batch is stroked when the figure is done with the backend.
impl Drop for Scaled {
    fn drop(&mut self) {
        self.flush();
    }
}

impl DrawingBackend for Scaled {
    type ErrorType = <CanvasBackend as DrawingBackend>::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.size
    }
    fn ensure_prepared(&mut self) -> Result<(), Err> {
        self.inner.ensure_prepared()
    }
    fn present(&mut self) -> Result<(), Err> {
        self.flush();
        self.inner.present()
    }
    fn draw_pixel(&mut self, p: BackendCoord, c: BackendColor) -> Result<(), Err> {
        self.flush();
        self.inner.draw_pixel(p, c)
    }
    fn draw_line<S: BackendStyle>(
        &mut self,
        a: BackendCoord,
        b: BackendCoord,
        s: &S,
    ) -> Result<(), Err> {
        if s.color().alpha == 0.0 {
            return Ok(());
        }
        // As plotters-canvas does: a horizontal or vertical line on the pixel grid is moved by
        // half a pixel, so that it covers whole pixels instead of blurring over two.
        let (mut a, mut b) = ((a.0 as f64, a.1 as f64), (b.0 as f64, b.1 as f64));
        if a.0 == b.0 {
            a.0 -= 0.5;
            b.0 -= 0.5;
        }
        if a.1 == b.1 {
            a.1 -= 0.5;
            b.1 -= 0.5;
        }
        self.stroke_piece(s, &[a, b]);
        Ok(())
    }
    fn draw_rect<S: BackendStyle>(
        &mut self,
        a: BackendCoord,
        b: BackendCoord,
        s: &S,
        fill: bool,
    ) -> Result<(), Err> {
        self.flush();
        self.inner.draw_rect(a, b, s, fill)
    }
    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        s: &S,
    ) -> Result<(), Err> {
        if s.color().alpha == 0.0 {
            return Ok(());
        }
        let points: Vec<(f64, f64)> = path.into_iter().map(|p| (p.0 as f64, p.1 as f64)).collect();
        self.stroke_piece(s, &points);
        Ok(())
    }
    fn draw_circle<S: BackendStyle>(
        &mut self,
        c: BackendCoord,
        r: u32,
        s: &S,
        fill: bool,
    ) -> Result<(), Err> {
        self.flush();
        self.inner.draw_circle(c, r, s, fill)
    }
    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        s: &S,
    ) -> Result<(), Err> {
        self.flush();
        self.inner.fill_polygon(vert, s)
    }
    fn draw_text<S: BackendTextStyle>(
        &mut self,
        text: &str,
        s: &S,
        p: BackendCoord,
    ) -> Result<(), Err> {
        self.flush();
        self.inner.draw_text(text, s, p)
    }
    fn estimate_text_size<S: BackendTextStyle>(
        &self,
        text: &str,
        s: &S,
    ) -> Result<(u32, u32), Err> {
        match self.measure(text, s) {
            Some(wh) => Ok(wh),
            None => self.inner.estimate_text_size(text, s),
        }
    }
}

/// One kernel of the speed comparison ([`crate::bench::Kernel`]: `robot_mc`, `lscr_raster`,
/// `glls_curves`, `ubb_step`, `uniform_report`), prepared once; `run()` does it once more and
/// returns what it computed. The page never uses it: `tests/bench/kernels.mjs` times it in
/// Chromium beside the native and NumPy figures.
#[wasm_bindgen]
pub struct BenchKernel {
    run: Box<dyn FnMut() -> crate::error::Result<String>>,
}

#[wasm_bindgen]
impl BenchKernel {
    #[wasm_bindgen(constructor)]
    pub fn new(key: &str) -> Result<BenchKernel, JsValue> {
        let kernel = crate::bench::Kernel::from_key(key).map_err(|e| js_error(&e))?;
        let run = kernel.prepare().map_err(|e| js_error(&e))?;
        Ok(BenchKernel { run })
    }

    pub fn run(&mut self) -> Result<String, JsValue> {
        (self.run)().map_err(|e| js_error(&e))
    }
}
