#!/usr/bin/env bash
# Side-by-side timing against the fastest peer measured (the Taichi explicit cloth script), in
# one sitting: `scenes/sphere_peer.toml` (static mesh, implicit Euler at a fixed 1/240 s, 0.6 s)
# with each linear solver (`auto`; CG; sparse Cholesky; CG preconditioned by the springs'
# Cholesky factor, `pcg_springs`, the default; the default thread count),
# against the peer on two threads, at N = 17, 33 and 65. Each figure is the smallest of ROUNDS runs (default 3), the configurations
# interleaved round by round so machine noise falls on all alike. Ours: `wall_time_s` of
# summary.json; the peer: `wall_s` of its JSON line (its stepping loop only).
#
# Needs a release build (`cargo build --release`), python3 with `taichi==1.7.4` and `numpy`
# (`pip install taichi==1.7.4 numpy`; PY names another interpreter) and the peer script (PEER,
# default ../shared/peers/taichi_cloth.py, outside this repository). Prints a markdown table;
# the runs go under OUT (default out/peer).
set -euo pipefail
PEER=${PEER:-../shared/peers/taichi_cloth.py}
PY=${PY:-python3}
OUT=${OUT:-out/peer}
ROUNDS=${ROUNDS:-3}
BIN=target/release/adaptcloth
[ -x "$BIN" ] || { echo "no $BIN: run cargo build --release first" >&2; exit 2; }
[ -f "$PEER" ] || { echo "no peer script at $PEER (set PEER)" >&2; exit 2; }
mkdir -p "$OUT"

# ours N SOLVER -> wall seconds, unconverged steps, status, steps rescued by Cholesky (auto)
ours() {
  local dir="$OUT/ours-$1-$2"
  "$BIN" run sphere_peer --strategy static --integrator implicit_euler \
    --set cloth.resolution="$1" --set 'time.mode="fixed"' --set time.dt=0.0041666666666666667 \
    --set integrator.solver="\"$2\"" --out "$dir" --quiet >/dev/null
  "$PY" -c 'import json,sys; d=json.load(open(sys.argv[1])); print(d["wall_time_s"], d.get("cg_unconverged", 0), d["status"], d.get("cholesky_rescues", 0))' \
    "$dir/summary.json"
}

peer() {
  "$PY" "$PEER" --n "$1" --threads 2 --out "$OUT/taichi-$1" |
    "$PY" -c 'import json,sys; d=json.loads(sys.stdin.readline()); print(d["wall_s"], 0, "stable" if d.get("stable") else "UNSTABLE", 0)'
}

declare -A best note unconverged rescued
configs=(peer auto cg cholesky pcg_springs)
for round in $(seq "$ROUNDS"); do
  for n in 17 33 65; do
    for c in "${configs[@]}"; do
      if [ "$c" = peer ]; then read -r s u st r < <(peer "$n")
      else read -r s u st r < <(ours "$n" "$c"); fi
      key="$n/$c"
      if [ -z "${best[$key]:-}" ] || "$PY" -c "import sys; sys.exit(0 if $s < ${best[$key]} else 1)"; then
        best[$key]=$s
      fi
      note[$key]=$st
      unconverged[$key]=$(( ${unconverged[$key]:-0} > u ? ${unconverged[$key]:-0} : u ))
      rescued[$key]=$(( ${rescued[$key]:-0} > r ? ${rescued[$key]:-0} : r ))
    done
  done
  echo "round $round done" >&2
done

# A figure with a solve stopped at its cap is marked (unconverged steps) and left out of the
# fastest of ours.
echo "| N | Taichi, 2 threads (s) | auto (s) | CG (s) | Cholesky (s) | pcg_springs (s) | Taichi's time over our fastest converged |"
echo "|---:|---:|---:|---:|---:|---:|---:|"
for n in 17 33 65; do
  row="| $n"
  fastest=""
  for c in "${configs[@]}"; do
    cell=${best[$n/$c]}
    u=${unconverged[$n/$c]}
    [ "$u" -gt 0 ] && cell="$cell ($u unconverged)"
    [ "${rescued[$n/$c]}" -gt 0 ] && cell="$cell (${rescued[$n/$c]} rescued)"
    [ "${note[$n/$c]}" = completed ] || [ "${note[$n/$c]}" = stable ] || cell="$cell (${note[$n/$c]})"
    row="$row | $cell"
    if [ "$c" != peer ] && [ "$u" -eq 0 ] && [ "${note[$n/$c]}" = completed ]; then
      fastest=$(printf '%s\n' ${fastest:+"$fastest"} "${best[$n/$c]}" | sort -g | head -1)
    fi
  done
  ratio=$("$PY" -c "print(f'{${best[$n/peer]} / ${fastest:-nan}:.2f}x')")
  echo "$row | $ratio |"
done
