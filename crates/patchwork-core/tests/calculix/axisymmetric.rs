//! The independent side of the 20 kPa cross-check: an axisymmetric CalculiX
//! (`ccx`) model of the closed-end tube, bare or with a patch round its whole
//! circumference (a band), inflated past the limit point onto the branch the
//! paper's balloon ends on.
//!
//! ccx has no arc-length or volume control, and its Newton stalls on the soft
//! branch of the inflation curve (a near-flat p(λ) leaves its tangent nearly
//! singular in the tube's axial mode: the force residual is 1e-6 N while the
//! corrections stay 0.02 mm). So the deck snaps the tube through dynamically
//! and then settles it statically:
//!
//! 1. static, to `START_KPA` — below the limit point (15.7 kPa for the
//!    paper's balloon), where load control works;
//! 2. implicit dynamics (HHT, α = −0.3, whose numerical damping removes the
//!    oscillation) with the pressure ramped to the full load over the first
//!    fifth of the step and held: the tube snaps onto the stiffening branch
//!    and comes to rest there;
//! 3. static at the full load from that rest state, with tight equilibrium
//!    tolerances: the answer is an equilibrium, not a moment of the motion.
//!
//! The wall is 8-node axisymmetric solids (CAX8), one element through the
//! thickness, a hemispherical cap closing the tip; the base is pinned, the
//! pole held on the axis. Materials as in ABAQUS (which ccx follows):
//! Arruda–Boyce with μ, λm and D for the wall, neo-Hookean with C₁₀ and D₁ for
//! the band, each D from its K₀/μ₀. The band keeps the wall's thickness and
//! carries the patch's membrane stiffness μ_p·t_p in μ, as the shell model
//! does (a membrane sees only μ·t: its thickness stretch does not depend on
//! t); its elements are those whose centre lies within the band.

use std::f64::consts::FRAC_PI_2;
use std::fmt::Write as _;
use std::path::Path;

use super::runner::{run_deck, tail};

/// Pressure of the static first step (kPa): below the limit point.
const START_KPA: f64 = 15.5;
/// Length of the dynamic step (s of model time, at a latex-like density):
/// long enough for the snap-through's oscillation to die out.
const DYNAMIC_S: f64 = 0.5;
/// Density (tonne/mm³ in ccx's mm–N–s units): latex's, about 1000 kg/m³.
const DENSITY: f64 = 1e-9;

/// Geometry, materials and load (mm, MPa).
#[derive(Debug, Clone, Copy)]
pub struct Scene {
    pub length: f64,
    pub radius: f64,
    pub wall: f64,
    /// The wall's Arruda–Boyce μ and λm, and its small-strain shear
    /// modulus μ₀ (ABAQUS's: μ times a series in 1/λm²).
    pub wall_mu: f64,
    pub lambda_m: f64,
    pub wall_mu0: f64,
    /// K₀/μ₀ of both materials.
    pub bulk_ratio: f64,
    pub pressure_mpa: f64,
    /// Element size along the wall's mid-surface.
    pub element: f64,
    pub band: Option<Band>,
}

/// A patch round the whole circumference.
#[derive(Debug, Clone, Copy)]
pub struct Band {
    /// Axial position of its middle and its height (mm).
    pub centre: f64,
    pub height: f64,
    /// Neo-Hookean μ_p·t_p (N/mm).
    pub mu_t: f64,
}

/// The settled tube: its mid-surface at every element corner along the
/// tube (the cap left out).
#[derive(Debug)]
pub struct Profile {
    /// (reference axial position, deformed radius, deformed axial position)
    /// per corner node of the tube, base to tip.
    pub points: Vec<(f64, f64, f64)>,
    /// Length of the band in the model (mm): whole elements.
    pub band_height: f64,
    /// Increment attempts of the three steps (cutbacks included).
    pub attempts: usize,
    pub seconds: f64,
}

/// The meridian: reference position of the mid-surface and its outward
/// normal at `i` half-elements from the base.
struct Meridian {
    scene: Scene,
    tube: usize,
    cap: usize,
}

impl Meridian {
    fn new(scene: &Scene) -> Meridian {
        Meridian {
            scene: *scene,
            tube: (scene.length / scene.element).round().max(1.0) as usize,
            cap: (FRAC_PI_2 * scene.radius / scene.element).round().max(4.0) as usize,
        }
    }

    fn elements(&self) -> usize {
        self.tube + self.cap
    }

