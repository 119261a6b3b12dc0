// One job: its target, live progress over server-sent events (stage,
// generation, evaluations against the budget, best objective as a chart,
// elapsed time and what is left of the search), cancel and delete; the
// result when it succeeds. A calibration job shows its iterations and its
// answer instead (calibration.js).

import { api } from "./api.js";
import { $, duration, el, num } from "./dom.js";
import { followEvents } from "./events.js";
import { lineChart } from "./plot.js";
import { hideCalibration, progressFacts, showCalibration } from "./calibration.js";
import { showResult } from "./result.js";

const STAGES = {
  queued: "queued: waiting for a worker",
  seed: "seed: KSA's first guess and the balloon's length",
  reach: "reach: what one patch can make",
  search: "search: CMA-ES on the model",
  polish: "polish: CMA-ES on the verification model",
  verify: "verify: the design on the verification model",
  length: "length: the balloon length matched to the curve's",
  refine: "refine: Levenberg–Marquardt on the shape error",
  layout: "layout: patches added where the curve bends gently, or taken out",
  final_refine: "final refine: the refine on the finest model",
  spread: "spread: the design at the tolerances, each source linearised, the large ones solved both ways",
  robust: "robust: the design refined for the error expected at the tolerances",
  calibrate: "calibrate: the material fitted to the measurements",
};

const running = (job) => job.status === "queued" || job.status === "running";

export class JobPage {
  /** `page` gives `view`, `showTarget(preview)`, `showReach(reach, preview)`. */
  constructor(page) {
    this.page = page;
    this.stop = () => {};
    $("#job-cancel").addEventListener("click", () => this.cancel());
    $("#job-delete").addEventListener("click", () => this.remove());
    $("#job-again").addEventListener("click", () => this.page.editAgain(this.job.request));
  }

  async open(id) {
    this.stop();
    this.id = id;
    this.progress = [];
    // The ids of the events shown, and how often the stream reconnected
    // (the browser tests read both).
    this.seen = [];
    this.reconnects = 0;
    this.stage = null;
    $("#job-error").textContent = "";
    $("#downloads").hidden = true;
    $("#progress-panel").hidden = true;
    $("#patches-panel").hidden = true;
    $("#compare-panel").hidden = true;
    $("#template-panel").hidden = true;
    hideCalibration();
    $("#job-heading").textContent = `Job ${id.slice(0, 8)}…`;
    $("#unrolled-caption").textContent = "The design's patches on the unrolled balloon, when it is done";
    $("#unrolled").replaceChildren();
    this.page.clearDesign();
    try {
      this.job = await api("GET", `/v1/jobs/${id}`);
    } catch (error) {
      this.status(`cannot open: ${error.message}`, "failed");
      return;
    }
    if (this.calibration()) {
      $("#job-heading").textContent = `Calibration ${id.slice(0, 8)}…`;
      this.page.clearStage("A calibration: the fitted materials and their files are on the left");
    }
    this.showStatus();
    this.preview = null;
    if (this.job.request && !this.calibration()) {
      const { curve, units, options } = this.job.request;
      try {
        this.preview = await api("POST", "/v1/curve", { curve, units, smooth_mm: options?.smooth_mm });
        this.page.showTarget(this.preview, null);
      } catch (error) {
        $("#job-error").textContent = `the target: ${error.message}`;
      }
    }
    const stream = followEvents(id, (e) => this.event(e), (state) => this.connection(state));
    this.stop = stream.stop;
  }

  calibration() {
    return this.job?.kind === "calibrate";
  }

  showStatus() {
    const job = this.job;
    this.status(job.status, job.status);
    const running = job.status === "queued" || job.status === "running";
    $("#job-cancel").disabled = !running;
    $("#job-delete").disabled = running;
    $("#job-again").hidden = this.calibration();
    this.facts();
  }

  status(text, kind) {
    const node = $("#job-status");
    node.textContent = text;
    node.className = `status ${kind}`;
  }

  connection(state) {
    if (state === "reconnecting") this.reconnects++;
    if (state === "reconnecting") this.status(`${this.job.status} (connection lost, reconnecting…)`, this.job.status);
    else this.showStatus();
  }

