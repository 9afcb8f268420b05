// The panels' compute client: each mounted panel runs its scenarios in a Web Worker of its own
// (worker.js, with its own wasm instance of the module the page compiled once: wasm.js), so the
// page's input is never blocked by a long run and a fault of the core (a panic or an allocation failure aborts a wasm instance, and every
// later call into it fails) takes down that worker only. The client then replaces the worker;
// the panel keeps its last picture. Drawing stays on the main thread (plotters' text layout
// panics inside a worker): the panel hands the report to its own Session (setReport).

// A run that did not end with a report or a core error: `kind` is 'crash' (the worker died or
// its instance aborted: a bug), 'timeout' (no answer within the watchdog's time: a worker that
// went silent, e.g. one the browser stopped on memory without a trap; also a bug, since every
// scenario the core accepts is budgeted to seconds), 'cancelled' (the user's Cancel) or
// 'superseded' (a newer scenario replaced a long run).
export class ComputeFault extends Error {
  constructor(kind, message) {
    super(message);
    this.name = 'ComputeFault';
    this.kind = kind;
  }
}

// Every worker start of the page, for the tests and the console: {panel, reason ('first' or
// the fault kind that replaced the previous one), readyMs (start → module loaded)}.
export const workerStarts = [];

// The live clients by panel (the panel root's id), so a browser test can reach one
// (`testOnlyAbortNextRun`, `testOnlySlowMs`); nothing in the page looks them up.
export const computeClients = new Map();

import { startWorker } from './wasm.js';

const WORKER_URL = new URL('./worker.js', import.meta.url);

// The watchdog: a job without an answer after this long ends as a 'timeout' fault and the
// worker is replaced. The core's work budget holds a report to about 2 s natively (README,
// Limits), a few times that in wasm on a slow machine; a minute is far past any accepted run.
export const WATCHDOG_MS = 60_000;

