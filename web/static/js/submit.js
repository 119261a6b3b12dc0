// The design form: fidelity, seed, budget, time limit, balloon profile or balloon,
// patches and bounds, the tolerances of the spread, keeping clear of itself,
// sent with the curve as POST /v1/jobs. The server's validation errors go
// beside the field they name.

import { api, ApiError } from "./api.js";
import { $, clearFieldErrors, showFieldError } from "./dom.js";

/** Number inputs → request paths (left out when empty: the server's default). */
const NUMBERS = [
  ["#seed", ["options", "seed"]],
  ["#budget", ["options", "budget"]],
  ["#time-limit", ["options", "time_limit_s"]],
  ["#radius", ["design", "balloon", "radius_mm"]],
  ["#wall", ["design", "balloon", "wall_mm"]],
  ["#pressure", ["design", "pressure_kpa"]],
  ["#thickness", ["design", "patch", "thickness_mm"]],
  ["#h-min", ["bounds", "h_min_mm"]],
  ["#h-max", ["bounds", "h_max_mm"]],
  ["#w-min", ["bounds", "w_min_mm"]],
  ["#w-max", ["bounds", "w_max_mm"]],
  ["#tol-placement", ["tolerances", "placement_mm"]],
  ["#tol-angle", ["tolerances", "angle_deg"]],
  ["#tol-size", ["tolerances", "size_mm"]],
  ["#tol-pressure", ["tolerances", "pressure_kpa"]],
  ["#tol-wall", ["tolerances", "wall_percent"]],
  ["#tol-modulus", ["tolerances", "modulus_percent"]],
];

function put(object, path, value) {
  let node = object;
  for (const key of path.slice(0, -1)) node = node[key] ??= {};
  node[path[path.length - 1]] = value;
}

function get(object, path) {
  return path.reduce((node, key) => node?.[key], object);
}

/** The material fields: JSON text, each a design material. */
const MATERIALS = [
  ["#material", ["design", "balloon", "material"]],
  ["#patch-material", ["design", "patch", "material"]],
];

/** The job request from the forms; throws an ApiError naming a field the page can check itself. */
export function jobRequest(curveSpec) {
  if (!curveSpec) throw new ApiError(422, { detail: "give the target curve first", field: "curve" });
  const request = { curve: curveSpec.curve, units: curveSpec.units, options: { fidelity: $("#fidelity").value } };
  if (curveSpec.smooth_mm !== undefined) request.options.smooth_mm = curveSpec.smooth_mm;
  for (const [id, path] of NUMBERS) {
    const text = $(id).value.trim();
    if (text !== "") put(request, path, Number(text));
  }
  for (const [id, path] of MATERIALS) {
    const text = $(id).value.trim();
    if (!text) continue;
    try {
      put(request, path, JSON.parse(text));
    } catch (e) {
      throw new ApiError(422, { detail: `not JSON: ${e.message}`, field: path.join(".") });
    }
  }
  const profile = $("#balloon-profile").value;
  if (profile) request.balloon_profile = profile;
  if ($("#keep-clear").checked) put(request, ["tuning", "keep_clear"], true);
  if ($("#robust").checked) put(request, ["tuning", "robust"], true);
  return request;
}

/** Sets the form from a job's request (to edit and run again); answers
 *  the balloon profile it named, for the profile choice to keep. */
export function fillForm(request) {
  $("#fidelity").value = request.options?.fidelity || "standard";
  for (const [id, path] of NUMBERS) $(id).value = get(request, path) ?? (id === "#seed" ? 1 : "");
  for (const [id, path] of MATERIALS) {
    const material = get(request, path);
    $(id).value = material ? JSON.stringify(material) : "";
  }
  $("#keep-clear").checked = request.tuning?.keep_clear === true;
  $("#robust").checked = request.tuning?.robust === true;
  return request.balloon_profile;
}

/** Submits; resolves to the created job, or shows the problem and resolves to null. */
export async function submit(curveSpec) {
  const form = $("#view-design");
  clearFieldErrors(form);
  $("#design-error").textContent = "";
  const button = $("#submit");
  button.disabled = true;
  try {
    return await api("POST", "/v1/jobs", jobRequest(curveSpec));
  } catch (error) {
    if (error.status === 401) return null;
    showFieldError(error, form, $("#design-error"));
    return null;
  } finally {
    button.disabled = false;
  }
}
