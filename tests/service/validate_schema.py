"""Validates JSON values against openapi.yaml's component schemas for the
service tests (tests/service/schema.rs), with jsonschema_rs: the Rust
`jsonschema` crate's Python binding, installed with schemathesis.

stdin: first line the spec's `components` object; then one request per
line, {"schema": NAME, "value": VALUE}. stdout: one line per request, the
list of errors ("MESSAGE at /instance/path"), empty when the value is valid.
"""

import json
import sys

import jsonschema_rs


def main():
    components = json.loads(sys.stdin.readline())
    validators = {}
    for line in sys.stdin:
        request = json.loads(line)
        name = request["schema"]
        if name not in validators:
            validators[name] = jsonschema_rs.validator_for(
                {
                    "$schema": "https://json-schema.org/draft/2020-12/schema",
                    "$ref": f"#/components/schemas/{name}",
                    "components": components,
                }
            )
        errors = [
            f"{e.message} at /{'/'.join(str(p) for p in e.instance_path)}"
            for e in validators[name].iter_errors(request["value"])
        ]
        print(json.dumps(errors), flush=True)


if __name__ == "__main__":
    main()
