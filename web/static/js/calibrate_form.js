// The calibration form: the bare balloon's inflation and pressure–volume
// curve (CSV with a header, pasted or from a file), the balloon to start
// from (one of this key's profiles, or a design's `balloon` as JSON), the
// parameters to fit and the profile to save the answer as; sent as
// POST /v1/calibrations. A refused row is named by its CSV line.

import { api, ApiError } from "./api.js";
import { $, $$, clearFieldErrors, showFieldError } from "./dom.js";

const TABLES = [
  ["#inflation-text", "inflation", ["pressure_kpa", "length_mm", "diameter_mm"]],
  ["#volume-text", "pressure_volume", ["pressure_kpa", "volume_ml"]],
];

/** The rows of CSV `text` whose header names `columns` (the first required,
 *  other columns ignored), each with the line it came from. */
export function readTable(text, columns, field) {
  const lines = text.split(/\r?\n/).map((line, i) => [i + 1, line.split("#")[0].trim()]).filter(([, l]) => l);
  if (!lines.length) return [];
  const split = (line) => line.split(/[,;\t]/).map((c) => c.trim());
  const header = split(lines[0][1]);
  const at = columns.map((c) => header.indexOf(c));
  if (at[0] < 0) {
    throw new ApiError(422, { detail: `line ${lines[0][0]}: the header names no ${columns[0]} column`, field });
  }
  return lines.slice(1).map(([line, text]) => {
    const cells = split(text);
    const row = {};
    columns.forEach((column, k) => {
      const cell = at[k] < 0 ? "" : cells[at[k]] ?? "";
      if (cell === "") return;
      const value = Number(cell);
      if (!Number.isFinite(value)) throw new ApiError(422, { detail: `line ${line}: ${column} is not a number`, field });
      row[column] = value;
    });
    return { line, row };
  });
}

export class CalibrateForm {
  constructor() {
    $("#calibrate-form").addEventListener("submit", (e) => { e.preventDefault(); this.submit(); });
    for (const [id] of TABLES) {
      const file = $(`${id}-file`);
      file.addEventListener("change", async () => {
        if (file.files[0]) $(id).value = await file.files[0].text();
      });
    }
  }

  /** The request, and each table's CSV lines (to name a refused row). */
  request() {
    const request = {};
    const lines = {};
    for (const [id, field, columns] of TABLES) {
      const rows = readTable($(id).value, columns, field);
      if (rows.length) request[field] = rows.map((r) => r.row);
      lines[field] = rows.map((r) => r.line);
    }
    const from = $("#calibrate-from").value;
    if (from) request.balloon_profile = from;
    const balloon = $("#calibrate-balloon").value.trim();
    if (balloon) {
      try {
        request.balloon = JSON.parse(balloon);
      } catch (e) {
        throw new ApiError(422, { detail: `not JSON: ${e.message}`, field: "balloon" });
      }
    }
    const fit = $$("#calibrate-form input[name=fit]:checked").map((box) => box.value);
    if (fit.length) request.fit = fit;
    const name = $("#calibrate-save").value.trim();
    if (name) request.save_as = name;
    return { request, lines };
  }

  async submit() {
    const form = $("#calibrate-form");
    clearFieldErrors(form);
    $("#calibrate-form-error").textContent = "";
    let lines = {};
    try {
      const made = this.request();
      lines = made.lines;
      const job = await api("POST", "/v1/calibrations", made.request);
      location.hash = `#/jobs/${job.id}`;
    } catch (error) {
      if (error.status === 401) return;
      showFieldError(byLine(error, lines), form, $("#calibrate-form-error"));
    }
  }
}

/** A refusal of row `field[i]`, named by its CSV line. */
function byLine(error, lines) {
  const match = /^(\w+)\[(\d+)\]$/.exec(error.field || "");
  const line = match && lines[match[1]]?.[Number(match[2])];
  if (!line) return error;
  const reason = error.message.replace(/^\w+ \d+: /, "");
  return new ApiError(error.status, { detail: `line ${line}: ${reason}`, field: error.field });
}
