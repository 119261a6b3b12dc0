//! The independent side of the CalculiX cross-check: writes a CalculiX (`ccx`)
//! model of a closed-end tube with one patch, runs it, and reads back the
//! displacements of the tip ring.
//!
//! The model is deliberately built from different parts than Patchwork's:
//! 8-node quadratic shells (S8R, S6 at the pole) instead of linear membrane
//! triangles, ccx's own neo-Hookean law (`*HYPERELASTIC, NEO HOOKE`, nearly
//! incompressible at K = 1000 μ, or compressible at a given K/μ) instead of the
//! plane-stress closed form, its
//! follower pressure and load incrementation. The patch "replaces" the wall in
//! every element whose centroid lies in the patch rectangle; the patch sections
//! keep the wall's thickness and carry the patch's membrane stiffness μ_p·t_p
//! in μ (a membrane sees only μ·t, and a thickness jump between shell sections
//! made ccx diverge).
//!
//! The mesh is structured: `around` elements round the tube, square elements
//! along it, rings of the hemispherical cap, a row of S6 triangles at the pole.
//! With `shear_deg` every ring is turned in proportion to its height so that
//! the element columns run at that angle from the axis (helical strips): a
//! patch at that angle then has its long edges on element edges.

use std::collections::HashMap;
use std::f64::consts::{FRAC_PI_2, TAU};
use std::fmt::Write as _;
use std::path::Path;

use patchwork_core::curve::Point;
use patchwork_core::design::Patch;

mod runner;

use runner::{run_deck, tail};

/// Geometry, materials and load of the cross-check (mm, MPa).
#[derive(Debug, Clone, Copy)]
pub struct Tube {
    pub length: f64,
    pub radius: f64,
    pub wall: f64,
    pub wall_mu: f64,
    /// Patch membrane stiffness μ_p·t_p (N/mm).
    pub patch_mu_t: f64,
    pub pressure_mpa: f64,
    /// K/μ of both materials (1000: nearly incompressible).
    pub bulk_ratio: f64,
}

/// The structured shell mesh and what the run needs from it.
#[derive(Debug, Clone, Copy)]
pub struct Mesh {
    /// Elements round the tube.
    pub around: usize,
    /// Angle of the element columns from the axis (degrees).
    pub shear_deg: f64,
}

/// What one ccx run produced.
#[derive(Debug)]
pub struct Run {
    /// Reference and deformed positions of the tip ring's corner nodes.
    pub tip_reference: Vec<Point>,
    pub tip_deformed: Vec<Point>,
    /// Area of the elements that carry the patch section (mm²).
    pub patch_area: f64,
    pub nodes: usize,
    pub newton_iterations: usize,
    pub seconds: f64,
}

