#!/usr/bin/env bash
# Records the designs of a fixed set of runs (same seeds), to check that a
# restructuring changes no result: run it on two builds and compare the two
# folders with `tools/golden_compare.py A B`.
#   tools/golden.sh OUT_DIR [full]
# The set (about 4 minutes on 2 cores): the quick bench suite's two curves
# under draft, draft without correction, draft without refine and standard;
# the arc under fine, with a polish, and unseeded; the Hilbert curve under
# draft and standard; the pancake under draft; the CLI's checkpoint/resume
# path; and the ten round trips (examples/round_trips).
# GOLDEN_BIN=DIR uses the patchwork and round_trips binaries found there.
set -euo pipefail
out=${1:?usage: tools/golden.sh OUT_DIR}
cd "$(dirname "$0")/.."
mkdir -p "$out/curves" "$out/bin"
if [ -n "${GOLDEN_BIN:-}" ]; then
  # Binaries built earlier (a folder with patchwork and round_trips).
  cp "$GOLDEN_BIN/patchwork" "$GOLDEN_BIN/round_trips" "$out/bin/"
else
  cargo build --release --quiet --bin patchwork --example round_trips -p patchwork -p patchwork-core
  # Copies of the binaries, so the tree can change while the runs go on.
  cp target/release/patchwork target/release/examples/round_trips "$out/bin/"
fi
bin=$out/bin/patchwork
$bin preset helix radius_mm=15 pitch_mm=40 turns=0.6 > "$out/curves/helix.csv"
$bin preset arc radius_mm=40 angle_deg=90 > "$out/curves/arc.csv"
$bin preset reference name=hilbert > "$out/curves/hilbert.csv"
$bin preset reference name=pancake > "$out/curves/pancake.csv"
run() { # name curve args...
  local name=$1 curve=$2; shift 2
  $bin design "$out/curves/$curve.csv" --out "$out/$name" --threads 2 --seed 1 "$@" > "$out/$name.txt"
}
for curve in helix arc; do
  run "$curve-draft" $curve --fidelity draft --budget 60
  run "$curve-draft-uncorrected" $curve --fidelity draft --budget 60 --tuning '{"correction": false}'
  run "$curve-draft-norefine" $curve --fidelity draft --budget 60 --tuning '{"refine_budget": 0}'
  run "$curve-standard" $curve --fidelity standard --budget 60
done
run arc-fine arc --fidelity fine --budget 60
run arc-polish arc --fidelity draft --budget 40 --tuning '{"polish_budget": 24, "uniform_mesh_mm": 3}'
run arc-even arc --fidelity draft --budget 40 --tuning '{"start": "even"}'
run hilbert-draft hilbert --fidelity draft
run hilbert-standard hilbert --fidelity standard
run pancake-draft pancake --fidelity draft
# A run stopped after its checkpoint and resumed gives the same design.
rm -f "$out/resume.ckpt"
run helix-checkpointed helix --fidelity draft --budget 60 --checkpoint "$out/resume.ckpt"
run helix-resumed helix --fidelity draft --budget 60 --checkpoint "$out/resume.ckpt"
"$out/bin/round_trips" out="$out/round-trips" > "$out/round-trips.txt"
