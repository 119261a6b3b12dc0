"""The closed-end tube of the authors' ABAQUS/Explicit balloon, in plain Python.

Arruda-Boyce (mu 0.317 MPa, lambda_m 2.3) with ABAQUS's volumetric part
U = (1/D)((J^2 - 1)/2 - ln J), D = 2/K0, K0/mu0 = 20 (ABAQUS/Explicit's
assumption for D = 0); R0 3.18 mm, t0 0.183 mm. Plane stress: lambda_3 from
dW/dlambda_3 = 0 by bisection. Equilibrium of a long closed-end tube:
P R0 / t0 = W1 / (l1 l2) and l1 W1 = 2 l2 W2, by Newton.

These are the values tests/fe_tube_compressible.rs pins (a computation separate
from the Rust one there and from the core's):

    python3 tools/compressible_tube.py
"""
import math

ALPHA = [0.5, 1 / 20, 11 / 1050, 19 / 7000, 519 / 673750]
MU, LM = 0.317, 2.3
MU0 = MU * (1 + 3 / (5 * LM**2) + 99 / (175 * LM**4) + 513 / (875 * LM**6) + 42039 / (67375 * LM**8))
D = 2 / (20 * MU0)
R, T = 3.18, 0.183


def energy(l1, l2, l3):
    j = l1 * l2 * l3
    i1 = j ** (-2 / 3) * (l1 * l1 + l2 * l2 + l3 * l3)
    w = sum(MU * a / LM ** (2 * i) * (i1 ** (i + 1) - 3 ** (i + 1)) for i, a in enumerate(ALPHA))
    return w + ((j * j - 1) / 2 - math.log(j)) / D


def thickness(l1, l2):
    slope = lambda l3: energy(l1, l2, l3 * (1 + 1e-7)) - energy(l1, l2, l3 * (1 - 1e-7))
    lo, hi = 1e-3, 1.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if slope(mid) > 0 else (mid, hi)
    return 0.5 * (lo + hi)


def membrane(l1, l2):
    return energy(l1, l2, thickness(l1, l2))


def derivative(l1, l2, k, h=1e-6):
    if k == 0:
        return (membrane(l1 + h, l2) - membrane(l1 - h, l2)) / (2 * h)
    return (membrane(l1, l2 + h) - membrane(l1, l2 - h)) / (2 * h)


def tube(pressure_mpa, l1, l2):
    def residual(a, b):
        w1 = derivative(a, b, 0)
        return (T * w1 - pressure_mpa * R * a * b, a * w1 - 2 * b * derivative(a, b, 1))

    for _ in range(50):
        r = residual(l1, l2)
        h = 1e-5
        da = [(x - y) / h for x, y in zip(residual(l1 + h, l2), r)]
        db = [(x - y) / h for x, y in zip(residual(l1, l2 + h), r)]
        det = da[0] * db[1] - da[1] * db[0]
        l1 -= (r[0] * db[1] - r[1] * db[0]) / det
        l2 -= (da[0] * r[1] - da[1] * r[0]) / det
    return l1, l2


if __name__ == "__main__":
    print(f"mu0 = {MU0:.6f} MPa, K0 = {2 / D:.4f} MPa")
    for kpa, start in [(18, (4.5, 3.2)), (20, (5.0, 3.6)), (23, (6.5, 4.6))]:
        l1, l2 = tube(kpa * 1e-3, *start)
        l3 = thickness(l1, l2)
        print(f"{kpa} kPa: hoop {l1:.6f}, axial {l2:.6f}, thickness {l3:.6f}, J {l1 * l2 * l3:.4f}")
