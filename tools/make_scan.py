#!/usr/bin/env python3
"""A synthetic scan of an inflated balloon (usage: make_scan.py balloon.ply
scan.ply POINTS NOISE_MM MISSING_FRACTION SEED): points sampled uniformly on the
surface of balloon.ply (written by `patchwork simulate --out`), Gaussian
noise on every coordinate, round holes where the scanner did not see;
written as binary little-endian PLY."""
import sys
import numpy as np

def read_ply(path):
    with open(path) as f:
        lines = f.read().splitlines()
    nv = int(next(l for l in lines if l.startswith("element vertex")).split()[2])
    nf = int(next(l for l in lines if l.startswith("element face")).split()[2])
    start = lines.index("end_header") + 1
    v = np.array([[float(x) for x in l.split()] for l in lines[start:start + nv]])
    f = np.array([[int(x) for x in l.split()[1:4]] for l in lines[start + nv:start + nv + nf]])
    return v, f

def main(src, dst, n, noise, missing, seed):
    rng = np.random.default_rng(seed)
    v, f = read_ply(src)
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    def sample(m):
        k = rng.choice(len(f), size=m, p=area / area.sum())
        u, w = rng.random(m), rng.random(m)
        flip = u + w > 1
        u[flip], w[flip] = 1 - u[flip], 1 - w[flip]
        return a[k] + (b[k] - a[k]) * u[:, None] + (c[k] - a[k]) * w[:, None]
    radius = 4.0
    holes = sample(int(missing * area.sum() / (np.pi * radius**2)))
    points = np.empty((0, 3))
    while len(points) < n:
        p = sample(n)
        keep = np.ones(len(p), bool)
        for h in np.array_split(holes, max(1, len(holes) // 50)):
            d = np.linalg.norm(p[:, None, :] - h[None, :, :], axis=2)
            keep &= (d >= radius).all(axis=1)
        points = np.vstack([points, p[keep]])
    points = points[:n] + rng.normal(0, noise, (n, 3))
    with open(dst, "wb") as out:
        out.write(f"ply\nformat binary_little_endian 1.0\nelement vertex {n}\n"
                  "property float x\nproperty float y\nproperty float z\nend_header\n".encode())
        out.write(points.astype("<f4").tobytes())

if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], int(sys.argv[3]), float(sys.argv[4]), float(sys.argv[5]), int(sys.argv[6]))