    /// ((r, z) of the mid-surface, (n_r, n_z)) at half-element `i`.
    fn at(&self, i: usize) -> ((f64, f64), (f64, f64)) {
        let (l, r) = (self.scene.length, self.scene.radius);
        if i <= 2 * self.tube {
            return ((r, l * i as f64 / (2 * self.tube) as f64), (1.0, 0.0));
        }
        let phi = FRAC_PI_2 * (i - 2 * self.tube) as f64 / (2 * self.cap) as f64;
        let (sin, cos) = phi.sin_cos();
        // The pole lies exactly on the axis.
        let radial = if i == 2 * self.elements() { 0.0 } else { cos };
        ((r * radial, l + r * sin), (radial, sin))
    }

    /// The node number of half-element `i`, layer `j` (0 inner, 1 mid, 2 outer).
    fn node(i: usize, j: usize) -> usize {
        3 * i + j + 1
    }
}

fn input_deck(scene: &Scene, meridian: &Meridian) -> (String, f64) {
    let mut deck = String::from("*NODE,NSET=NALL\n");
    for i in 0..=2 * meridian.elements() {
        let ((r, z), (nr, nz)) = meridian.at(i);
        for j in 0..3 {
            let offset = (j as f64 - 1.0) * 0.5 * scene.wall;
            let _ = writeln!(
                deck,
                "{},{:.12e},{:.12e}",
                Meridian::node(i, j),
                r + offset * nr,
                z + offset * nz
            );
        }
    }
    let (mut wall, mut band) = (Vec::new(), Vec::new());
    let dz = scene.length / meridian.tube as f64;
    for e in 0..meridian.elements() {
        let (a, b) = (2 * e, 2 * e + 2);
        let n = Meridian::node;
        // Counter-clockwise in (r, z): inner and outer at a, outer and inner at b.
        let nodes = [
            n(a, 0),
            n(a, 2),
            n(b, 2),
            n(b, 0),
            n(a, 1),
            n(a + 1, 2),
            n(b, 1),
            n(a + 1, 0),
        ];
        let centre = (e as f64 + 0.5) * dz;
        let banded = scene.band.is_some_and(|band| {
            e < meridian.tube && (centre - band.centre).abs() < 0.5 * band.height
        });
        match banded {
            true => band.push((e + 1, nodes)),
            false => wall.push((e + 1, nodes)),
        }
    }
    let band_height = band.len() as f64 * dz;
    for (set, elements) in [("WALL", &wall), ("BAND", &band)] {
        if elements.is_empty() {
            continue;
        }
        let _ = writeln!(deck, "*ELEMENT,TYPE=CAX8,ELSET={set}");
        for (number, nodes) in elements {
            let list: Vec<String> = nodes.iter().map(usize::to_string).collect();
            let _ = writeln!(deck, "{number},{}", list.join(","));
        }
    }
    let pole = 2 * meridian.elements();
    let list = |nodes: Vec<usize>| {
        let items: Vec<String> = nodes.iter().map(usize::to_string).collect();
        items.join("\n")
    };
    let _ = writeln!(
        deck,
        "*NSET,NSET=BASE\n{}\n*NSET,NSET=AXIS\n{}\n*NSET,NSET=MID\n{}",
        list((0..3).map(|j| Meridian::node(0, j)).collect()),
        list((0..3).map(|j| Meridian::node(pole, j)).collect()),
        list(
            (0..=pole)
                .step_by(2)
                .map(|i| Meridian::node(i, 1))
                .collect()
        ),
    );
    let sets = if band.is_empty() {
        "WALL"
    } else {
        "WALL\nBAND"
    };
    let _ = writeln!(deck, "*ELSET,ELSET=EALL\n{sets}");
    deck.push_str(&materials(scene, !band.is_empty()));
    deck.push_str(&steps(scene, !band.is_empty()));
    (deck, band_height)
}

fn materials(scene: &Scene, banded: bool) -> String {
    // D = 2/K₀ with K₀ = bulk_ratio · μ₀.
    let d = |mu0: f64| 2.0 / (scene.bulk_ratio * mu0);
    let mut text = format!(
        "*MATERIAL,NAME=LATEX\n*HYPERELASTIC,ARRUDA-BOYCE\n{:.9e},{:.9e},{:.9e}\n*DENSITY\n{DENSITY:e}\n\
         *SOLID SECTION,ELSET=WALL,MATERIAL=LATEX\n",
        scene.wall_mu,
        scene.lambda_m,
        d(scene.wall_mu0)
    );
    if let (true, Some(band)) = (banded, scene.band) {
        let mu = band.mu_t / scene.wall;
        let _ = write!(
            text,
            "*MATERIAL,NAME=BAND\n*HYPERELASTIC,NEO HOOKE\n{:.9e},{:.9e}\n*DENSITY\n{DENSITY:e}\n\
             *SOLID SECTION,ELSET=BAND,MATERIAL=BAND\n",
            0.5 * mu,
            d(mu)
        );
    }
    text
}

