// A finished design: the predicted centreline over the target in 3D (and
// the inflated surface, simulated again through POST /v1/simulate), the
// metrics, κ/τ profiles, the patches (editable, to simulate a design by
// hand), the placement template and the files.

import { api, download } from "./api.js";
import { align } from "./align.js";
import { $, el, num } from "./dom.js";
import { drawUnrolled } from "./unrolled.js";
import { offerComparison } from "./compare.js";

const FIELDS = [["x_mm", "X (mm)"], ["y_mm", "Y (mm)"], ["h_mm", "H (mm)"], ["w_mm", "W (mm)"], ["theta_deg", "Θ (°)"]];

// Where smoothing, a spline through sparse points or keeping the tube clear
// of itself changed the target, the design against the curve as the user
// gave it too.
function asGiven(result) {
  const g = result.as_given;
  const input = result.input ?? {};
  if (!g || !(input.smoothing_mm > 0 || input.interpolated || input.cleared)) return [];
  return [["shape error, curve as given",
    `${num(g.shape_error_percent, 3)} % of its length (${num(g.shape_error_mm, 3)} mm RMS; the curve as given, ${num(g.length_mm, 4)} mm long)`]];
}

// A target a tube could not follow without passing through itself, and the
// clear curve the design aimed at instead.
function cleared(result) {
  const c = result.input?.cleared;
  if (!c) return [];
  return [["kept clear of itself",
    `a tube of radius ${num(c.radius_mm, 3)} mm along the curve would pass ${num(c.overlap_mm, 3)} mm into itself; the design aims at the nearest clear curve, moved up to ${num(c.moved_max_mm, 3)} mm (${num(c.moved_rms_mm, 3)} mm RMS)${c.converged ? "" : ", not wholly clear"}`]];
}

// What the run's time limit cut short: the stage under way and the stages
// skipped (the design shown is the best found by then, verified).
function timeLimited(result) {
  const t = result.time_limited;
  if (!t) return [];
  const skipped = t.skipped.length ? `; skipped: ${t.skipped.join(", ").replaceAll("_", " ")}` : "";
  return [["time limit", `${t.limit_s} s, reached in the ${t.reached_in.replaceAll("_", " ")}${skipped}: the design is the best found by then, verified`]];
}

// Where the shape error is above 1 %, the causes the run found, in the
// server's words.
function shortfalls(result) {
  const causes = result.shortfalls ?? [];
  if (!causes.length) return [];
  return [["why above 1 %", causes.map((c) => c.message).join("; ")]];
}

// The layouts the run tried after the refine (KSA's, patches on gentle
// bends, patches taken out), each with the shape error it reached.
function layouts(result) {
  const tried = result.layouts ?? [];
  if (tried.length < 2) return [];
  const text = tried.map((l) =>
    `${l.layout}: ${l.patches} patches, ${num(l.shape_error_percent, 3)} %${l.chosen ? " (chosen)" : ""}`);
  return [["layouts tried", text.join("; ")]];
}

// Where the predicted tube passes through itself (the model has no contact).
function selfContact(result) {
  const contacts = result.self_contact ?? [];
  if (!contacts.length) return [];
  const text = contacts.map((c) =>
    `${num(c.overlap_mm, 2)} mm deep at s ${num(c.s_mm[0], 3)} and ${num(c.s_mm[1], 3)} mm (balloon Y ${num(c.y_mm[0], 3)} and ${num(c.y_mm[1], 3)} mm)`);
  const remedy = result.input?.keep_clear ? "" : " (Keep the tube clear of itself designs one that does not)";
  return [["passes through itself", `${text.join("; ")}: the real balloon pushes apart there${remedy}`]];
}

// How far the built balloon may stray at the run's tolerances, and the
// three sources that matter most (the server's words: "P3 X (around")).
function spread(result) {
  const s = result.spread;
  if (!s) return result.spread_failed ? [["spread at the tolerances", `not found: ${result.spread_failed}`]] : [];
  const expected = s.expected_shape_error_percent === undefined ? ""
    : `; expected shape error as built ${num(s.expected_shape_error_percent, 3)} %`;
  const offset = s.mean_shift_mm > 0 ? `; on average ${num(s.mean_shift_mm, 3)} mm RMS from the predicted centreline` : "";
  const top = s.contributors.slice(0, 3).map((c) =>
    `${c.label} ±${c.tolerance}${c.unit === "°" ? "" : " "}${c.unit}: ${num(c.rms_mm, 3)} mm RMS, tip ${num(c.tip_mm, 3)} mm`);
  return [
    ["spread at the tolerances", `${num(s.rms_mm, 3)} mm RMS (${num(s.rms_percent, 3)} % of the length), at worst ${num(s.worst_mm, 3)} mm; tip ${num(s.tip_rms_mm, 3)} mm RMS${offset}${expected}`],
    ...monteCarlo(s.monte_carlo),
    ["matters most", top.join("; ")],
    ...robust(result),
  ];
}

