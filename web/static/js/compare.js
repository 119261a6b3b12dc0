// A built balloon against its design: the centreline measured on it (a
// file or pasted x,y,z lines) sent to POST /v1/jobs/{id}/compare, or a 3D
// scan of it (a .ply, .obj, .stl, .xyz or .pts file) sent as it is to
// POST /v1/jobs/{id}/compare/scan; the figures, every patch's stretch (the
// one that diverges most marked) and the measured centreline in 3D over
// the prediction; then the offer to calibrate to it.

import { api } from "./api.js";
import { builtOf, offerCalibration } from "./calibration.js";
import { $, el, num } from "./dom.js";

const SCAN_FORMATS = ["ply", "obj", "stl", "xyz", "pts"];

/** The scan format a file's name says, or null for a centreline. */
function scanFormat(file) {
  const extension = file?.name.split(".").pop().toLowerCase();
  return SCAN_FORMATS.includes(extension) ? extension : null;
}

/** The comparison of job `jobId` with what the page holds: the file chosen
 *  (a scan or a centreline) or the pasted lines; and what was sent. */
async function measure(jobId) {
  const file = $("#measured-file").files[0];
  const units = $("#measured-units").value;
  const format = scanFormat(file);
  if (format) {
    const path = `/v1/jobs/${jobId}/compare/scan?format=${format}&units=${units}`;
    return { comparison: await api("POST", path, undefined, { bytes: file }), sent: null };
  }
  const csv = file ? await file.text() : $("#measured-text").value;
  if (!csv.trim()) throw new Error("choose a file or paste the measured points");
  const sent = { measured: { csv }, units };
  return { comparison: await api("POST", `/v1/jobs/${jobId}/compare`, sent), sent };
}

const shape = (f) => `${num(f.shape_error_percent, 3)} % of the length (${num(f.shape_error_mm, 3)} mm RMS), largest ${num(f.largest_mm, 3)} mm at ${num(100 * f.largest_at_fraction, 2)} % from the base`;

function facts(c) {
  const m = c.measured;
  const rows = [
    ["measured", `${m.points} points${m.reversed ? " (given tip to base)" : ""}, noise ${num(m.input.noise_mm, 2)} mm`],
    ["inflated length", `${num(m.smoothed_length_mm, 4)} mm measured, ${num(c.predicted_length_mm, 4)} mm predicted (${num(c.length_difference_percent, 2)} %)`],
    ["vs prediction", shape(c.against_prediction)],
  ];
  if (c.against_target) rows.push(["vs target", shape(c.against_target)]);
  if (c.radius) rows.push(["inflated radius", `${num(c.radius.measured_median_mm, 3)} mm measured, ${num(c.radius.predicted_median_mm, 3)} mm predicted (${num(c.radius.difference_percent, 2)} %)`]);
  if (c.scan) rows.push(["scan", `${c.scan.points} points; centreline at ${c.scan.centreline_mm.length} cross-sections, ${num(c.scan.section_residual_mm, 2)} mm RMS off their circles`]);
  if (c.most_divergent_patch) rows.push(["diverges most", `P${c.most_divergent_patch}`]);
  return rows.flatMap(([k, v]) => [el("dt", { text: k }), el("dd", { text: v, "data-compare": k })]);
}

function table(c) {
  const heads = ["patch", "stretch (%)", "bend measured / predicted (°)", "twist measured / predicted (°)", "local error"];
  const rows = c.patches.map((r) => {
    const worst = r.patch === c.most_divergent_patch;
    return el("tr", { class: worst ? "divergent" : undefined, "data-patch": r.patch },
      el("th", { scope: "row", text: `P${r.patch}${worst ? " (diverges most)" : ""}` }),
      el("td", { text: `${num(100 * r.from_fraction, 2)} – ${num(100 * r.to_fraction, 2)}` }),
      el("td", { text: `${num(r.measured_bend_deg, 3)} / ${num(r.predicted_bend_deg, 3)}` }),
      el("td", { text: `${num(r.measured_twist_deg, 3)} / ${num(r.predicted_twist_deg, 3)}` }),
      el("td", { text: `${num(r.local_error_mm, 2)} mm (${num(r.local_error_percent, 2)} %)` }));
  });
  return [el("thead", {}, el("tr", {}, ...heads.map((h) => el("th", { scope: "col", text: h })))), el("tbody", {}, ...rows)];
}

/** Offers the comparison for job `jobId`; `draw(comparison)` puts what
 *  was measured on the 3D view and the profiles. */
export function offerComparison(page, jobId, draw) {
  $("#compare-panel").hidden = false;
  $("#compare-error").textContent = "";
  $("#compare-facts").replaceChildren();
  $("#compare-table").replaceChildren();
  $("#calibrate-offer").hidden = true;
  $("#compare").onclick = async () => {
    $("#compare-error").textContent = "";
    $("#compare").disabled = true;
    try {
      const { comparison: c, sent } = await measure(jobId);
      page.comparison = c; // for the browser tests and the console
      $("#compare-facts").replaceChildren(...facts(c));
      $("#compare-table").replaceChildren(...table(c));
      draw(c);
      offerCalibration(jobId, builtOf(jobId, c, sent));
    } catch (error) {
      $("#compare-error").textContent = error.field ? `${error.field}: ${error.message}` : error.message;
    } finally {
      $("#compare").disabled = false;
    }
  };
}
