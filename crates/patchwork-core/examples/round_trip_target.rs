//! Writes one of the bench's round trips as a curve: design N of the ten
//! seeded random designs (`round_trip_designs(10, 2027)`, as `patchwork
//! bench --suite round-trips` draws them) simulated on draft's finest model
//! (its correction's), its centreline as `x,y,z` CSV on stdout and the
//! design itself as JSON on stderr — to design the trip from the command
//! line and read its summary:
//!
//! `cargo run --release -p patchwork-core --example round_trip_target -- 8 > trip8.csv`
//! then `patchwork design trip8.csv --fidelity draft --out trip8`.

use patchwork_core::design::random::round_trip_designs;
use patchwork_core::fe::simulate;
use patchwork_core::inverse::{Fidelity, Plan, TuningOverrides, UserSettings};

fn main() {
    let trip: usize = match std::env::args().nth(1).map(|a| a.parse()) {
        Some(Ok(n @ 1..=10)) => n,
        _ => {
            eprintln!("usage: round_trip_target N (a trip from 1 to 10)");
            std::process::exit(2);
        }
    };
    let settings = UserSettings {
        fidelity: Fidelity::Draft,
        ..UserSettings::default()
    };
    let draft = Plan::resolve(settings, &TuningOverrides::default()).expect("the draft preset");
    let tuning = draft.tuning();
    let model = tuning.model(tuning.correction_mesh.unwrap_or(tuning.verify_mesh));
    let truth = &round_trip_designs(10, 2027)[trip - 1];
    let centreline = simulate(truth, &model)
        .expect("a round trip inflates")
        .centreline;
    println!("x,y,z");
    for p in centreline.points() {
        println!("{},{},{}", p.x, p.y, p.z);
    }
    eprintln!(
        "{}",
        serde_json::to_string(truth).expect("a design serialises")
    );
}