/// The three steps (static to `START_KPA`, dynamic snap-through, static at
/// the full load); the mid-surface printed at the end of the last.
fn steps(scene: &Scene, banded: bool) -> String {
    let faces = if banded {
        "WALL,P4\nBAND,P4"
    } else {
        "WALL,P4"
    };
    let load = |scale: f64| {
        faces
            .lines()
            .map(|f| format!("{f},{:.9e}\n", scale * scene.pressure_mpa))
            .collect::<String>()
    };
    let start = START_KPA * 1e-3 / scene.pressure_mpa;
    let mut text = String::from("*BOUNDARY\nBASE,1,2\nAXIS,1,1\n");
    let _ = writeln!(
        text,
        "*AMPLITUDE,NAME=SNAP\n0.0,{start:.9},{:e},1.0,{:e},1.0",
        0.2 * DYNAMIC_S,
        10.0 * DYNAMIC_S
    );
    // ccx asks for energy output in the first step of a dynamic analysis.
    let _ = write!(
        text,
        "*STEP,NLGEOM,INC=1000\n*STATIC\n0.25,1.0,1e-6,0.25\n*DLOAD\n{}\
         *EL PRINT,ELSET=EALL,TOTALS=ONLY\nENER\n*END STEP\n",
        load(start)
    );
    let _ = write!(
        text,
        "*STEP,NLGEOM,INC=100000\n*DYNAMIC,ALPHA=-0.3\n{:e},{DYNAMIC_S:e},1e-9,{:e}\n\
         *DLOAD,AMPLITUDE=SNAP\n{}*END STEP\n",
        DYNAMIC_S / 400.0,
        DYNAMIC_S / 100.0,
        load(1.0)
    );
    let _ = write!(
        text,
        "*CONTROLS,PARAMETERS=FIELD,FIELD=DISPLACEMENT\n1e-5,1e-4\n\
         *STEP,NLGEOM,INC=1000\n*STATIC\n1.0,1.0,1e-6,1.0\n*DLOAD\n{}\
         *NODE PRINT,NSET=MID\nU\n*END STEP\n",
        load(1.0)
    );
    text
}

/// Writes the deck into `dir`, runs `ccx` there and reads the mid-surface.
pub fn run(dir: &Path, scene: &Scene) -> Result<Profile, String> {
    let meridian = Meridian::new(scene);
    let (deck, band_height) = input_deck(scene, &meridian);
    let output = run_deck(dir, &deck)?;
    let settled = output.dat.contains("displacements (vx,vy,vz) for set MID");
    if !output.clean || !settled {
        return Err(format!(
            "ccx did not settle the tube at the full load; its output ends:\n{}",
            tail(&output.log)
        ));
    }
    let displacements = mid_surface(&output.dat)?;
    let points = (0..=2 * meridian.tube)
        .step_by(2)
        .map(|i| {
            let ((r, z), _) = meridian.at(i);
            let (ur, uz) = displacements.get(&Meridian::node(i, 1)).ok_or_else(|| {
                format!("no displacement printed for node {}", Meridian::node(i, 1))
            })?;
            Ok((z, r + ur, z + uz))
        })
        .collect::<Result<_, String>>()?;
    Ok(Profile {
        points,
        band_height,
        attempts: output.log.matches(" attempt ").count(),
        seconds: output.seconds,
    })
}

/// The displacements (u_r, u_z) of the `MID` set, printed once at the end.
fn mid_surface(dat: &str) -> Result<std::collections::HashMap<usize, (f64, f64)>, String> {
    const HEADER: &str = "displacements (vx,vy,vz) for set MID and time";
    let block = dat
        .rsplit(HEADER)
        .next()
        .ok_or("tube.dat holds no mid-surface")?;
    let mut displacements = std::collections::HashMap::new();
    for line in block.lines().skip(1) {
        let fields: Vec<&str> = line.split_whitespace().collect();
        if fields.is_empty() {
            continue;
        }
        let parsed = (fields.len() == 4)
            .then(|| {
                let n = fields[0].parse().ok()?;
                Some((n, (fields[1].parse().ok()?, fields[2].parse().ok()?)))
            })
            .flatten();
        match parsed {
            Some((n, u)) => displacements.insert(n, u),
            None => break,
        };
    }
    match displacements.is_empty() {
        true => Err("tube.dat's mid-surface block is empty".into()),
        false => Ok(displacements),
    }
}
