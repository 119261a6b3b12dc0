// Shape error as the server computes it (curve/shape_error.rs): both curves
// resampled to 200 points at equal fractions of their length, the rigid
// motion that best maps one onto the other (Horn's quaternion method, the
// same optimum as Kabsch's), and the RMS distance that remains.

export const SHAPE_SAMPLES = 200;

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const norm = (a) => Math.hypot(a[0], a[1], a[2]);

export function length(points) {
  let total = 0;
  for (let i = 1; i < points.length; i++) total += norm(sub(points[i], points[i - 1]));
  return total;
}

/** `n` points at equal arc-length fractions along the polyline. */
export function resample(points, n) {
  const s = [0];
  for (let i = 1; i < points.length; i++) s.push(s[i - 1] + norm(sub(points[i], points[i - 1])));
  const total = s[s.length - 1];
  const out = [];
  let j = 0;
  for (let k = 0; k < n; k++) {
    const target = (total * k) / (n - 1);
    while (j < points.length - 2 && s[j + 1] < target) j++;
    const span = s[j + 1] - s[j] || 1;
    const t = Math.min(1, Math.max(0, (target - s[j]) / span));
    out.push([0, 1, 2].map((c) => points[j][c] + t * (points[j + 1][c] - points[j][c])));
  }
  return out;
}

/** Eigenvector of the largest eigenvalue of a symmetric 4×4 matrix (Jacobi rotations). */
function largestEigenvector(a) {
  const m = a.map((row) => row.slice());
  const v = [0, 1, 2, 3].map((i) => [0, 1, 2, 3].map((j) => (i === j ? 1 : 0)));
  for (let sweep = 0; sweep < 50; sweep++) {
    let off = 0;
    for (let p = 0; p < 4; p++) for (let q = p + 1; q < 4; q++) off += m[p][q] ** 2;
    if (off < 1e-22) break;
    for (let p = 0; p < 4; p++) {
      for (let q = p + 1; q < 4; q++) {
        if (Math.abs(m[p][q]) < 1e-300) continue;
        const theta = (m[q][q] - m[p][p]) / (2 * m[p][q]);
        const t = Math.sign(theta || 1) / (Math.abs(theta) + Math.sqrt(theta * theta + 1));
        const c = 1 / Math.sqrt(t * t + 1), s = t * c;
        for (let k = 0; k < 4; k++) {
          const mkp = m[k][p], mkq = m[k][q];
          m[k][p] = c * mkp - s * mkq;
          m[k][q] = s * mkp + c * mkq;
        }
        for (let k = 0; k < 4; k++) {
          const mpk = m[p][k], mqk = m[q][k];
          m[p][k] = c * mpk - s * mqk;
          m[q][k] = s * mpk + c * mqk;
        }
        for (let k = 0; k < 4; k++) {
          const vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
    }
  }
  let best = 0;
  for (let i = 1; i < 4; i++) if (m[i][i] > m[best][best]) best = i;
  return [0, 1, 2, 3].map((k) => v[k][best]);
}

/**
 * The rigid motion taking `moving` onto `fixed` (both polylines):
 * `{apply(p), rmsMm, percent}` where percent is of `fixed`'s length.
 */
export function align(moving, fixed) {
  const a = resample(moving, SHAPE_SAMPLES), b = resample(fixed, SHAPE_SAMPLES);
  const mean = (ps) => [0, 1, 2].map((c) => ps.reduce((t, p) => t + p[c], 0) / ps.length);
  const ca = mean(a), cb = mean(b);
  const S = [[0, 0, 0], [0, 0, 0], [0, 0, 0]];
  for (let i = 0; i < a.length; i++) {
    const p = sub(a[i], ca), q = sub(b[i], cb);
    for (let r = 0; r < 3; r++) for (let c = 0; c < 3; c++) S[r][c] += p[r] * q[c];
  }
  const [[xx, xy, xz], [yx, yy, yz], [zx, zy, zz]] = S;
  const N = [
    [xx + yy + zz, yz - zy, zx - xz, xy - yx],
    [yz - zy, xx - yy - zz, xy + yx, zx + xz],
    [zx - xz, xy + yx, -xx + yy - zz, yz + zy],
    [xy - yx, zx + xz, yz + zy, -xx - yy + zz],
  ];
  const [w, x, y, z] = largestEigenvector(N);
  const R = [
    [w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)],
    [2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)],
    [2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z],
  ];
  const apply = (p) => {
    const d = sub(p, ca);
    return [0, 1, 2].map((r) => R[r][0] * d[0] + R[r][1] * d[1] + R[r][2] * d[2] + cb[r]);
  };
  let sum = 0;
  for (let i = 0; i < a.length; i++) sum += norm(sub(apply(a[i]), b[i])) ** 2;
  const rmsMm = Math.sqrt(sum / a.length);
  return { apply, rmsMm, percent: (100 * rmsMm) / length(fixed) };
}
