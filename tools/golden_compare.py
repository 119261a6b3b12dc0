#!/usr/bin/env python3
"""Compares two folders written by tools/golden.sh: every design.json and
round-trip JSON, number by number (relative tolerance 1e-9; elapsed times
ignored). Prints each difference and exits non-zero if there is one."""
import json, math, pathlib, sys

IGNORED = {"elapsed_s"}
TOL = 1e-9


def walk(a, b, path, out):
    if isinstance(a, dict) and isinstance(b, dict):
        for key in sorted(set(a) | set(b)):
            if key in IGNORED:
                continue
            if key not in a or key not in b:
                out.append(f"{path}.{key}: only in {'first' if key in a else 'second'}")
                continue
            walk(a[key], b[key], f"{path}.{key}", out)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            out.append(f"{path}: length {len(a)} vs {len(b)}")
            return
        for i, (x, y) in enumerate(zip(a, b)):
            walk(x, y, f"{path}[{i}]", out)
    elif isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
        if a == b:
            return
        scale = max(abs(a), abs(b))
        if not (math.isfinite(a) and math.isfinite(b)) or abs(a - b) > TOL * scale:
            out.append(f"{path}: {a!r} vs {b!r}")
    elif a != b:
        out.append(f"{path}: {a!r} vs {b!r}")


def main():
    first, second = map(pathlib.Path, sys.argv[1:3])
    files = sorted(p.relative_to(first) for p in first.rglob("*.json"))
    if not files:
        sys.exit(f"no JSON files in {first}")
    differences = 0
    for rel in files:
        other = second / rel
        if not other.exists():
            print(f"{rel}: missing in {second}")
            differences += 1
            continue
        out = []
        walk(json.loads((first / rel).read_text()), json.loads(other.read_text()), "", out)
        for line in out[:20]:
            print(f"{rel}{line}")
        differences += len(out)
        print(f"{rel}: {'same' if not out else f'{len(out)} differences'}")
    print(f"{len(files)} files compared, {differences} differences")
    sys.exit(1 if differences else 0)


main()
