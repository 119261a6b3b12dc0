#!/usr/bin/env python3
"""Cross-check of Patchwork's membrane model against CalculiX (ccx).

One patch on a short closed-end tube, inflated below the limit point, in both
codes; the tip ring's rotation is compared: bend angle (tilt of the ring's
normal) and twist (the rotation about the tube axis, by swing-twist
decomposition of the best-fit rotation of the tip ring's nodes, Kabsch).

CalculiX side: S4 shells on a structured quad mesh of the tube and a
hemispherical cap (S3 at the pole), neo-Hookean (*HYPERELASTIC, K/μ = 1000),
base ring pinned, follower pressure (*DLOAD P, NLGEOM). A patch "replaces" the
wall in every element whose centroid lies in the patch's rotated rectangle; its
thickness equals the wall's and its μ carries the patch's membrane stiffness
μ_p·t_p (a thickness jump between shell sections made ccx diverge at the first
increment on meshes finer than 16 around; a membrane sees only μ·t, so
Patchwork's answer is unchanged). Patchwork side: `patchwork simulate` on the
same patch, W and H set to the ccx staircase's extent (exact for Θ = 0).

Usage (ccx from the Debian package calculix-ccx; numpy):
    tools/calculix/crosscheck.py --around 32 --pressure-kpa 6 --theta 0
Minutes per run: ccx takes ~0.5 s per Newton iteration at 32 around and needs
~200 iterations. Findings are in BENCHMARKS.md ("CalculiX cross-check").
"""

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

R, T_WALL, MU_WALL = 3.18, 0.183, 0.317
T_PATCH, MU_PATCH = 0.49, 1.3
BULK_OVER_MU = 1000.0


def tube_mesh(length, around, shear_deg=0.0):
    """Quad mesh of the tube (rings of `around` nodes) and the cap. With
    `shear_deg`, each ring is turned so that the element columns run at that
    angle from the axis (helical strips): a patch at that Θ then has its long
    edges on element edges instead of a staircase."""
    h = 2 * math.pi * R / around
    rings = max(1, round(length / h))
    turn = math.tan(math.radians(shear_deg)) / R  # radians per mm of axis
    nodes, index = [], {}

    def add(key, xyz):
        index[key] = len(nodes) + 1
        nodes.append(xyz)

    for j in range(rings + 1):
        for i in range(around):
            y = length * j / rings
            a = 2 * math.pi * i / around + turn * y
            add(("t", j, i), (R * math.cos(a), R * math.sin(a), y))
    cap = max(2, round(math.pi / 2 * R / h))
    for k in range(1, cap):
        phi = math.pi / 2 * k / cap
        for i in range(around):
            a = 2 * math.pi * i / around + turn * length
            r = R * math.cos(phi)
            add(("c", k, i), (r * math.cos(a), r * math.sin(a), length + R * math.sin(phi)))
    add(("pole",), (0.0, 0.0, length + R))

    def node(j, i):
        key = ("t", j, i % around) if j <= rings else ("c", j - rings, i % around)
        return index[key]

    quads = []
    for j in range(rings + cap - 1):
        for i in range(around):
            # Counter-clockwise seen from outside: the normal points out.
            quads.append(((j, i), (node(j, i), node(j, i + 1), node(j + 1, i + 1), node(j + 1, i))))
    tris = [(node(rings + cap - 1, i), node(rings + cap - 1, i + 1), index[("pole",)]) for i in range(around)]
    tip = [node(rings, i) for i in range(around)]
    base = [node(0, i) for i in range(around)]
    return nodes, quads, tris, tip, base, rings, h


def in_patch(x, y, patch, circumference):
    dx = (x - patch["x_mm"] + circumference / 2) % circumference - circumference / 2
    dy = y - patch["y_mm"]
    th = math.radians(patch["theta_deg"])
    u = dx * math.cos(th) - dy * math.sin(th)
    v = dx * math.sin(th) + dy * math.cos(th)
    return abs(u) <= patch["w_mm"] / 2 and abs(v) <= patch["h_mm"] / 2


