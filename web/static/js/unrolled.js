// The balloon cut open along its seam and laid flat: axial position to the
// right (mm from the clamped base), the circumference upwards, each patch a
// rectangle H long and W wide turned by Θ from the axis.

import { ticks } from "./plot.js";

const NS = "http://www.w3.org/2000/svg";
const WIDTH = 1000, MARGIN = 24, AXIS = 26;

function svgEl(tag, attributes = {}, text) {
  const node = document.createElementNS(NS, tag);
  for (const [k, v] of Object.entries(attributes)) node.setAttribute(k, v);
  if (text !== undefined) node.textContent = text;
  return node;
}

/** Draws `patches` on a balloon of `lengthMm` and `radiusMm` into `container`. */
export function drawUnrolled(container, { lengthMm, radiusMm, patches }) {
  const circumference = 2 * Math.PI * radiusMm;
  const scale = (WIDTH - 2 * MARGIN) / lengthMm;
  // A long balloon is drawn taller than true so its patches stay visible.
  const stretch = Math.max(1, 36 / (circumference * scale));
  const height = circumference * scale * stretch;
  const total = height + MARGIN + AXIS;
  const svg = svgEl("svg", { viewBox: `0 0 ${WIDTH} ${total}`, role: "img",
    "aria-label": `${patches.length} patches on a balloon ${lengthMm.toFixed(1)} mm long` });
  const X = (axial) => MARGIN + axial * scale;
  const Y = (around) => MARGIN / 2 + height - around * scale * stretch;
  svg.append(svgEl("rect", { x: X(0), y: Y(circumference), width: lengthMm * scale, height,
    fill: "#f1f3f5", stroke: "#495057" }));
  for (const t of ticks(0, lengthMm, 8)) {
    svg.append(svgEl("line", { x1: X(t), x2: X(t), y1: Y(0), y2: Y(0) + 5, stroke: "#495057" }));
    svg.append(svgEl("text", { x: X(t), y: Y(0) + 17, "text-anchor": "middle", "font-size": 11 }, `${t}`));
  }
  svg.append(svgEl("text", { x: WIDTH - MARGIN, y: total - 2, "text-anchor": "end", "font-size": 11 },
    stretch > 1 ? `mm from the base (circumference drawn ×${stretch.toFixed(1)})` : "mm from the base"));
  patches.forEach((p, i) => {
    const around = ((p.x_mm % circumference) + circumference) % circumference;
    // Θ turns the long axis from the balloon's axis; drawn in true shape
    // (scaled back when the circumference is stretched).
    const t = (p.theta_deg * Math.PI) / 180;
    const corners = [[-1, -1], [1, -1], [1, 1], [-1, 1]].map(([a, b]) => {
      const u = (a * p.h_mm) / 2, v = (b * p.w_mm) / 2;
      const axial = p.y_mm + u * Math.cos(t) - v * Math.sin(t);
      const circ = around + u * Math.sin(t) + v * Math.cos(t);
      return `${X(axial).toFixed(1)},${Y(circ).toFixed(1)}`;
    });
    const group = svgEl("g", { "data-patch": i + 1 });
    group.append(svgEl("title", {}, `P${i + 1}: X ${p.x_mm.toFixed(2)}, Y ${p.y_mm.toFixed(2)}, H ${p.h_mm.toFixed(2)}, W ${p.w_mm.toFixed(2)} mm, Θ ${p.theta_deg.toFixed(1)}°`));
    group.append(svgEl("polygon", { points: corners.join(" "), fill: "#d9480f", "fill-opacity": 0.75, stroke: "#862e00" }));
    group.append(svgEl("text", { x: X(p.y_mm), y: Y(circumference) - 3, "text-anchor": "middle", "font-size": 10 }, `P${i + 1}`));
    svg.append(group);
  });
  container.replaceChildren(svg);
}
