//! Helpers shared by the black-box test crates.

pub mod cli;

use std::process::Command;

/// What ezdxf (the independent reader; `.ci/run` installs it) reads in a
/// DXF file.
#[allow(dead_code)] // not every test crate writes DXF
#[derive(Debug)]
pub struct DxfRead {
    /// The audit's error count (a well-formed file has none).
    pub errors: usize,
    /// The DXF version, e.g. "AC1009" (R12).
    pub version: String,
    /// The $INSUNITS header value (4: millimetres).
    pub units: i64,
    /// Every closed polyline's bounding box: width (x) and height (y), mm,
    /// in the file's order.
    pub closed_outlines: Vec<[f64; 2]>,
    /// Every TEXT's string, in the file's order.
    pub texts: Vec<String>,
}

const READ_DXF: &str = r#"
import sys, json, ezdxf
from ezdxf import bbox
doc = ezdxf.readfile(sys.argv[1])
errors = len(doc.audit().errors)
msp = doc.modelspace()
outlines = []
for e in msp.query("POLYLINE LWPOLYLINE"):
    if e.is_closed:
        size = bbox.extents([e]).size
        outlines.append([size.x, size.y])
print(json.dumps({"errors": errors, "version": doc.dxfversion,
    "units": doc.header.get("$INSUNITS", 0), "outlines": outlines,
    "texts": [t.dxf.text for t in msp.query("TEXT")]}))
"#;

/// Reads and audits a DXF file with ezdxf.
#[allow(dead_code)] // not every test crate writes DXF
pub fn ezdxf_read(path: &std::path::Path) -> DxfRead {
    let output = Command::new("python3")
        .args(["-c", READ_DXF])
        .arg(path)
        .output()
        .expect("python3 runs");
    assert!(
        output.status.success(),
        "ezdxf failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&output.stdout).expect("ezdxf's JSON");
    let outline = |o: &serde_json::Value| [o[0].as_f64().unwrap(), o[1].as_f64().unwrap()];
    DxfRead {
        errors: v["errors"].as_u64().expect("a count") as usize,
        version: v["version"].as_str().unwrap().to_string(),
        units: v["units"].as_i64().unwrap(),
        closed_outlines: v["outlines"]
            .as_array()
            .unwrap()
            .iter()
            .map(outline)
            .collect(),
        texts: v["texts"]
            .as_array()
            .unwrap()
            .iter()
            .map(|t| t.as_str().unwrap().to_string())
            .collect(),
    }
}

/// ezdxf must read and audit a DXF with zero errors: returns the audit's
/// error count.
#[allow(dead_code)] // not every test crate writes DXF
pub fn ezdxf_errors(path: &std::path::Path) -> usize {
    ezdxf_read(path).errors
}
