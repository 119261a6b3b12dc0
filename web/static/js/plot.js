// Small SVG line charts: round ticks, labelled axes, a legend.

const NS = "http://www.w3.org/2000/svg";
const W = 520, H = 230, M = { left: 58, right: 12, top: 26, bottom: 40 };
export const COLOURS = ["#1f6feb", "#d9480f", "#2b8a3e", "#862e9c", "#495057"];

function svgEl(tag, attributes = {}, text) {
  const node = document.createElementNS(NS, tag);
  for (const [k, v] of Object.entries(attributes)) node.setAttribute(k, v);
  if (text !== undefined) node.textContent = text;
  return node;
}

/** About `count` round tick values covering [lo, hi]. */
export function ticks(lo, hi, count = 5) {
  if (!(hi > lo)) return [lo];
  const raw = (hi - lo) / count;
  const power = 10 ** Math.floor(Math.log10(raw));
  const step = [1, 2, 5, 10].map((m) => m * power).find((s) => s >= raw);
  const out = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) out.push(+v.toPrecision(12));
  return out;
}

/**
 * The span the axis shows: all values, or with `robust` the 1st to 99th
 * percentile widened by a fifth (a spike at a curve's end, where torsion
 * is ill-defined, must not flatten the rest).
 */
function range(values, log, robust = false) {
  const finite = values.filter((v) => Number.isFinite(v) && (!log || v > 0)).sort((a, b) => a - b);
  if (!finite.length) return [0, 1];
  let lo = finite[0], hi = finite[finite.length - 1];
  if (robust && finite.length > 50) {
    const p = (q) => finite[Math.floor(q * (finite.length - 1))];
    const [a, b] = [p(0.01), p(0.99)];
    lo = Math.max(lo, a - (b - a) * 0.2);
    hi = Math.min(hi, b + (b - a) * 0.2);
  }
  if (log) return [Math.log10(lo) - 0.05, Math.log10(hi) + 0.05];
  if (hi - lo < 1e-12) { lo -= 1; hi += 1; }
  const pad = (hi - lo) * 0.05;
  return [lo - pad, hi + pad];
}

/**
 * Draws `series` ({name, x, y, colour?, dashed?}) into `container`.
 * `logY` plots y on a log scale (positive values only).
 */
export function lineChart(container, { series, xLabel, yLabel, logY = false, robust = false }) {
  const svg = svgEl("svg", { viewBox: `0 0 ${W} ${H}`, role: "img", "aria-label": `${yLabel} against ${xLabel}` });
  const xs = series.flatMap((s) => s.x);
  const ys = series.flatMap((s) => s.y);
  const [x0, x1] = range(xs, false);
  const [y0, y1] = range(ys, logY, robust);
  const px = (x) => M.left + ((x - x0) / (x1 - x0)) * (W - M.left - M.right);
  const py = (y) => {
    const v = logY ? Math.log10(y) : y;
    return H - M.bottom - ((v - y0) / (y1 - y0)) * (H - M.top - M.bottom);
  };
  const axis = { stroke: "#8a94a3", "stroke-width": 1 };
  svg.append(svgEl("line", { x1: M.left, y1: H - M.bottom, x2: W - M.right, y2: H - M.bottom, ...axis }));
  svg.append(svgEl("line", { x1: M.left, y1: M.top, x2: M.left, y2: H - M.bottom, ...axis }));
  for (const t of ticks(x0, x1)) {
    svg.append(svgEl("line", { x1: px(t), x2: px(t), y1: H - M.bottom, y2: H - M.bottom + 4, ...axis }));
    svg.append(svgEl("text", { x: px(t), y: H - M.bottom + 16, "text-anchor": "middle", "font-size": 11 }, fmt(t)));
  }
  const yTicks = logY ? logTicks(y0, y1) : ticks(y0, y1, 4);
  for (const t of yTicks) {
    svg.append(svgEl("line", { x1: M.left, x2: W - M.right, y1: py(t), y2: py(t), stroke: "#eef0f3" }));
    svg.append(svgEl("text", { x: M.left - 5, y: py(t) + 4, "text-anchor": "end", "font-size": 11 }, fmt(t)));
  }
  svg.append(svgEl("text", { x: (M.left + W - M.right) / 2, y: H - 6, "text-anchor": "middle", "font-size": 12 }, xLabel));
  svg.append(svgEl("text", { x: 12, y: (M.top + H - M.bottom) / 2, "text-anchor": "middle", "font-size": 12,
    transform: `rotate(-90 12 ${(M.top + H - M.bottom) / 2})` }, yLabel));
  series.forEach((s, i) => {
    const colour = s.colour || COLOURS[i % COLOURS.length];
    const points = s.x.map((x, k) => [x, s.y[k]]).filter(([x, y]) => Number.isFinite(x) && Number.isFinite(y) && (!logY || y > 0));
    if (!points.length) return;
    // Values beyond the shown span are drawn at its edge.
    const clamp = (v) => Math.min(H - M.bottom, Math.max(M.top, v));
    const d = points.map(([x, y], k) => `${k ? "L" : "M"}${px(x).toFixed(1)},${clamp(py(y)).toFixed(1)}`).join("");
    svg.append(svgEl("path", { d, fill: "none", stroke: colour, "stroke-width": 1.6,
      "stroke-dasharray": s.dashed ? "5 3" : "none", "data-series": s.name }));
    const lx = M.left + 8 + i * 105;
    svg.append(svgEl("line", { x1: lx, x2: lx + 20, y1: 10, y2: 10, stroke: colour,
      "stroke-width": 2, "stroke-dasharray": s.dashed ? "5 3" : "none" }));
    svg.append(svgEl("text", { x: lx + 24, y: 14, "font-size": 11 }, s.name));
  });
  container.replaceChildren(svg);
}

/** Ticks of a log axis spanning log10 values [e0, e1]: powers of ten, or 1-2-5 steps within one decade. */
function logTicks(e0, e1) {
  const powers = [];
  for (let e = Math.ceil(e0); e <= Math.floor(e1); e++) powers.push(10 ** e);
  if (powers.length >= 2) return powers;
  return ticks(10 ** e0, 10 ** e1, 4).filter((v) => v > 0);
}

function fmt(v) {
  if (v === 0) return "0";
  const a = Math.abs(v);
  if (a >= 1e4 || a < 1e-3) return v.toExponential(0);
  return String(+v.toPrecision(3));
}
