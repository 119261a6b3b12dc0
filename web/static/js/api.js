// The page's one way to the server: the public API, with the API key (kept
// in this tab's session storage) as the bearer token. Errors are the
// server's problem+json documents, thrown as ApiError with their `field`.

const KEY = "patchwork.apiKey";
const listeners = new Set();

export class ApiError extends Error {
  constructor(status, problem) {
    super(problem.detail || problem.title || `HTTP ${status}`);
    this.status = status;
    this.field = problem.field || null;
    this.problem = problem;
  }
}

export function apiKey() {
  return sessionStorage.getItem(KEY) || "";
}

export function setApiKey(key) {
  if (key) sessionStorage.setItem(KEY, key);
  else sessionStorage.removeItem(KEY);
}

/** `callback(error)` runs on every 401: the page asks for a key. */
export function onUnauthorized(callback) {
  listeners.add(callback);
}

export function headers(extra = {}) {
  const key = apiKey();
  return key ? { ...extra, Authorization: `Bearer ${key}` } : extra;
}

/** A request to the API; resolves to the parsed JSON (or the Response when `raw`).
 *  `bytes` (a Blob or ArrayBuffer) is sent as the body instead of `body`'s JSON. */
export async function api(method, path, body, { raw = false, signal, bytes } = {}) {
  const init = { method, headers: headers(), signal };
  if (bytes !== undefined) {
    // A file as it is (a scan): its bytes are the body.
    init.headers["Content-Type"] = "application/octet-stream";
    init.body = bytes;
  } else if (body !== undefined) {
    init.headers["Content-Type"] = "application/json";
    init.body = JSON.stringify(body);
  }
  let response;
  try {
    response = await fetch(path, init);
  } catch (e) {
    if (e.name === "AbortError") throw e;
    throw new ApiError(0, { detail: `the server did not answer (${e.message})` });
  }
  if (!response.ok) {
    const error = new ApiError(response.status, await problemOf(response));
    if (response.status === 401) listeners.forEach((f) => f(error));
    throw error;
  }
  if (raw) return response;
  return response.status === 204 ? null : response.json();
}

async function problemOf(response) {
  const text = await response.text();
  try {
    return JSON.parse(text);
  } catch {
    return { detail: text || response.statusText };
  }
}

/** Saves a job's file: fetched with the key, handed to the browser as a download. */
export async function download(jobId, name) {
  const response = await api("GET", `/v1/jobs/${jobId}/files/${name}`, undefined, { raw: true });
  const url = URL.createObjectURL(await response.blob());
  const link = Object.assign(document.createElement("a"), { href: url, download: name });
  document.body.append(link);
  link.click();
  link.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10_000);
}