def write_ccx(path, length, around, patch, pressure_mpa, shear_deg):
    nodes, quads, tris, tip, base, rings, h = tube_mesh(length, around, shear_deg)
    shift = math.tan(math.radians(shear_deg))
    circumference = 2 * math.pi * R
    wall, patched = [], []
    cells = []
    for (j, i), quad in quads:
        y = (j + 0.5) * length / rings
        centre = ((i + 0.5) * h + shift * y, y)
        if j < rings and in_patch(*centre, patch, circumference):
            patched.append(quad)
            cells.append((i, j))
        else:
            wall.append(quad)
    with open(path, "w") as out:
        out.write("*NODE,NSET=NALL\n")
        for k, (x, y, z) in enumerate(nodes):
            out.write(f"{k + 1},{x:.12g},{y:.12g},{z:.12g}\n")
        k = 0
        for name, kind, elements in (("EW", "S4", wall), ("EP", "S4", patched), ("ET", "S3", tris)):
            out.write(f"*ELEMENT,TYPE={kind},ELSET={name}\n")
            for e in elements:
                k += 1
                out.write(f"{k}," + ",".join(map(str, e)) + "\n")
        out.write("*ELSET,ELSET=EALL\nEW,EP,ET\n*ELSET,ELSET=EWALL\nEW,ET\n")
        out.write("*NSET,NSET=BASE\n" + "\n".join(map(str, base)) + "\n")
        out.write("*NSET,NSET=TIP\n" + "\n".join(map(str, tip)) + "\n")
        mu_patch = MU_PATCH * T_PATCH / T_WALL
        for name, mu in (("LATEX", MU_WALL), ("PATCH", mu_patch)):
            d1 = 2.0 / (BULK_OVER_MU * mu)
            out.write(f"*MATERIAL,NAME={name}\n*HYPERELASTIC,NEO HOOKE\n{mu / 2:.9g},{d1:.9g}\n")
        out.write(f"*SHELL SECTION,ELSET=EWALL,MATERIAL=LATEX\n{T_WALL}\n")
        out.write(f"*SHELL SECTION,ELSET=EP,MATERIAL=PATCH\n{T_WALL}\n")
        out.write("*BOUNDARY\nBASE,1,3\n")
        out.write("*STEP,NLGEOM,INC=1000\n*STATIC\n0.05,1.0,1e-6,0.1\n")
        out.write(f"*DLOAD\nEALL,P,{pressure_mpa}\n")
        out.write("*NODE PRINT,NSET=TIP\nU\n*END STEP\n")
    reference_tip = np.array([nodes[n - 1] for n in tip])
    return tip, reference_tip, cells, h, length / rings


def ring_rotation(reference, deformed):
    """Bend angle and twist (degrees) of the best-fit rotation of a ring."""
    a = reference - reference.mean(0)
    b = deformed - deformed.mean(0)
    u, _, vt = np.linalg.svd(a.T @ b)
    d = np.sign(np.linalg.det(vt.T @ u.T))
    rot = vt.T @ np.diag([1, 1, d]) @ u.T
    bend = math.degrees(math.acos(np.clip(rot[2, 2], -1, 1)))
    w = math.sqrt(max(0.0, 1 + np.trace(rot))) / 2
    z = (rot[1, 0] - rot[0, 1]) / (4 * w)
    return bend, math.degrees(2 * math.atan2(z, w)), deformed.mean(0)


def run_ccx(workdir, length, around, patch, pressure_mpa, shear_deg):
    tip, reference, cells, hx, hy = write_ccx(
        os.path.join(workdir, "tube.inp"), length, around, patch, pressure_mpa, shear_deg)
    env = dict(os.environ, OMP_NUM_THREADS="1")
    log = subprocess.run(["ccx", "-i", "tube"], cwd=workdir, env=env, capture_output=True, text=True)
    text = open(os.path.join(workdir, "tube.dat")).read()
    last = text.split("displacements (vx,vy,vz) for set TIP and time")[-1].strip().splitlines()
    time = float(last[0]) if last else 0.0
    if time < 1.0 or "ERROR" in log.stdout:
        sys.exit(f"ccx did not reach the full load (step time {time})")
    u = {int(f[0]): [float(v) for v in f[1:]] for f in (line.split() for line in last[1:]) if len(f) == 4}
    deformed = np.array([reference[k] + np.array(u[n]) for k, n in enumerate(tip)])
    iterations = log.stdout.count(" iteration ")
    return ring_rotation(reference, deformed), cells, hx, hy, iterations


