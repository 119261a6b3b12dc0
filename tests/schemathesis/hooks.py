"""Rules of the Patchwork API that join fields, which JSON Schema cannot state.

openapi.yaml lists them in its description; the server answers 422 naming the
field when one is broken. Generated bodies that break one are skipped, so that
schemathesis' `positive_data_acceptance` judges exactly the field-by-field
schema, and every other check runs on every body. Nothing else is filtered.
"""

import math

import schemathesis

# Defaults of the fields a rule joins (the reference scene, the default bounds).
BALLOON = {"length_mm": 292.0, "radius_mm": 3.18, "wall_mm": 0.183}
BOUNDS = {"h_min_mm": 10.0, "h_max_mm": 30.0, "w_min_mm": 1.0, "w_max_mm": 3.0}
HILBERT = {"edge_mm": 144.0, "corner_radius_mm": 47.0}
# Millimetres per unit of a curve's coordinates.
UNITS_MM = {"mm": 1.0, "cm": 10.0, "m": 1000.0, "in": 25.4}
# The coarsest element of every preset's models (the search mesh), mm.
PRESET_ELEMENT_MM = 3.0
# The default mesh of POST /v1/simulate under patches, mm.
SIMULATE_ELEMENT_MM = 0.5


def _dict(value):
    return value if isinstance(value, dict) else {}


def _distinct_successive(points):
    """As the server counts them: successive points closer than 1e-9 × the
    diagonal of the bounding box are one point."""
    if not points:
        return 0
    diagonal = math.dist(
        [min(p[i] for p in points) for i in range(3)],
        [max(p[i] for p in points) for i in range(3)],
    )
    tolerance = 1e-9 * max(diagonal, 1e-12)
    kept = []
    for point in points:
        if not kept or math.dist(kept[-1], point) > tolerance:
            kept.append(point)
    return len(kept)


def _csv_points(text):
    rows = [line.split("#")[0].strip() for line in text.splitlines()]
    return [tuple(float(v) for v in row.split(",")) for row in rows if row]


def _curve_points(curve):
    """The points of a points or csv curve; None for a preset."""
    if isinstance(curve.get("points"), list):
        return [tuple(p) for p in curve["points"] if isinstance(p, list)]
    if isinstance(curve.get("csv"), str):
        return _csv_points(curve["csv"])
    return None


def smoothing_ok(body, sigma):
    """`sigma` (a job's `options.smooth_mm`, `smooth_mm` of POST /v1/curve)
    is at most a quarter of the curve's length. A preset's length depends
    on its parameters: a preset with smoothing is skipped."""
    if not sigma:
        return True
    points = _curve_points(_dict(body.get("curve")))
    if points is None:
        return False
    scale = UNITS_MM.get(body.get("units", "mm"), 1.0)
    length = scale * sum(math.dist(a, b) for a, b in zip(points, points[1:]))
    return sigma <= length / 4


def curve_ok(curve):
    """At least 4 distinct successive points; a Hilbert corner fits its edge."""
    curve = _dict(curve)
    try:
        points = _curve_points(curve)
        if points is not None:
            return _distinct_successive(points) >= 4
    except (TypeError, ValueError, IndexError):
        return True  # not a plain curve: a negative case, left to the server
    if curve.get("preset") == "hilbert":
        params = {**HILBERT, **_dict(curve.get("params"))}
        return params["corner_radius_mm"] <= params["edge_mm"] / 2
    return True


def material_ok(material):
    """An Ogden material's terms pair up, each μₚαₚ positive (stability)."""
    material = _dict(material)
    if material.get("model") != "ogden":
        return True
    mu, alpha = material.get("mu_mpa", []), material.get("alpha", [])
    return len(mu) == len(alpha) and all(m * a > 0 for m, a in zip(mu, alpha))


def balloon_ok(design, element_mm):
    """A membrane (wall thinner than the radius) that the mesh fits round."""
    design = _dict(design)
    balloon = {**BALLOON, **_dict(design.get("balloon"))}
    if balloon["wall_mm"] >= balloon["radius_mm"]:
        return False
    materials = [balloon.get("material"), _dict(design.get("patch")).get("material")]
    return element_mm <= 2 * balloon["radius_mm"] and all(map(material_ok, materials))


def patches_ok(design):
    """Every patch overlaps the balloon along its axis."""
    length = {**BALLOON, **_dict(_dict(design).get("balloon"))}["length_mm"]
    for patch in _dict(design).get("patches") or []:
        theta = math.radians(patch["theta_deg"])
        half = 0.5 * (patch["h_mm"] * abs(math.cos(theta)) + patch["w_mm"] * abs(math.sin(theta)))
        if patch["y_mm"] + half <= 0 or patch["y_mm"] - half >= length:
            return False
    return True


def bounds_ok(bounds):
    bounds = {**BOUNDS, **_dict(bounds)}
    return bounds["h_min_mm"] < bounds["h_max_mm"] and bounds["w_min_mm"] < bounds["w_max_mm"]


def job_ok(body):
    mesh = _dict(body.get("tuning")).get("uniform_mesh_mm", PRESET_ELEMENT_MM)
    # A `balloon_profile` must name a profile this key stored: which names
    # exist, no schema can say (a 422 naming the field otherwise).
    return (
        "balloon_profile" not in body
        and curve_ok(body.get("curve"))
        and smoothing_ok(body, _dict(body.get("options")).get("smooth_mm"))
        and bounds_ok(body.get("bounds"))
        and balloon_ok(body.get("design"), mesh)
    )


def simulate_ok(body):
    mesh = body.get("mesh_mm", SIMULATE_ELEMENT_MM)
    straight = body.get("straight_mm")
    if straight is not None and not (mesh <= straight <= 100 * mesh):
        return False
    design = body.get("design")
    return balloon_ok(design, mesh) and patches_ok(design)


RULES = {
    ("POST", "/v1/jobs"): job_ok,
    ("POST", "/v1/curve"): lambda body: curve_ok(body.get("curve"))
    and smoothing_ok(body, body.get("smooth_mm")),
    ("POST", "/v1/ksa"): lambda body: curve_ok(body.get("curve")),
    ("POST", "/v1/simulate"): simulate_ok,
    # A profile is a design's balloon and patch: the same membrane rules.
    ("PUT", "/v1/balloons/{name}"): lambda body: balloon_ok(body, 0.0),
}


@schemathesis.hook
def filter_case(ctx, case):
    """`filter_case` runs in every phase, the coverage phase's included."""
    rule = RULES.get((case.operation.method.upper(), case.operation.path))
    body = case.body
    if rule is None or not isinstance(body, dict):
        return True
    try:
        return rule(body)
    except (KeyError, TypeError, ValueError, OverflowError, IndexError):
        return True  # a body the schema would not allow: a negative case