struct Model {
    nodes: Vec<Point>,
    /// (element type, node numbers from 1, in the patch)
    elements: Vec<(&'static str, Vec<usize>, bool)>,
    base: Vec<usize>,
    tip: Vec<usize>,
    patch_area: f64,
}

/// Builds the quadratic shell mesh: a node grid at half the element size,
/// of which the element corners and mid-sides are used.
fn build(tube: &Tube, mesh: &Mesh, patch: &Patch) -> Model {
    let circumference = TAU * tube.radius;
    let h = circumference / mesh.around as f64;
    let rings = ((tube.length / h).round() as usize).max(1);
    let cap_rows = ((FRAC_PI_2 * tube.radius / h).round() as usize).max(2);
    let turn = mesh.shear_deg.to_radians().tan() / tube.radius; // rad per mm of axis
    let columns = 2 * mesh.around;
    // Grid rows 0..=2·rings are tube rings; then cap rows up to the pole.
    let last_row = 2 * (rings + cap_rows);
    let row_height = |r: usize| tube.length * r.min(2 * rings) as f64 / (2 * rings) as f64;

    let mut nodes = Vec::new();
    let mut index: HashMap<(usize, usize), usize> = HashMap::new();
    let mut node = |r: usize, c: usize| -> usize {
        let key = if r == last_row {
            (r, 0)
        } else {
            (r, c % columns)
        };
        *index.entry(key).or_insert_with(|| {
            let a = TAU * key.1 as f64 / columns as f64 + turn * row_height(r);
            let p = if r <= 2 * rings {
                Point::new(tube.radius * a.cos(), tube.radius * a.sin(), row_height(r))
            } else {
                let phi = FRAC_PI_2 * (r - 2 * rings) as f64 / (2 * cap_rows) as f64;
                let ring = tube.radius * phi.cos();
                Point::new(
                    ring * a.cos(),
                    ring * a.sin(),
                    tube.length + tube.radius * phi.sin(),
                )
            };
            nodes.push(p);
            nodes.len()
        })
    };

    let shift = mesh.shear_deg.to_radians().tan();
    let dy = tube.length / rings as f64;
    let mut elements = Vec::new();
    let mut patch_area = 0.0;
    for e_row in 0..rings + cap_rows {
        for e_col in 0..mesh.around {
            let (r, c) = (2 * e_row, 2 * e_col);
            // Counter-clockwise seen from outside: the normal points out.
            if e_row + 1 == rings + cap_rows {
                let corners = [node(r, c), node(r, c + 2), node(last_row, 0)];
                let sides = [node(r, c + 1), node(r + 1, c + 2), node(r + 1, c)];
                elements.push(("S6", [corners, sides].concat(), false));
                continue;
            }
            let corners = [
                node(r, c),
                node(r, c + 2),
                node(r + 2, c + 2),
                node(r + 2, c),
            ];
            let sides = [
                node(r, c + 1),
                node(r + 1, c + 2),
                node(r + 2, c + 1),
                node(r + 1, c),
            ];
            let centre_y = (e_row as f64 + 0.5) * dy;
            let centre_x = (e_col as f64 + 0.5) * h + shift * centre_y;
            let patched = e_row < rings && covers(patch, centre_x, centre_y, circumference);
            if patched {
                patch_area += h * dy;
            }
            elements.push(("S8R", [corners, sides].concat(), patched));
        }
    }
    let base = (0..columns).map(|c| node(0, c)).collect();
    let tip = (0..columns)
        .step_by(2)
        .map(|c| node(2 * rings, c))
        .collect();
    Model {
        nodes,
        elements,
        base,
        tip,
        patch_area,
    }
}

/// Whether the unrolled point (x, y) lies in the patch rectangle, whose long
/// axis makes Θ with the tube axis (Patchwork's convention), or in one of its
/// images a circumference either side (a long oblique patch reaches past the
/// seam by more than half a circumference).
fn covers(patch: &Patch, x: f64, y: f64, circumference: f64) -> bool {
    let (sin, cos) = patch.theta_deg.to_radians().sin_cos();
    let dy = y - patch.y_mm;
    [-circumference, 0.0, circumference].iter().any(|shift| {
        let dx = x - (patch.x_mm + shift);
        let along = dx * sin + dy * cos;
        let across = dx * cos - dy * sin;
        along.abs() <= 0.5 * patch.h_mm && across.abs() <= 0.5 * patch.w_mm
    })
}

fn input_deck(tube: &Tube, model: &Model) -> String {
    let mut deck = String::from("*NODE,NSET=NALL\n");
    for (k, p) in model.nodes.iter().enumerate() {
        let _ = writeln!(deck, "{},{:.12e},{:.12e},{:.12e}", k + 1, p.x, p.y, p.z);
    }
    let mut number = 0;
    for (set, kind, patched) in [
        ("WALL", "S8R", false),
        ("POLE", "S6", false),
        ("PATCH", "S8R", true),
    ] {
        let _ = writeln!(deck, "*ELEMENT,TYPE={kind},ELSET={set}");
        for (_, nodes, _) in model
            .elements
            .iter()
            .filter(|(k, _, p)| *k == kind && *p == patched)
        {
            number += 1;
            let list: Vec<String> = nodes.iter().map(usize::to_string).collect();
            let _ = writeln!(deck, "{number},{}", list.join(","));
        }
    }
    let list = |nodes: &[usize]| {
        let items: Vec<String> = nodes.iter().map(usize::to_string).collect();
        items.join("\n")
    };
    let _ = writeln!(deck, "*NSET,NSET=BASE\n{}", list(&model.base));
    let _ = writeln!(deck, "*NSET,NSET=TIP\n{}", list(&model.tip));
    deck.push_str("*ELSET,ELSET=EALL\nWALL,POLE,PATCH\n*ELSET,ELSET=LATEX\nWALL,POLE\n");
    for (name, mu) in [
        ("LATEX", tube.wall_mu),
        ("STIFF", tube.patch_mu_t / tube.wall),
    ] {
        // ccx's neo-Hooke: W = C10 (Ī₁ − 3) + (J − 1)²/D1, C10 = μ/2, D1 = 2/K.
        let bulk = tube.bulk_ratio * mu;
        let _ = writeln!(
            deck,
            "*MATERIAL,NAME={name}\n*HYPERELASTIC,NEO HOOKE\n{:.9e},{:.9e}",
            0.5 * mu,
            2.0 / bulk
        );
    }
    let _ = writeln!(
        deck,
        "*SHELL SECTION,ELSET=LATEX,MATERIAL=LATEX\n{w}\n*SHELL SECTION,ELSET=PATCH,MATERIAL=STIFF\n{w}",
        w = tube.wall
    );
    deck.push_str("*BOUNDARY\nBASE,1,3\n");
    // Tight equilibrium tolerances (defaults 0.005 and 0.01): at the defaults
    // the bend depended on the load increments by 1.5 %, with these by 0.13 %.
    deck.push_str("*CONTROLS,PARAMETERS=FIELD,FIELD=DISPLACEMENT\n1e-5,1e-4\n");
    deck.push_str("*STEP,NLGEOM,INC=1000\n*STATIC\n0.25,1.0,1e-6,0.5\n");
    let _ = writeln!(deck, "*DLOAD\nEALL,P,{:.9e}", tube.pressure_mpa);
    deck.push_str("*NODE PRINT,NSET=TIP\nU\n*END STEP\n");
    deck
}

/// Writes the deck into `dir`, runs `ccx` there and reads the tip ring.
pub fn run(dir: &Path, tube: &Tube, mesh: &Mesh, patch: &Patch) -> Result<Run, String> {
    let model = build(tube, mesh, patch);
    let output = run_deck(dir, &input_deck(tube, &model))?;
    let (time, displacements) = last_tip_block(&output.dat)?;
    if !output.clean || (time - 1.0).abs() > 1e-9 {
        return Err(format!(
            "ccx stopped at step time {time}; its output ends:\n{}",
            tail(&output.log)
        ));
    }
    let tip_reference: Vec<Point> = model.tip.iter().map(|&n| model.nodes[n - 1]).collect();
    let tip_deformed = model
        .tip
        .iter()
        .zip(&tip_reference)
        .map(|(n, p)| {
            displacements
                .get(n)
                .map(|u| p + u)
                .ok_or_else(|| format!("no displacement printed for tip node {n}"))
        })
        .collect::<Result<_, _>>()?;
    Ok(Run {
        tip_reference,
        tip_deformed,
        patch_area: model.patch_area,
        nodes: model.nodes.len(),
        newton_iterations: output.log.matches(" iteration ").count(),
        seconds: output.seconds,
    })
}

/// The last `*NODE PRINT` block of the tip set: its step time and the
/// displacement of each node.
fn last_tip_block(dat: &str) -> Result<(f64, HashMap<usize, Point>), String> {
    const HEADER: &str = "displacements (vx,vy,vz) for set TIP and time";
    let block = dat
        .rsplit(HEADER)
        .next()
        .filter(|_| dat.contains(HEADER))
        .ok_or("tube.dat holds no tip displacements")?;
    let mut lines = block.lines();
    let time: f64 = lines
        .next()
        .and_then(|l| l.trim().parse().ok())
        .ok_or("unreadable step time in tube.dat")?;
    let mut displacements = HashMap::new();
    for line in lines {
        let fields: Vec<&str> = line.split_whitespace().collect();
        if fields.is_empty() {
            continue;
        }
        let parsed: Option<(usize, [f64; 3])> = (|| {
            let n = fields.first()?.parse().ok()?;
            let mut u = [0.0; 3];
            for (k, v) in u.iter_mut().enumerate() {
                *v = fields.get(k + 1)?.parse().ok()?;
            }
            Some((n, u))
        })();
        match parsed {
            Some((n, u)) if fields.len() == 4 => {
                displacements.insert(n, Point::new(u[0], u[1], u[2]));
            }
            _ => break,
        }
    }
    Ok((time, displacements))
}