def run_patchwork(binary, workdir, length, patch, pressure_kpa, mesh_mm):
    design = {
        "balloon": {"length_mm": length, "radius_mm": R, "wall_mm": T_WALL,
                    "material": {"model": "neo_hookean", "mu_mpa": MU_WALL}},
        "patch": {"thickness_mm": T_PATCH, "material": {"model": "neo_hookean", "mu_mpa": MU_PATCH},
                  "bonding": "replace"},
        "pressure_kpa": pressure_kpa,
        "patches": [patch],
    }
    path = os.path.join(workdir, "design.json")
    json.dump(design, open(path, "w"))
    out = os.path.join(workdir, "patchwork")
    subprocess.run([binary, "simulate", path, "--mesh-mm", str(mesh_mm), "--out", out], check=True,
                   capture_output=True)
    lines = open(os.path.join(out, "balloon.vtk")).read().split("\n")
    start = next(k for k, line in enumerate(lines) if line.startswith("POINTS"))
    count = int(lines[start].split()[1])
    points = np.array([[float(v) for v in lines[start + 1 + k].split()] for k in range(count)])
    # Patchwork's uniform mesh (MeshSpec::around_for and TubeMesh::new): rings
    # of `around` nodes, ring-major, the tip ring last before the cap.
    around = max(8, round(2 * math.pi * R / mesh_mm))
    rings = max(2, round(length / mesh_mm)) + 1
    tip = points[(rings - 1) * around: rings * around]
    reference = np.array([[R * math.cos(2 * math.pi * j / around), R * math.sin(2 * math.pi * j / around), length]
                          for j in range(around)])
    return ring_rotation(reference, tip)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--around", type=int, default=32)
    parser.add_argument("--length-mm", type=float, default=40.0)
    parser.add_argument("--pressure-kpa", type=float, default=6.0)
    parser.add_argument("--theta", type=float, default=0.0)
    parser.add_argument("--mesh-mm", type=float, nargs="+", default=[1.0, 0.5, 0.25])
    parser.add_argument("--shear", action="store_true",
                        help="align the ccx element columns with the patch (Θ ≠ 0)")
    parser.add_argument("--patchwork", default="target/release/patchwork")
    args = parser.parse_args()
    patch = {"x_mm": 5.0, "y_mm": args.length_mm / 2, "h_mm": 15.0, "w_mm": 3.0, "theta_deg": args.theta}
    with tempfile.TemporaryDirectory() as workdir:
        (bend, twist, centre), cells, hx, hy, iterations = run_ccx(
            workdir, args.length_mm, args.around, patch, args.pressure_kpa / 1000,
            args.theta if args.shear else 0.0)
        print(f"ccx {args.around} around: bend {bend:.3f}°, twist {twist:.3f}°, tip {np.round(centre, 3)}, "
              f"{iterations} iterations, patch {len(cells) * hx * hy:.2f} mm² (exact {patch['h_mm'] * patch['w_mm']:.2f})")
        if args.theta == 0 or args.shear:
            # The element columns the patch covers, as a rectangle of the same
            # width and area (exact for Θ = 0; for a sheared mesh only the
            # short ends are staircases). X only turns the bending plane.
            columns = sorted({i for i, _ in cells})
            rows = sorted({j for _, j in cells})
            patch["w_mm"] = len(columns) * hx * math.cos(math.radians(args.theta))
            patch["h_mm"] = len(cells) * hx * hy / patch["w_mm"]
            if args.theta == 0:
                patch["x_mm"] = (columns[0] + len(columns) / 2) * hx
                patch["y_mm"] = (rows[0] + len(rows) / 2) * hy
        print(f"patchwork's patch: {patch}")
        for mesh in args.mesh_mm:
            bend, twist, centre = run_patchwork(args.patchwork, workdir, args.length_mm, patch,
                                                args.pressure_kpa, mesh)
            print(f"patchwork {mesh} mm: bend {bend:.3f}°, twist {twist:.3f}°, tip {np.round(centre, 3)}")


if __name__ == "__main__":
    main()
