//! Text of the benchmark report that is not a table: the header (machine,
//! build, date, command) and the known limits, with the figures of the run
//! where the run shows them.

use std::process::Command;

use super::row::Row;

/// The title, what was run where, and how to read the figures.
pub fn header(command: &str) -> String {
    let date = time::OffsetDateTime::now_utc().date();
    format!(
        "# Benchmarks\n\n\
         How good a design Patchwork makes, and in how long. Written by\n\n\
         ```sh\n{command}\n```\n\n\
         | | |\n|---|---|\n\
         | date | {date} |\n\
         | build | {} ({} profile) |\n\
         | machine | {} |\n\
         | scene | {} |\n\n\
         **Shape error** is the root-mean-square distance between the target \
         and the design's inflated centreline, compared at equal fractions of \
         their length after the best rigid alignment, as a percentage of the \
         target's length; every design is re-simulated on the uniform 0.5 mm \
         reference model to measure it. **Wall time** is one \
         `patchwork design` run on this machine with 2 threads, from the curve \
         to the verified design; the scene's tables, the reach table (21 \
         solves, about 2 s) and the search's rod table (73 solves, about \
         2.5 s), are solved by the first design and read back by the rest, as \
         a user's later designs of a scene read them from disk. Times on a shared \
         machine vary by up to ±30 % from one run to the next, so compare them \
         as ratios within this report.\n",
        build(),
        if cfg!(debug_assertions) {
            "debug"
        } else {
            "release"
        },
        machine(),
        scene()
    )
}

/// The reference scene every curve is designed on: its materials and
/// their compressibility, and the pressure.
fn scene() -> String {
    let d = patchwork_core::design::Design::reference(vec![]);
    let (b, p) = (&d.balloon.material, &d.patch.material);
    format!(
        "the reference balloon ({}, {}) with {} patches ({}) at {} kPa",
        b.model_name(),
        b.compressibility,
        p.model_name(),
        p.compressibility,
        d.pressure_kpa
    )
}

/// The commit this binary was run from, `+changes` when the work tree
/// differs from it.
fn build() -> String {
    let git = |args: &[&str]| {
        Command::new("git")
            .args(args)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    match git(&["rev-parse", "--short", "HEAD"]) {
        Some(commit) => match git(&["status", "--porcelain", "--untracked-files=no"]) {
            Some(changes) if !changes.is_empty() => format!("{commit}+changes"),
            _ => commit,
        },
        None => "unknown commit".into(),
    }
}

/// CPU model, cores and memory, from /proc where it exists.
fn machine() -> String {
    let read = |path| std::fs::read_to_string(path).unwrap_or_default();
    let cpuinfo = read("/proc/cpuinfo");
    let cpu = cpuinfo
        .lines()
        .find_map(|l| l.strip_prefix("model name"))
        .and_then(|l| l.split(':').nth(1))
        .map_or("unknown CPU", str::trim)
        .to_string();
    let cores = patchwork_core::available_cores();
    let memory_gib = read("/proc/meminfo")
        .lines()
        .find_map(|l| l.strip_prefix("MemTotal:"))
        .and_then(|l| l.trim().trim_end_matches("kB").trim().parse::<f64>().ok())
        .map_or(String::new(), |kb| {
            format!(", {:.0} GiB", kb / 1024.0 / 1024.0)
        });
    format!("{cpu}, {cores} cores{memory_gib}")
}

/// The limits of the model and the pipeline, the curves of this run that
/// show them named with their figures.
pub fn known_limits(curves: &[Row]) -> String {
    let out_of_reach: Vec<String> = curves
        .iter()
        .filter(|r| r.setting == "draft" && r.reach != "yes" && r.reach != "–")
        .map(|r| {
            format!(
                "{} ({:.2} %: {})",
                r.curve, r.figures.reference_error_percent, r.reach
            )
        })
        .collect();
    let shown = match out_of_reach.is_empty() {
        true => "No curve of this run is out of reach.".to_string(),
        false => format!("In this run: {}.", out_of_reach.join("; ")),
    };
    format!(
        "## Known limits\n\n\
         - **Bends tighter than the balloon can make.** Before the search, the \
         run compares the target's bends with what one patch within the bounds \
         makes, and reports where the target asks for more (`reach` in \
         design.json). Those designs do their best and miss there. {shown}\n\
         - **Corners are not rounded for you.** A kink is reported out of reach \
         where it is and designed as given; the balloon rounds it.\n\
         - **Noise on sparse points.** Points more than 20 mm apart are read \
         through a cubic spline, noise and all (no noise estimate can tell it \
         from the bends there): set `--smooth-mm` by hand for noisy sparse \
         input.\n\
         - **The layout** is KSA's (trains of patches where a bend is longer \
         than one patch), plus a trial of patches on gentle bends (however \
         gentle, on a curved target; on the part of a bend the refined \
         design's patches leave free) and, while the error stays above 1 % \
         with patches at their smallest, up to three trials each taking one \
         out: the search does not insert, split or merge patches. Round trips \
         match the shape with layouts of their own, not the truth's: most \
         with fewer patches than the truth, some with more.\n\
         - **Planar targets get planar designs** (Θ = 0 on two opposite \
         lines); a little twist sometimes places bends better, which \
         `--tuning '{{\"planar_designs\": false}}'` allows.\n\
         - **Very long curves are slow**: a 1.3 m helix (a 360 mm balloon) \
         takes about 4 minutes with `draft`, KSA's layout and no refine \
         (`cargo test --release -p patchwork-core --test stress -- \
         --ignored --nocapture`, on request).\n\
         - **Coarse meshes are for searching and quick looks**: with patches, \
         the uniform 2 mm mesh lies over a per cent of the length from a \
         converged solution (table above); every preset verifies on 0.5 mm \
         elements.\n"
    )
}