// The client of one panel: run(scenarioJson) → Promise of {report (JSON text), ms (compute time
// in the worker)}; it rejects with the core's error (an Error with `field`) or a ComputeFault.
// Jobs run one at a time in the order sent; replace(kind) ends them all (with that fault) and
// starts a fresh worker.
export function computeClient(panel) {
  let worker = null;
  let nextId = 1;
  const jobs = new Map(); // id → {resolve, reject}
  const client = {
    // Test only: the next job aborts the worker's instance instead of running (worker.js).
    testOnlyAbortNextRun: false,
    // Test only: every run first holds its worker this long (worker.js), as a long run would.
    testOnlySlowMs: 0,
    // The watchdog's time for the next jobs (a test shortens it).
    watchdogMs: WATCHDOG_MS,
    run(scenarioJson) {
      const testOnlyAbort = client.testOnlyAbortNextRun;
      client.testOnlyAbortNextRun = false;
      return post({ scenario: scenarioJson, testOnlyAbort, testOnlySlowMs: client.testOnlySlowMs }).then((d) => ({ report: d.report, ms: d.ms, cursor: keyOf(d.cursor) }));
    },
    // The detail of step t of a scenario's time cursor (worker.js): a Promise of {t, at (JSON
    // text of the report's `at` at t), cursor (the key of the cursor it comes from, as run()
    // gives it for the report)}, or of null when a newer at() came before its answer (the newest
    // request wins; a stale answer is dropped). Rejects as run() does.
    at(scenarioJson, t) {
      const mine = ++atRequests;
      return post({ cursor: { scenario: scenarioJson, t } })
        .then((d) => (d.superseded || mine !== atRequests ? null : { ...d.detail, cursor: keyOf(d.detail.cursor) }));
    },
    // The smallest value of the quantity the scenario's view animates by rerunning that the
    // core accepts (worker.js): a Promise of {field, value}. Rejects as run() does.
    firstAccepted(scenarioJson) {
      return post({ firstAccepted: scenarioJson }).then((d) => JSON.parse(d.first));
    },
    // The scenario with the data of a CSV file (worker.js: the core's reader, off the page's
    // thread), its columns chosen by the header's names when `columns` is an array (y1 … yq,
    // then u1 … ur): a Promise of the scenario object. Rejects as run() does (a refusal names
    // `data…`, or `columns` for a name chosen).
    withCsvData(scenarioJson, text, name, columns) {
      return post({ csv: { scenario: scenarioJson, text, name, columns } }).then((d) => JSON.parse(d.withData));
    },
    // Called with (cursor key, t, at JSON) for every detail the worker sends (prefetched or
    // asked for): the panel keeps those of its report's cursor.
    onDetail: null,
    // Whether a job is waiting for the worker.
    get pending() { return jobs.size > 0; },
    replace,
  };

  // One job to the current worker (a new one if the last never loaded), with its watchdog.
  function post(message) {
    if (!worker) start('retry'); // the last one never loaded
    const id = nextId++;
    return new Promise((resolve, reject) => {
      const watchdog = setTimeout(() => {
        if (!jobs.has(id)) return;
        const s = (client.watchdogMs / 1000).toLocaleString('en-US');
        end(new ComputeFault('timeout', `The computation gave no answer within ${s} s and was stopped`));
        start('timeout');
      }, client.watchdogMs);
      jobs.set(id, { resolve, reject, watchdog });
      worker.postMessage({ id, ...message });
    });
  }

  // Cursor keys: the worker numbers its cursors (a report's answer names the cursor of its
  // scenario), and every worker start is a new epoch, so a key never names another worker's.
  let epoch = 0;
  let atRequests = 0;
  const keyOf = (n) => `${epoch}.${n}`;

  function start(reason) {
    const t0 = performance.now();
    const entry = { panel, reason, readyMs: null };
    workerStarts.push(entry);
    // Sent the module the page compiled once (wasm.js) before any job: it never fetches it.
    const w = startWorker(WORKER_URL);
    worker = w;
    epoch++;
    let ready = false;
    w.onmessage = ({ data }) => {
      if (w !== worker) return; // a replaced worker's late message
      if (data.ready) {
        ready = true;
        entry.readyMs = performance.now() - t0;
        return;
      }
      const detail = data.prefetched || data.detail;
      if (detail) client.onDetail?.(keyOf(detail.cursor), detail.t, detail.at);
      if (data.prefetched) return;
      const job = jobs.get(data.id);
      if (!job) return;
      if (data.fault) { fail(data.fault, ready); return; } // this job fails with every other
      clearTimeout(job.watchdog);
      jobs.delete(data.id);
      if (data.error) job.reject(Object.assign(new Error(data.error.message), { field: data.error.field }));
      else job.resolve(data);
    };
    // An uncaught error in the worker (its script or module did not load, or it died): handled
    // here, not reported again as the page's.
    w.onerror = (e) => {
      e.preventDefault();
      if (w === worker) fail(e.message || 'the compute worker stopped', ready);
    };
    w.onmessageerror = () => { if (w === worker) fail('a message from the compute worker could not be read', ready); };
  }

  // The worker failed: every job fails with it. A worker that had loaded is replaced at once
  // (the next run finds it warm); one that never loaded is not (no restart loop), the next run
  // tries again.
  function fail(message, wasReady) {
    end(new ComputeFault('crash', `The computation failed: ${message}`));
    if (wasReady) start('crash');
  }

  function end(fault) {
    worker?.terminate();
    worker = null;
    const waiting = [...jobs.values()];
    jobs.clear();
    for (const j of waiting) { clearTimeout(j.watchdog); j.reject(fault); }
  }

  // Stop what runs (Cancel, or a newer scenario) and start a fresh worker.
  function replace(kind) {
    end(new ComputeFault(kind, kind));
    start(kind);
  }

  // Warm from the start: the module loads while the panel builds its first scenario.
  start('first');
  computeClients.set(panel, client);
  return client;
}