  event({ id, event, data }) {
    if (id !== null) this.seen.push(Number(id));
    if (event === "stage") {
      this.stage = data.stage;
      if (data.stage !== "queued") this.job.status = "running";
      this.showStatus();
    } else if (event === "progress") {
      this.stage = data.stage;
      this.job.status = "running";
      this.progress.push(data);
      if (!this.calibration()) this.drawProgress();
      this.showStatus();
    } else if (event === "reach") {
      this.reach = data;
      if (this.preview) this.page.showReach(data, this.preview);
      this.facts();
    } else if (event === "done") {
      this.job.status = "succeeded";
      this.showStatus();
      this.loadResult();
    } else if (event === "failed") {
      this.job.status = "failed";
      this.showStatus();
      $("#job-error").textContent = data?.error || this.job.error || "the job failed";
    } else if (event === "cancelled") {
      this.job.status = "cancelled";
      this.showStatus();
    }
  }

  facts() {
    if (this.calibration()) return this.calibrationFacts();
    const last = this.progress[this.progress.length - 1];
    const budget = this.job.search_budget;
    const rows = [
      ["created", new Date(this.job.created_at).toLocaleString()],
      ["fidelity", this.job.request?.options?.fidelity || "standard"],
      this.job.plan && ["plan", this.job.plan],
      this.job.stage_budgets && ["budgets", this.job.stage_budgets],
      this.stage && running(this.job) && ["stage", STAGES[this.stage] || this.stage],
    ];
    if (last) {
      rows.push(["generation", last.generation]);
      rows.push(["evaluations", budget ? `${last.evaluations} of ${budget}` : last.evaluations]);
      rows.push(["best objective", num(last.best_objective, 4)]);
      rows.push(["elapsed", duration(last.elapsed_s)]);
      if (running(this.job) && budget && last.stage === "search" && last.evaluations > 0 && last.evaluations < budget) {
        const left = (last.elapsed_s / last.evaluations) * (budget - last.evaluations);
        rows.push(["search left", `about ${duration(left)}, then the refine`]);
      }
    }
    if (this.reach) {
      const out = this.reach.out_of_reach;
      rows.push(["reach", out.length ? `${out.length} stretch${out.length > 1 ? "es" : ""} out of reach (red)` : "all within reach"]);
    }
    $("#job-facts").replaceChildren(...rows.filter(Boolean).flatMap(([k, v]) => [el("dt", { text: k }), el("dd", { text: String(v) })]));
  }

  calibrationFacts() {
    const rows = [
      ["created", new Date(this.job.created_at).toLocaleString()],
      ["fits", (this.job.fit || []).join(", ")],
      ...(running(this.job) ? [
        this.stage && ["stage", STAGES[this.stage] || this.stage],
        ...progressFacts(this.progress[this.progress.length - 1] ?? this.job.progress),
      ] : []),
    ];
    $("#job-facts").replaceChildren(...rows.filter(Boolean).flatMap(([k, v]) => [el("dt", { text: k }), el("dd", { text: String(v) })]));
  }

  drawProgress() {
    $("#progress-panel").hidden = false;
    const points = this.progress.filter((p) => Number.isFinite(p.best_objective));
    lineChart($("#progress-chart"), {
      series: [{ name: "best objective", x: points.map((p) => p.evaluations), y: points.map((p) => p.best_objective) }],
      xLabel: "evaluations", yLabel: "objective", logY: true,
    });
  }

  async loadResult() {
    try {
      const result = await api("GET", `/v1/jobs/${this.id}/result`);
      if (this.calibration()) return showCalibration(this.page, this.id, this.job, result);
      $("#downloads").hidden = false;
      await showResult(this.page, this.id, result, this.preview);
    } catch (error) {
      $("#job-error").textContent = `the result: ${error.message}`;
    }
  }

  async cancel() {
    try {
      await api("POST", `/v1/jobs/${this.id}/cancel`);
    } catch (error) {
      $("#job-error").textContent = error.message;
    }
  }

  async remove() {
    try {
      await api("DELETE", `/v1/jobs/${this.id}`);
      location.hash = "#/jobs";
    } catch (error) {
      $("#job-error").textContent = error.message;
    }
  }

  close() {
    this.stop();
    this.stop = () => {};
  }
}
