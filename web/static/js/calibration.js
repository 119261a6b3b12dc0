// Calibration in the page: a built balloon, once compared with its design,
// sent to POST /v1/calibrations (the job's design and the measured
// centreline, a scan's with its radius) and saved as a balloon profile; a
// calibration job's answer (the fitted parameters, their intervals, the
// fit, the warnings and its files); and the design form's choice of this
// key's balloon profiles (GET /v1/balloons).

import { api, download } from "./api.js";
import { $, el, num } from "./dom.js";

/** The built balloon as a calibration takes it, from what was compared:
 *  a scan's extracted centreline (mm) and radius, or the measured lines. */
export function builtOf(jobId, comparison, sent) {
  if (comparison.scan) {
    return { job: jobId, measured: { points: comparison.scan.centreline_mm },
      radius_mm: comparison.radius?.measured_median_mm };
  }
  return { job: jobId, measured: sent.measured, units: sent.units };
}

/** Offers to calibrate to `built` (a design job's balloon, measured). */
export function offerCalibration(jobId, built) {
  $("#calibrate-offer").hidden = false;
  $("#calibrate-error").textContent = "";
  if (!$("#profile-name").value) $("#profile-name").value = `built-${jobId.slice(0, 8)}`;
  $("#calibrate").onclick = async () => {
    $("#calibrate-error").textContent = "";
    $("#calibrate").disabled = true;
    const { units, ...one } = built;
    const request = { built: [one], units: units || "mm" };
    const name = $("#profile-name").value.trim();
    if (name) request.save_as = name;
    try {
      const job = await api("POST", "/v1/calibrations", request);
      location.hash = `#/jobs/${job.id}`;
    } catch (error) {
      $("#calibrate-error").textContent = error.field ? `${error.field}: ${error.message}` : error.message;
    } finally {
      $("#calibrate").disabled = false;
    }
  };
}

export function hideCalibration() {
  $("#calibrate-offer").hidden = true;
  $("#calibration-downloads").hidden = true;
}

/** A running calibration's facts, from its latest progress. */
export function progressFacts(progress) {
  if (!progress || progress.stage !== "calibrate") return [];
  const values = Object.entries(progress.parameters || {}).map(([k, v]) => `${k} ${num(v, 4)}`).join(", ");
  return [
    ["iteration", progress.iteration],
    ["FE solves", progress.solves],
    ["misfit", `${num(progress.rms_percent, 3)} % RMS`],
    values && ["now", values],
  ].filter(Boolean);
}

const interval = (p) => (p.interval95 ? ` (95 %: ${num(p.interval95[0], 4)} – ${num(p.interval95[1], 4)})` : "");

/** A finished calibration: its answer among the job's facts, its files,
 *  and the profile it saved. */
export function showCalibration(page, jobId, job, result) {
  page.calibration = result; // for the browser tests and the console
  const rows = [
    ...result.parameters.map((p) => [p.parameter, `${num(p.value, 4)}${interval(p)}; from ${num(p.start, 4)}`]),
    ["misfit", `${num(result.rms_percent, 3)} % RMS, ${result.solves} FE solves`],
    ...result.residuals.map((r) => [`${r.quantity} at ${num(r.pressure_kpa, 3)} kPa`,
      `${num(r.measured, 4)} measured, ${num(r.predicted, 4)} model (${num(r.percent, 2)} %)`]),
    ...result.built.map((b) => [`built balloon ${b.index + 1}`,
      `model against the measured centreline ${num(b.shape_error_percent, 3)} % of its length (from ${num(b.shape_error_start_percent, 3)} % before)`]),
    ...result.warnings.map((w) => ["warning", w]),
  ];
  $("#job-facts").append(...rows.flatMap(([k, v]) => [el("dt", { text: k }), el("dd", { text: String(v), "data-fact": k })]));
  $("#calibration-downloads").hidden = false;
  for (const button of document.querySelectorAll("#calibration-downloads [data-file]")) {
    button.onclick = () => download(jobId, button.dataset.file).catch((e) => ($("#job-error").textContent = e.message));
  }
  const name = job.request?.save_as;
  const link = $("#design-with-profile");
  link.hidden = !name;
  if (name) {
    link.textContent = `Design with the balloon profile “${name}”`;
    link.onclick = () => { page.useProfile = name; };
  }
}

/** Fills the forms' profile choices with this key's profiles, keeping
 *  (or setting, for the design form) the one chosen. */
export async function loadProfiles(chosen) {
  let balloons;
  try {
    ({ balloons } = await api("GET", "/v1/balloons"));
  } catch {
    return; // without profiles (or a key yet) the forms go on with the balloon given
  }
  const label = (b) => (typeof b.balloon.material?.mu_mpa === "number"
    ? `${b.name} (μ ${num(b.balloon.material.mu_mpa, 4)} MPa)` : b.name);
  for (const [id, none, keep] of [
    ["#balloon-profile", "none: the balloon below", chosen],
    ["#calibrate-from", "none", undefined],
  ]) {
    const select = $(id);
    const wanted = keep ?? select.value;
    const options = balloons.map((b) => el("option", { value: b.name, text: label(b) }));
    select.replaceChildren(el("option", { value: "", text: none }), ...options);
    select.value = balloons.some((b) => b.name === wanted) ? wanted : "";
  }
}