// The robust refine (tuning.robust): both designs' figures and which stands.
function robust(result) {
  const r = result.robust;
  if (!r) return result.robust_skipped ? [["robust design", `not run: ${result.robust_skipped}`]] : [];
  const figures = (e) =>
    `${num(e.shape_error_percent, 3)} % as designed, spread ${num(e.spread_percent, 3)} %, ${num(e.expected_percent, 3)} % expected`;
  const verdict = r.kept ? "kept: the design shown is the robust one" : "not kept: the nominal design stands";
  return [["robust design",
    `weighing ${r.sources.join(", ")}: nominal design ${figures(r.nominal_design)}; robust design ${figures(r.robust_design)}; ${verdict}`]];
}

// The Monte-Carlo check of the spread, where the run made one (fine's
// preset, or tuning.monte_carlo): sampled against linear, and whether they
// agree within 20 %.
function monteCarlo(m) {
  if (!m) return [];
  const verdict = m.agrees ? "agrees"
    : "differs by more than 20 %: the response is not linear at these tolerances, the sampled figure holds";
  const failed = m.failed ? `; ${m.failed} samples did not solve` : "";
  return [["Monte-Carlo check",
    `${m.samples} designs (seed ${m.seed}): ${num(m.rms_mm, 3)} mm RMS, tip ${num(m.tip_rms_mm, 3)} mm; ${num(m.ratio, 3)} ± ${num(m.ratio_sigma, 2)} × the linear estimate: ${verdict}${failed}`]];
}

// The patches among the three largest sources of spread (numbered from 1).
function sensitivePatches(result) {
  const top = (result.spread?.contributors ?? []).slice(0, 3);
  return new Set(top.filter((c) => c.source === "patch").map((c) => c.patch));
}

export async function showResult(page, jobId, result, preview) {
  const target = preview?.points_mm;
  const m = result.metrics;
  page.result = result; // for the browser tests and the console
  const facts = $("#job-facts");
  const rows = [
    ["shape error", `${num(m.shape_error_percent, 3)} % of the length (${num(m.shape_error_mm, 3)} mm RMS)`],
    ...timeLimited(result),
    ...asGiven(result),
    ...cleared(result),
    ...shortfalls(result),
    ...layouts(result),
    ...selfContact(result),
    ...spread(result),
    ["DTW κ, τ", `${num(m.dtw_curvature, 3)}, ${num(m.dtw_torsion, 3)}`],
    ["target", `${num(result.target_length_mm, 4)} mm`],
    ["inflated", `${num(result.inflated_length_mm, 4)} mm`],
    ["cut the balloon", `${num(result.uninflated_length_to_cut_mm, 4)} mm long`],
    ["patches", result.design.patches.length],
    ["time", `${num(result.elapsed_s, 3)} s, ${result.evaluations} evaluations`],
  ];
  facts.append(...rows.flatMap(([k, v]) => [el("dt", { text: k }), el("dd", { text: String(v), "data-fact": k })]));
  // The prediction's frame onto the target's (when shown): the measured
  // centreline of a comparison, aligned onto the prediction, goes with it.
  let placed = (p) => p;
  if (target) {
    const fit = align(result.centreline_mm, target);
    placed = fit.apply;
    // The page's alignment reproduces the server's shape error (a browser test compares them).
    page.resultFit = { percent: fit.percent, server: m.shape_error_percent };
    page.view.curve("design", result.centreline_mm.map(fit.apply), {
      colour: "#1f6feb", label: "designed balloon, inflated (centreline)", radius: page.tubeRadius * 0.8 });
    // The spread at the tolerances as a band around it (RMS, after the best
    // rigid alignment, as the spread is measured).
    page.view.band("design-band", result.centreline_mm.map(fit.apply), result.spread?.band_mm, {
      colour: "#1f6feb", label: "spread at the tolerances (RMS band)" });
    page.view.fit();
  }
  const designed = [
    { name: "κ design", y: result.profiles.curvature_per_mm, colour: "#1f6feb" },
    { name: "τ design", y: result.profiles.torsion_per_mm, colour: "#d9480f" },
  ];
  if (preview) page.showProfiles(preview, designed, result.target_length_mm);
  $("#unrolled-caption").textContent = "The design's patches on the unrolled balloon (as cut)";
  drawUnrolled($("#unrolled"), {
    lengthMm: result.design.balloon.length_mm, radiusMm: result.design.balloon.radius_mm, patches: result.design.patches });
  patchTable(page, result.design, target, sensitivePatches(result));
  for (const button of document.querySelectorAll("#downloads [data-file]")) {
    button.onclick = () => download(jobId, button.dataset.file).catch((e) => ($("#job-error").textContent = e.message));
  }
  showTemplate(jobId);
  offerComparison(page, jobId, (comparison) => {
    page.view.curve("measured", comparison.measured_aligned_mm.map(placed), {
      colour: "#e8590c", label: "built balloon, measured (centreline)", radius: page.tubeRadius * 0.8 });
    page.view.render();
    // The built balloon's κ and τ beside the design's and the target's.
    if (preview) page.showProfiles(preview, [...designed,
      { name: "κ built", y: comparison.profiles.measured_curvature_per_mm, colour: "#2b8a3e" },
      { name: "τ built", y: comparison.profiles.measured_torsion_per_mm, colour: "#862e9c" },
    ], result.target_length_mm);
  });
  if (target) await inflate(page, result.design, target, "surface", "inflated membrane");
}

