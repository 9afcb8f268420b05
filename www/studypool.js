// The studies' workers: every chunked Monte Carlo of the page runs off the main thread, on all
// cores. A study is split into one shard per worker (the core's `Study.restrict(i, n)`: a
// contiguous range of run indices); each worker runs its shard in slices and sends its partial
// counts after each slice; the main thread hands the newest partial of every shard to its own
// `Study` (`merge`), and the core gives the merged result — the page never adds counts. Run i
// draws from a random stream fixed by the seed and i alone, so the result is the same whatever
// the number of workers (tests/suite/study.rs). A crash or a silent worker fails the study only;
// Cancel (or a newer scenario) ends it by terminating its workers.
import { WATCHDOG_MS } from './compute.js';
import { startWorker } from './wasm.js';

const WORKER_URL = new URL('./worker.js', import.meta.url);

// One worker per logical core (a browser may report fewer than it has: the count stays correct
// either way, only slower), at most 8.
export const poolSize = () => Math.max(1, Math.min(8, navigator.hardwareConcurrency || 2));

// Every study of the page, for the tests: {workers, runs, wallMs} when it ended.
export const studiesRun = [];

let idle = []; // warm workers, module loaded or loading

function spawn() {
  return startWorker(WORKER_URL);
}

// `size` warm workers (started on the first study, kept between studies).
function take(size) {
  while (idle.length < size) idle.push(spawn());
  return idle.splice(0, size);
}

// Run the study `scenario` (JSON text; `runs` 0: the scenario's own count) on every worker,
// merging into `merger` (the main thread's Study of the same scenario). `onCounts(result)` gets
// the merged result (parsed) at most once per frame while it runs. `me.stop()` is set: it ends
// the study at once (its workers are terminated and replaced). Resolves with
// {counts, wall, compute, workers} — `compute` sums the workers' busy time — or rejects with the
// core's error (an Error with `field`) or with an Error naming the fault. `workers` (default: one
// per core) changes the speed, never the counts.
export function runStudy({ scenario, runs, merger, me, onCounts, workers: size = poolSize() }) {
  const t0 = performance.now();
  const n = size;
  const workers = take(n);
  const parts = new Array(n).fill(null); // the newest partial (JSON text) of each shard
  const busyMs = new Array(n).fill(0);
  const done = new Array(n).fill(false);
  let counts = null;
  let queued = false;
  let lastWord = performance.now();
  return new Promise((resolve, reject) => {
    let over = false;
    const finish = (keep, err) => {
      if (over) return;
      over = true;
      clearInterval(watchdog);
      for (const w of workers) {
        if (keep) { w.onmessage = null; w.onerror = null; idle.push(w); } else w.terminate();
      }
      if (err) reject(err);
      else {
        const wall = performance.now() - t0;
        const compute = busyMs.reduce((a, b) => a + b, 0);
        studiesRun.push({ workers: n, runs: counts ? merger.runs() : 0, wallMs: wall });
        resolve({ counts, wall, compute, workers: n });
      }
    };
    // The core merges the shards' newest partials (once per frame at most: a merge re-adds them all).
    const merge = () => {
      queued = false;
      if (over) return;
      const have = parts.filter(Boolean);
      if (!have.length) return;
      try {
        counts = JSON.parse(merger.merge(`[${have.join(',')}]`));
      } catch (e) {
        finish(false, e);
        return;
      }
      if (done.every(Boolean)) finish(true);
      else onCounts(counts);
    };
    me.stop = () => finish(false);
    const watchdog = setInterval(() => {
      if (performance.now() - lastWord > WATCHDOG_MS) {
        finish(false, new Error(`The study's workers gave no answer within ${WATCHDOG_MS / 1000} s and were stopped — this is a bug`));
      }
    }, 1000);
    workers.forEach((w, i) => {
      w.onmessage = ({ data }) => {
        if (over || data.ready) return;
        lastWord = performance.now();
        if (data.error) { finish(false, Object.assign(new Error(data.error.message), { field: data.error.field })); return; }
        if (data.fault) { finish(false, new Error(`The study failed — this is a bug (${data.fault})`)); return; }
        parts[i] = data.partial;
        busyMs[i] = data.ms;
        done[i] = data.done;
        if (done.every(Boolean)) merge();
        else if (!queued) { queued = true; requestAnimationFrame(merge); }
      };
      w.onerror = (e) => {
        e.preventDefault();
        finish(false, new Error(`The study failed — this is a bug (${e.message || 'its worker stopped'})`));
      };
      w.postMessage({ id: 0, study: { scenario, runs, shard: [i, n] } });
    });
  }).finally(() => {
    // Workers that were terminated are replaced, warm for the next study.
    while (idle.length < Math.min(n, poolSize())) idle.push(spawn());
  });
}
