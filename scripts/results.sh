#!/usr/bin/env bash
# Regenerates docs/results.md and docs/results/<scene>/*.svg: compares every built strategy with
# the static mesh on the three source scenes (sphere, round_table, bunny) against a cached
# reference. Strategies that are not built are skipped and listed; rerun when they land.
#
# Settings (override with the environment; the defaults finish in about 10-15 minutes on a
# 2-core machine, see scripts/results-notes.md for the costs):
#   REF=33 FLOOR=17 RUNS=static@5,static@9,static@17,remesh,simnett,bisect48 JOBS=2
#   OUT=out/results CACHE=out/reference-cache
# The full default of `adaptcloth compare` (reference 65x65, floor 33x33, static up to 33x33)
# is REF=65 FLOOR=33 RUNS=static@5,static@9,static@17,static@33,remesh,simnett,bisect48.
set -euo pipefail
cd "$(dirname "$0")/.."
REF=${REF:-33}
FLOOR=${FLOOR:-17}
RUNS=${RUNS:-static@5,static@9,static@17,remesh,simnett,bisect48}
JOBS=${JOBS:-2}
OUT=${OUT:-out/results}
CACHE=${CACHE:-out/reference-cache}
cargo build --release --quiet
BIN=target/release/adaptcloth
for scene in sphere round_table bunny; do
  "$BIN" compare "$scene" --runs "$RUNS" --ref-resolution "$REF" --floor-resolution "$FLOOR" \
    --jobs "$JOBS" --cache "$CACHE" --out "$OUT/$scene" --quiet
done
"$BIN" report "$OUT/sphere" "$OUT/round_table" "$OUT/bunny" --write-docs docs \
  --docs-notes scripts/results-notes.md \
  --docs-command "scripts/results.sh (REF=$REF FLOOR=$FLOOR RUNS=$RUNS JOBS=$JOBS)"