/** Simulates `design` with its surface and draws both, aligned to the target. */
async function inflate(page, design, target, name, label) {
  const started = performance.now();
  const sim = await api("POST", "/v1/simulate", { design, surface: true });
  const fit = align(sim.centreline_mm, target);
  page.view.surface(name, sim.surface, fit.apply, label);
  page.view.setVisible(name, $("#show-surface").checked);
  return { sim, fit, seconds: (performance.now() - started) / 1000 };
}

// The patch table; the patches in `sensitive` (numbered from 1) are marked
// as the ones to place with most care.
function patchTable(page, design, target, sensitive = new Set()) {
  const table = $("#patch-table");
  const head = el("tr", {}, el("th", { scope: "col", text: "patch" }), ...FIELDS.map(([, h]) => el("th", { scope: "col", text: h })));
  const name = (i) => sensitive.has(i + 1) ? `P${i + 1} (place with care)` : `P${i + 1}`;
  const rows = design.patches.map((p, i) => el("tr", sensitive.has(i + 1) ? { class: "sensitive" } : {}, el("th", { scope: "row", text: name(i) }),
    ...FIELDS.map(([key, h]) => el("td", {}, el("input", { type: "number", step: "any", value: +p[key].toFixed(3),
      "aria-label": `P${i + 1} ${h}`, "data-patch": i, "data-key": key })))));
  table.replaceChildren(el("thead", {}, head), el("tbody", {}, ...rows));
  $("#patches-panel").hidden = false;
  $("#simulate-error").textContent = "";
  $("#simulate-info").textContent = "";
  $("#simulate").onclick = async () => {
    const edited = structuredClone(design);
    for (const input of table.querySelectorAll("input")) edited.patches[input.dataset.patch][input.dataset.key] = Number(input.value);
    $("#simulate").disabled = true;
    $("#simulate-error").textContent = "";
    $("#simulate-info").textContent = "Simulating…";
    try {
      const { sim, fit, seconds } = await inflate(page, edited, target, "surface", "inflated membrane (edited patches)");
      page.view.curve("edited", sim.centreline_mm.map(fit.apply), {
        colour: "#2b8a3e", label: "edited patches, inflated (centreline)", radius: page.tubeRadius * 0.8 });
      page.view.render();
      const contact = selfContact(sim).map(([k, v]) => `; ${k}: ${v}`).join("");
      $("#simulate-info").textContent =
        `edited design: shape error ${num(fit.percent, 3)} % (${num(fit.rmsMm, 3)} mm), inflated ${num(sim.inflated_length_mm, 4)} mm, ${num(seconds, 2)} s${contact}`;
    } catch (error) {
      $("#simulate-info").textContent = "";
      $("#simulate-error").textContent = error.field ? `${error.field}: ${error.message}` : error.message;
    } finally {
      $("#simulate").disabled = false;
    }
  };
}

async function showTemplate(jobId) {
  const response = await api("GET", `/v1/jobs/${jobId}/files/template.svg`, undefined, { raw: true });
  const url = URL.createObjectURL(await response.blob());
  $("#template").replaceChildren(el("img", { src: url, alt: "Placement template: the balloon unrolled with each patch's outline and dimensions" }));
  $("#template-panel").hidden = false;
}
