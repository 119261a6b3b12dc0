// Small DOM helpers shared by the views.

export const $ = (selector, root = document) => root.querySelector(selector);
export const $$ = (selector, root = document) => [...root.querySelectorAll(selector)];

/** An element with attributes (`text` sets its text) and children. */
export function el(tag, attributes = {}, ...children) {
  const node = document.createElement(tag);
  for (const [name, value] of Object.entries(attributes)) {
    if (value === undefined || value === null || value === false) continue;
    if (name === "text") node.textContent = value;
    else if (name.startsWith("on")) node.addEventListener(name.slice(2), value);
    else node.setAttribute(name, value === true ? "" : value);
  }
  node.append(...children);
  return node;
}

/** A number with `digits` significant digits, or "–". */
export function num(value, digits = 3) {
  if (value === null || value === undefined || !Number.isFinite(value)) return "–";
  return Number(value.toPrecision(digits)).toString();
}

/** "12 s", "3 min 5 s", "1 h 2 min". */
export function duration(seconds) {
  if (!Number.isFinite(seconds)) return "–";
  const s = Math.max(0, Math.round(seconds));
  if (s < 60) return `${s} s`;
  if (s < 3600) return `${Math.floor(s / 60)} min ${s % 60} s`;
  return `${Math.floor(s / 3600)} h ${Math.floor((s % 3600) / 60)} min`;
}

/** How long ago an RFC 3339 time was. */
export function age(time) {
  return `${duration((Date.now() - Date.parse(time)) / 1000)} ago`;
}

/**
 * Shows a problem beside the form control whose `data-field` is the longest
 * prefix of the problem's `field` (else in `fallback`). Returns the element
 * the message went to.
 */
export function showFieldError(error, root, fallback) {
  clearFieldErrors(root);
  const field = error.field || "";
  let best = null;
  for (const node of $$("[data-field]", root)) {
    const name = node.dataset.field;
    if ((field === name || field.startsWith(`${name}.`) || field.startsWith(`${name}[`))
        && (!best || name.length > best.dataset.field.length)) best = node;
  }
  if (!best) {
    fallback.textContent = error.message;
    return fallback;
  }
  if (best.classList.contains("error")) {
    best.textContent = error.message;
    return best;
  }
  best.classList.add("field-error");
  best.setAttribute("aria-invalid", "true");
  const note = el("p", { class: "error field-note", role: "alert", text: error.message });
  best.after(note);
  best.focus();
  return note;
}

export function clearFieldErrors(root) {
  $$(".field-note", root).forEach((n) => n.remove());
  $$(".field-error", root).forEach((n) => {
    n.classList.remove("field-error");
    n.removeAttribute("aria-invalid");
  });
  $$("p.error[data-field]", root).forEach((n) => (n.textContent = ""));
}
