// The target curve: a preset with its parameters, a dropped or chosen file,
// or pasted points; units and smoothing. Every change asks the server how it
// reads the curve (POST /v1/curve) and KSA's first guess (POST /v1/ksa).

import { api } from "./api.js";
import { $, $$, el, num } from "./dom.js";

export class CurveInput {
  /** `onPreview({preview, ksa, spec})` after each successful read; `onError(error)`. */
  constructor({ onPreview, onError }) {
    this.onPreview = onPreview;
    this.onError = onError;
    this.source = "preset";
    this.fileText = null;
    this.presets = [];
    this.generation = 0;
    for (const tab of $$("#curve-form [data-source]")) {
      tab.addEventListener("click", () => this.select(tab.dataset.source));
    }
    $("#preset").addEventListener("change", () => { this.drawParams(); this.changed(); });
    for (const id of ["#units", "#smooth", "#curve-text"]) $(id).addEventListener("input", () => this.changed());
    $("#curve-file").addEventListener("change", (e) => this.readFile(e.target.files[0]));
    const drop = $("#drop");
    drop.addEventListener("dragover", (e) => { e.preventDefault(); drop.classList.add("over"); });
    drop.addEventListener("dragleave", () => drop.classList.remove("over"));
    drop.addEventListener("drop", (e) => {
      e.preventDefault();
      drop.classList.remove("over");
      this.readFile(e.dataTransfer.files[0]);
    });
  }

  async loadPresets() {
    const { presets } = await api("GET", "/v1/presets");
    this.presets = presets;
    $("#preset").replaceChildren(...presets.map((p) => el("option", { value: p.name, text: p.name })));
    $("#preset").value = presets.some((p) => p.name === "grasp") ? "grasp" : presets[0].name;
    this.drawParams();
  }

  select(source) {
    this.source = source;
    for (const tab of $$("#curve-form [data-source]")) tab.setAttribute("aria-selected", tab.dataset.source === source);
    for (const panel of $$("#curve-form [data-panel]")) panel.hidden = panel.dataset.panel !== source;
    this.changed();
  }

  drawParams() {
    const preset = this.presets.find((p) => p.name === $("#preset").value);
    const fields = Object.entries(preset?.params || {}).map(([name, value]) => {
      const id = `param-${name}`;
      const input = Array.isArray(value)
        ? el("select", { id, "data-param": name }, ...value.map((v) => el("option", { text: v })))
        : el("input", { id, "data-param": name, type: typeof value === "number" ? "number" : "text",
          step: "any", value });
      input.addEventListener("input", () => this.changed());
      return el("div", {}, el("label", { for: id, text: name.replaceAll("_", " ") }), input);
    });
    $("#preset-params").replaceChildren(...fields);
  }

  async readFile(file) {
    if (!file) return;
    this.fileText = await file.text();
    $("#file-name").textContent = `${file.name}: ${this.fileText.split("\n").filter((l) => l.trim()).length} lines`;
    this.changed();
  }

  /** The request's `curve` (and `units`, `smooth_mm`) as chosen now; null when nothing is given yet. */
  spec() {
    let curve = null;
    if (this.source === "preset") {
      const params = {};
      for (const input of $$("#preset-params [data-param]")) {
        const value = input.type === "number" ? Number(input.value) : input.value;
        if (input.value !== "") params[input.dataset.param] = value;
      }
      curve = { preset: $("#preset").value, params };
    } else {
      const text = this.source === "file" ? this.fileText : $("#curve-text").value;
      if (!text || !text.trim()) return null;
      curve = text.trim().startsWith("{") ? jsonCurve(text) : { csv: text };
    }
    const out = { curve, units: $("#units").value };
    const smooth = $("#smooth").value;
    if (smooth !== "") out.smooth_mm = Number(smooth);
    return out;
  }

  /** Sets the inputs from a job's request (a job reopened for editing). */
  fill(request) {
    const curve = request.curve || {};
    $("#units").value = request.units || "mm";
    $("#smooth").value = request.options?.smooth_mm ?? "";
    if (curve.preset) {
      this.select("preset");
      $("#preset").value = curve.preset;
      this.drawParams();
      for (const [name, value] of Object.entries(curve.params || {})) {
        const input = $(`#param-${name}`);
        if (input) input.value = value;
      }
    } else {
      $("#curve-text").value = curve.csv ?? (curve.points || []).map((p) => p.join(", ")).join("\n");
      this.select("paste");
    }
    this.changed();
  }

  changed() {
    clearTimeout(this.timer);
    this.timer = setTimeout(() => this.preview(), 350);
  }

  async preview() {
    const spec = this.spec();
    const generation = ++this.generation;
    $("#curve-error").textContent = "";
    if (!spec) { $("#curve-info").textContent = "Give the curve's points."; return; }
    $("#curve-info").textContent = "Reading the curve…";
    try {
      const preview = await api("POST", "/v1/curve", { curve: spec.curve, units: spec.units, smooth_mm: spec.smooth_mm });
      // As the design's seed: long bends become trains of patches no
      // longer than the longest patch allowed.
      const ksa = await api("POST", "/v1/ksa", { curve: { points: preview.points_mm },
        max_patch_mm: Number($("#h-max").value) || 30 });
      if (generation !== this.generation) return;
      const input = preview.input;
      $("#curve-info").textContent = [
        `${num(preview.length_mm, 4)} mm long, ${preview.points} points`,
        input.smoothing_mm > 0
          ? `noise ${num(input.noise_mm, 2)} mm found, smoothed with σ ${num(input.smoothing_mm, 2)} mm${input.automatic ? " (automatic)" : ""}`
          : "not smoothed",
        input.interpolated
          ? `${input.interpolated.points} points ${num(input.interpolated.median_spacing_mm, 2)} mm apart, read through a cubic spline`
          : null,
        input.planar ? "planar" : null,
        `KSA's first guess: ${ksa.patches.length} patches`,
      ].filter(Boolean).join(" · ");
      this.onPreview({ preview, ksa, spec });
    } catch (error) {
      if (generation !== this.generation) return;
      $("#curve-info").textContent = "";
      const target = error.field === "smooth_mm" ? "Smoothing: " : "";
      $("#curve-error").textContent = `${target}${error.message}`;
      this.onError(error);
    }
  }
}

/** JSON text: `{"points": [...]}` or a bare list; the server reads it either way. */
function jsonCurve(text) {
  try {
    const value = JSON.parse(text);
    return { points: Array.isArray(value) ? value : value.points };
  } catch {
    return { csv: text };
  }
}
