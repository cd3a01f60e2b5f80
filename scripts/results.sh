#!/usr/bin/env bash
# Regenerates docs/results.md and docs/results/<scene>/*.svg: every strategy against the static
# mesh on the three source scenes (sphere, round_table, bunny), each against its cached reference.
#
# Settings (override with the environment). The defaults are `adaptcloth compare`'s own: reference
# 65x65, floor 33x33, static 5/9/17/33 and the three adaptive strategies. They take about 1.5 hours
# on a 2-core machine (scripts/results-notes.md lists the costs); a quicker pass is
# REF=33 FLOOR=17 RUNS=static@5,static@9,static@17,remesh,simnett,bisect48 (about 15 minutes).
#   REF=65 FLOOR=33 RUNS=(compare's default list) JOBS=2 OUT=out/results CACHE=out/reference-cache
# To spread the sweep over machines, run `adaptcloth compare SCENE --shard k/n ...` for each k,
# combine the folders with `adaptcloth merge`, then `adaptcloth report ... --write-docs docs`.
set -euo pipefail
cd "$(dirname "$0")/.."
REF=${REF:-65}
FLOOR=${FLOOR:-33}
JOBS=${JOBS:-2}
OUT=${OUT:-out/results}
CACHE=${CACHE:-out/reference-cache}
cargo build --release --quiet
target/release/adaptcloth compare --all-source-scenes ${RUNS:+--runs "$RUNS"} \
  --ref-resolution "$REF" --floor-resolution "$FLOOR" --jobs "$JOBS" --cache "$CACHE" \
  --out "$OUT" --quiet --write-docs docs --docs-notes scripts/results-notes.md
