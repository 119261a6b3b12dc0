use patchwork_core::design::{Design, Patch};
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::{SimulateOptions, simulate};
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let h: f64 = args.get(1).map(|s| s.parse().unwrap()).unwrap_or(2.0);
    let patched = args.get(2).is_some();
    let patches = if patched {
        vec![Patch {
            x_mm: 0.0,
            y_mm: 146.0,
            h_mm: 18.0,
            w_mm: 1.5,
            theta_deg: 0.0,
        }]
    } else {
        vec![]
    };
    let design = Design::reference(patches);
    let opts = SimulateOptions {
        mesh: MeshSpec::uniform(h),
        ..Default::default()
    };
    match simulate(&design, &opts) {
        Ok(s) => {
            println!(
                "tube theory hoop {:.5} axial {:.5}",
                s.tube_state.hoop, s.tube_state.axial
            );
            println!(
                "FE mid hoop {:.5} axial {:.5} len {:.2} iters {} steps {} stable {} resid {:.2e} t {:?} asm {:?} fac {:?} nodes {}",
                s.hoop_stretch_mid,
                s.axial_stretch_mid,
                s.inflated_length_mm,
                s.newton_iterations,
                s.continuation_steps,
                s.stable,
                s.residual,
                s.elapsed,
                s.assembly_time,
                s.factor_time,
                s.positions.len()
            );
            let kmax = s.curvature.iter().cloned().fold(0.0, f64::max);
            let tip = s.centreline.points().last().unwrap();
            println!("kappa max {:.4} tip {:?}", kmax, tip);
        }
        Err(e) => println!("error: {e}"),
    }
}
