// The page: four views (new design, calibration, one job, the jobs list)
// chosen by the address's hash (#/, #/calibrate, #/jobs/ID, #/jobs), the API key when the server asks
// for one, and the shared 3D view and plots.

import { onUnauthorized, apiKey, setApiKey, api } from "./api.js";
import { $, el } from "./dom.js";
import { CurveInput } from "./curve.js";
import { CalibrateForm } from "./calibrate_form.js";
import { loadProfiles } from "./calibration.js";
import { fillForm, submit } from "./submit.js";
import { JobPage } from "./watch.js";
import { JobList } from "./jobs.js";
import { View3D } from "./view3d.js";
import { lineChart } from "./plot.js";
import { drawUnrolled } from "./unrolled.js";

const DESIGN_ITEMS = ["design", "edited", "surface", "reach", "measured"];

class Page {
  constructor() {
    this.view = new View3D($("#view3d"), $("#legend"));
    this.tubeRadius = 1;
    this.curve = new CurveInput({
      onPreview: ({ preview, ksa, spec }) => {
        this.spec = spec;
        if (this.route !== "design") return;
        this.showTarget(preview, ksa);
      },
      onError: () => { this.spec = null; },
    });
    this.job = new JobPage(this);
    this.jobs = new JobList();
    this.calibrate = new CalibrateForm();
    $("#design-form").addEventListener("submit", (e) => { e.preventDefault(); this.submit(); });
    $("#view-reset").addEventListener("click", () => this.view.fit());
    $("#show-surface").addEventListener("change", (e) => this.view.setVisible("surface", e.target.checked));
    $("#key-form").addEventListener("submit", (e) => { e.preventDefault(); this.useKey($("#api-key").value.trim()); });
    onUnauthorized(() => this.askKey());
    window.addEventListener("hashchange", () => this.navigate());
  }

  async start() {
    try {
      await this.curve.loadPresets();
      this.started = true;
    } catch (error) {
      if (error.status !== 401) $("#curve-error").textContent = error.message;
    }
    this.navigate();
  }

  askKey() {
    const form = $("#key-form");
    form.hidden = false;
    $("#key-message").textContent = apiKey() ? "the server refused this key" : "this server needs an API key";
    $("#api-key").focus();
  }

  async useKey(key) {
    setApiKey(key);
    $("#key-message").textContent = "";
    try {
      await api("GET", "/v1/presets");
    } catch {
      return; // askKey has said why
    }
    $("#key-form").hidden = true;
    if (!this.started) await this.start();
    else this.navigate();
  }

