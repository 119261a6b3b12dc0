//! Helpers shared by the black-box test crates.

pub mod cli;

use std::process::Command;

/// ezdxf (the independent reader; `.ci/run` installs it) must read and audit a
/// DXF with zero errors. It repairs the table-head handles the `dxf` crate
/// writes, which are fixes, not errors. Returns the audit's error count.
#[allow(dead_code)] // not every test crate writes DXF
pub fn ezdxf_errors(path: &std::path::Path) -> usize {
    let script =
        "import sys, ezdxf\ndoc = ezdxf.readfile(sys.argv[1])\nprint(len(doc.audit().errors))";
    let output = Command::new("python3")
        .args(["-c", script])
        .arg(path)
        .output()
        .expect("python3 runs");
    assert!(
        output.status.success(),
        "ezdxf failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8_lossy(&output.stdout)
        .trim()
        .parse()
        .expect("a count")
}
