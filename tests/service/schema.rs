//! Response bodies checked against openapi.yaml's component schemas.
//!
//! The check is jsonschema_rs (the Rust `jsonschema` crate's Python binding,
//! which `.ci/run` installs with schemathesis) in one Python process per test
//! binary, `validate_schema.py`, fed one value per line: the same validator
//! without compiling the crate into every build of the tests.

use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};
use std::sync::{Mutex, OnceLock};

use serde_json::{Value, json};

/// The validator process and its ends: requests in, answers out.
struct Validator {
    _process: Child,
    input: ChildStdin,
    output: BufReader<ChildStdout>,
}

/// openapi.yaml as JSON.
pub fn spec() -> &'static Value {
    static SPEC: OnceLock<Value> = OnceLock::new();
    SPEC.get_or_init(|| {
        let text =
            std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("openapi.yaml"))
                .unwrap();
        serde_norway::from_str(&text).unwrap()
    })
}

/// Starts `validate_schema.py` and hands it the spec's components. The
/// process ends when the test binary does (its stdin closes).
fn start() -> Validator {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/service/validate_schema.py");
    let mut child = Command::new("python3")
        .arg(script)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("python3 runs (jsonschema_rs comes with schemathesis: .ci/run installs it)");
    let mut input = child.stdin.take().unwrap();
    writeln!(input, "{}", spec()["components"]).unwrap();
    let output = BufReader::new(child.stdout.take().unwrap());
    Validator {
        _process: child,
        input,
        output,
    }
}

/// The errors of `value` against `#/components/schemas/{schema}`.
fn errors(schema: &str, value: &Value) -> Vec<String> {
    static VALIDATOR: OnceLock<Mutex<Validator>> = OnceLock::new();
    let validator = VALIDATOR.get_or_init(|| Mutex::new(start()));
    // A test that failed while holding the lock left the process in step:
    // each request is written and answered whole under it.
    let mut v = validator.lock().unwrap_or_else(|e| e.into_inner());
    let mut line = String::new();
    let asked = writeln!(v.input, "{}", json!({"schema": schema, "value": value}));
    let answered = asked.and_then(|()| v.output.read_line(&mut line));
    serde_json::from_str(&line).unwrap_or_else(|_| {
        panic!(
            "validate_schema.py answered {line:?} ({answered:?}): it needs python3 with \
             jsonschema_rs (`pip install schemathesis`, as .ci/run does)"
        )
    })
}

/// Asserts `value` is valid against `#/components/schemas/{schema}`.
pub fn assert_schema(schema: &str, value: &Value) {
    let errors = errors(schema, value);
    assert!(errors.is_empty(), "{schema}: {errors:?}\n{value}");
}
