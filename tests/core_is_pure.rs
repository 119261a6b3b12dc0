//! The numerical core must not depend on async, web or database crates, so that
//! it stays usable from the CLI, the service, benchmarks and other programs alike.

use std::process::Command;

#[test]
fn core_has_no_async_web_or_database_dependency() {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let output = Command::new(cargo)
        .args([
            "tree",
            "-p",
            "patchwork-core",
            "-e",
            "normal",
            "--prefix",
            "none",
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("cargo tree runs");
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let tree = String::from_utf8(output.stdout).unwrap();
    assert!(
        tree.contains("nalgebra"),
        "cargo tree output looks wrong:\n{tree}"
    );
    let forbidden = [
        "tokio",
        "axum",
        "hyper",
        "sqlx",
        "tower",
        "reqwest",
        "async-std",
        "rusqlite",
    ];
    for line in tree.lines() {
        let name = line.split_whitespace().next().unwrap_or("");
        assert!(
            !forbidden.contains(&name),
            "patchwork-core depends on {name}"
        );
    }
}