  navigate() {
    const hash = location.hash || "#/";
    const jobMatch = hash.match(/^#\/jobs\/([\w-]+)/);
    this.route = jobMatch ? "job" : hash.startsWith("#/jobs") ? "jobs"
      : hash.startsWith("#/calibrate") ? "calibrate" : "design";
    $("#view-design").hidden = this.route !== "design";
    $("#view-calibrate").hidden = this.route !== "calibrate";
    $("#view-job").hidden = this.route !== "job";
    $("#view-jobs").hidden = this.route !== "jobs";
    $("#nav-design").toggleAttribute("aria-current", this.route === "design");
    $("#nav-jobs").toggleAttribute("aria-current", this.route === "jobs" || this.route === "job");
    $("#nav-calibrate").toggleAttribute("aria-current", this.route === "calibrate");
    if ($("#nav-calibrate").hasAttribute("aria-current")) $("#nav-calibrate").setAttribute("aria-current", "page");
    if ($("#nav-design").hasAttribute("aria-current")) $("#nav-design").setAttribute("aria-current", "page");
    if ($("#nav-jobs").hasAttribute("aria-current")) $("#nav-jobs").setAttribute("aria-current", "page");
    if (this.route !== "job") this.job.close();
    if (this.route === "jobs") this.jobs.show(); else this.jobs.hide();
    if (this.route === "job") this.job.open(jobMatch[1]);
    if (this.route === "calibrate") {
      this.clearStage("Calibrating: the FE model's bare balloon fitted to the measurements");
      loadProfiles();
    }
    if (this.route === "design") {
      this.clearDesign();
      $("#progress-panel").hidden = true;
      $("#patches-panel").hidden = true;
      $("#compare-panel").hidden = true;
      $("#template-panel").hidden = true;
      if (this.started) this.curve.preview();
      loadProfiles(this.useProfile);
      this.useProfile = undefined;
    }
  }

  async submit() {
    const job = await submit(this.spec ?? this.curve.spec());
    if (job) location.hash = `#/jobs/${job.id}`;
  }

  editAgain(request) {
    if (!request) return;
    this.useProfile = fillForm(request) ?? "";
    location.hash = "#/";
    this.curve.fill(request);
  }

  clearDesign() {
    for (const name of [...this.view.items.keys()]) {
      if (DESIGN_ITEMS.some((d) => name.startsWith(d))) this.view.set(name, null);
    }
    this.view.render();
  }

  /** Nothing on the 3D view and the plots, `caption` where the patches go
   *  (a job with no curve to show). */
  clearStage(caption) {
    for (const name of [...this.view.items.keys()]) this.view.set(name, null);
    this.view.render();
    $("#profiles").replaceChildren();
    $("#unrolled").replaceChildren();
    $("#unrolled-caption").textContent = caption;
  }

  /** The target (as the server reads it) in 3D, its profiles, and KSA's first guess. */
  showTarget(preview, ksa) {
    const points = preview.points_mm;
    const xs = points.map((p) => p[0]), ys = points.map((p) => p[1]), zs = points.map((p) => p[2]);
    const diagonal = Math.hypot(Math.max(...xs) - Math.min(...xs), Math.max(...ys) - Math.min(...ys), Math.max(...zs) - Math.min(...zs));
    this.tubeRadius = Math.max(diagonal / 300, 0.05);
    this.clearDesign();
    this.view.curve("target", points, { colour: "#1d2430", label: "target", radius: this.tubeRadius });
    if (preview.given_mm) {
      this.view.dots("given", preview.given_mm, { colour: "#8a94a3", label: "points as given (before smoothing)", size: this.tubeRadius * 2 });
    } else {
      this.view.set("given", null);
    }
    this.view.fit();
    this.showProfiles(preview, [], preview.length_mm);
    if (ksa) {
      $("#unrolled-caption").textContent = `KSA's first guess: ${ksa.patches.length} patches on the unrolled balloon, ${ksa.uninflated_length_to_cut_mm.toFixed(1)} mm long`;
      drawUnrolled($("#unrolled"), { lengthMm: ksa.uninflated_length_to_cut_mm,
        radiusMm: Number($("#radius").value) || 3.18, patches: ksa.patches });
    }
  }

  /** Stretches of the target out of reach, in red. */
  showReach(reach, preview) {
    const stretches = reach.out_of_reach.map((r) => preview.points_mm.filter((_, i) =>
      preview.s_mm[i] >= r.s_start_mm && preview.s_mm[i] <= r.s_end_mm));
    this.view.set("reach", null);
    stretches.filter((s) => s.length > 1).forEach((s, i) =>
      this.view.curve(i ? `reach-${i}` : "reach", s, { colour: "#e03131", label: i ? null : "out of reach", radius: this.tubeRadius * 1.6 }));
    this.view.render();
  }

  /** κ and τ of the target (dashed) and of `series` (at equal fractions of `lengthMm`). */
  showProfiles(preview, series, lengthMm) {
    const at = (n) => Array.from({ length: n }, (_, i) => (i * lengthMm) / (n - 1));
    const targetTorsion = preview.torsion_per_mm.map((t, i) => (preview.torsion_defined[i] ? t : NaN));
    lineChart($("#profiles"), {
      series: [
        { name: "κ target", x: preview.s_mm, y: preview.curvature_per_mm, colour: "#1f6feb", dashed: true },
        { name: "τ target", x: preview.s_mm, y: targetTorsion, colour: "#d9480f", dashed: true },
        ...series.map((s) => ({ ...s, x: at(s.y.length) })),
      ],
      xLabel: "s, arc length (mm)", yLabel: "κ, τ (1/mm)", robust: true,
    });
  }
}

const page = new Page();
window.patchwork = page; // for the browser tests and the console
page.start();
