#!/usr/bin/env bash
# The hostile-input sweep (issue 15): runs the release binary over about 530 malformed or extreme
# inputs and classifies what each one does. Usage, from the repository root:
#
#   cargo build --release
#   tests/hostile/sweep.sh                 # all cases; writes docs/hostile.md (a few minutes)
#   SWEEP_ONLY='render|mesh' tests/hostile/sweep.sh   # only cases whose name matches (no doc)
#
# Each case runs in a fresh temporary working directory (WORK/cNNN/d1/d2/cwd, so a `../..` escape
# stays inside the case's folder where it can be seen), with a sentinel folder beside it, under
# `timeout -s INT` (SWEEP_TIMEOUT seconds, default 30; KILL 10 s after an ignored interrupt) and a
# memory cap (`ulimit -v`, SWEEP_MEM_KB, default 4 GiB). Run as root, the cases run as `nobody`
# (setpriv), so a defect cannot replace a device such as /dev/full. Outcome classes:
#
#   exit 0 | exit 1 (message) | exit 2 (message) | exit 1/2 without a message | other exit code |
#   panic (stderr says "panicked") | abort (killed by a signal: allocation failure, SIGSEGV) |
#   timeout (answered the interrupt; accepted only for a case marked `long`: a legitimate long
#   run that was correctly accepted) | hang (ignored the interrupt, killed) |
#   escaped (a file appeared or changed anywhere but under the case's `out/` or `o*` paths in its
#   working directory: the case folder, the sentinel, the shared inputs, /tmp/x*, /tmp/escaped*,
#   HOME; or /dev/full stopped being a character device)
#
# Every case's command, outcome and first line of stderr go to WORK/cases.tsv; the full run writes
# the summary to docs/hostile.md (SWEEP_DOC). Exit status 1 when a case is a defect.
set -u
REPO=$(cd "$(dirname "$0")/../.." && pwd)
BIN=${ADAPTCLOTH_BIN:-$REPO/target/release/adaptcloth}
TIMEOUT=${SWEEP_TIMEOUT:-30}
MEM_KB=${SWEEP_MEM_KB:-4194304}
DOC=${SWEEP_DOC:-$REPO/docs/hostile.md}
ONLY=${SWEEP_ONLY:-}
[ -x "$BIN" ] || { echo "no binary at $BIN: cargo build --release" >&2; exit 2; }
WORK=$(mktemp -d /tmp/adaptcloth-hostile.XXXXXX)
chmod 755 "$WORK"
IN=$WORK/inputs
mkdir -p "$IN" "$WORK/logs"
AS=()
if [ "$(id -u)" = 0 ] && command -v setpriv >/dev/null; then
    AS=(setpriv --reuid=65534 --regid=65534 --clear-groups --)
fi
START=$(date +%s)
N=0
printf 'n\tname\tclass\trc\tsecs\tcommand\tmessage\n' >"$WORK/cases.tsv"

# ---------------------------------------------------------------------------------------------
# Inputs (shared, read-only for the cases)
put() { cat >"$IN/$1"; }
base='name = "b"
[time]
duration = 0.01
'
# obst NAME OBSTACLE-LINES [MOTION-LINES]: a scene with one obstacle (and its motion).
obst() {
    { printf '%s\n[[obstacles]]\n%s\n' "$base" "$2"
      [ -n "${3:-}" ] && printf '[obstacles.motion]\n%s\n' "$3"; } >"$IN/$1.toml"
}
SPH='kind = "sphere"
center = [0.0, 0.0, 0.0]
radius = 0.25'
obst box "kind = \"box\"
center = [0.0, 0.0, 0.0]
half_extents = [0.2, 0.2, 0.2]"
obst cyl "kind = \"cylinder\"
center = [0.0, 0.0, 0.0]
radius = 0.3
height = 0.2"
obst ground 'kind = "ground"
height = 0.0'
obst lin "$SPH" 'kind = "linear"
velocity = [0.0, 1.0, 0.0]'
obst spin "$SPH" 'kind = "spin"
axis = [0.0, 0.0, 1.0]
axis_point = [0.0, 0.0, 0.0]
angular_velocity = 3.0'
obst kf "$SPH" 'kind = "keyframes"
times = [0.0, 1.0]
positions = [[0.0, 0.0, 0.0], [0.0, 0.0, 0.5]]
rotations = [[0.0, 0.0, 0.0], [0.0, 0.0, 3.0]]
pivot = [0.0, 0.0, 0.0]'
obst ground_moving 'kind = "ground"' 'kind = "linear"
velocity = [0.0, 0.0, 1.0]'
cp "$REPO/scenes/meshes/bunny.obj" "$IN/bunny.obj"
mesh_scene() { obst "$1" "kind = \"mesh\"
file = \"$2\"
scale = 1.0
translation = [0.0, 0.0, 0.0]"; }
mesh_scene mesh bunny.obj
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n' >"$IN/tet.obj"
printf 'v 0 0 0\nv nan 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n' >"$IN/nan.obj"
printf 'v 0 0 0\nv inf 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n' >"$IN/inf.obj"
printf 'v 0 0 0\nv 1e308 0 0\nv 0 1e308 0\nv 0 0 1e308\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n' >"$IN/huge.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n' >"$IN/range.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n' >"$IN/zero.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -9\n' >"$IN/neg.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 18446744073709551616\n' >"$IN/bigidx.obj"
printf 'v 0 0 0\nv 1 0 0\nf 1 2\n' >"$IN/twovert.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 1 1\n' >"$IN/degen.obj"
printf 'f 1 2 3\n' >"$IN/nov.obj"
printf 'v 0 0\nf 1 1 1\n' >"$IN/short.obj"
printf 'v 1 2 3\n' >"$IN/noface.obj"
: >"$IN/empty.obj"
head -c 4096 /dev/urandom >"$IN/garbage.obj"
printf 'v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n' >"$IN/flat.obj"
mkdir -p "$IN/dir.obj" "$IN/dir.toml"
for m in tet nan inf huge range zero neg bigidx twovert degen nov short noface empty garbage flat; do
    mesh_scene "mesh_$m" "$m.obj"
done
mesh_scene mesh_dir dir.obj
mesh_scene mesh_missing gone.obj
mesh_scene mesh_dev /dev/zero
mesh_scene mesh_abs /etc/passwd
mesh_scene mesh_up ../../../../../../etc/hostname
printf 'v 0 0 0\nv 1e300 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n' >"$IN/far.obj"
for m in tet nan range empty garbage far; do
    printf '%s[cloth]\nshape = "obj"\nmesh = "%s.obj"\n' "$base" "$m" >"$IN/cloth_$m.toml"
done
printf '%s[cloth]\nshape = "obj"\nmesh = "/dev/zero"\n' "$base" >"$IN/cloth_dev.toml"
printf '%s[cloth]\nshape = "disk"\nresolution = 1000000000\n' "$base" >"$IN/disk_huge.toml"
printf '%s[cloth]\nshape = "disk"\nresolution = 2\n' "$base" >"$IN/disk_2.toml"
printf '%s' "$base" >"$IN/base.toml"
: >"$IN/empty.toml"
printf '\n\n# only a comment\n' >"$IN/comment.toml"
head -c 65536 /dev/urandom >"$IN/garbage.toml"
printf 'name = "b\xff\xfe"\n' >"$IN/utf8.toml"
printf 'name = "b\n' >"$IN/unterminated.toml"
printf '%s[cloth]\nresolution = 5\nresolution = 6\n' "$base" >"$IN/dup.toml"
printf '%s[cloth]\nresolution = "five"\n' "$base" >"$IN/type_res.toml"
printf '%s[cloth]\nsize = "big"\n' "$base" >"$IN/type_size.toml"
printf 'obstacles = 5\n%s' "$base" >"$IN/type_obst.toml"
printf '%s[[obstacles]]\nkind = "teapot"\n' "$base" >"$IN/kind.toml"
printf '%s[[obstacles]]\nkind = "sphere"\n' "$base" >"$IN/sphere_nofields.toml"
printf '%s[cloth]\nbogus = 1\n[bogus_section]\nx = 1\n' "$base" >"$IN/unknown.toml"
printf '%s[adaptivity]\nstrategy = "remesh"\nwat = 3\n' "$base" >"$IN/unknown_adapt.toml"
python3 - "$IN" <<'EOF'
import sys, os
d = sys.argv[1]
base = 'name = "b"\n[time]\nduration = 0.01\n'
open(os.path.join(d, "deep_array.toml"), "w").write(base + "[cloth]\nsize = " + "[" * 100000 + "]" * 100000 + "\n")
open(os.path.join(d, "deep_table.toml"), "w").write("x = " + "{ a = " * 50000 + "1" + " }" * 50000 + "\n" + base)
open(os.path.join(d, "deep_dotted.toml"), "w").write(base + "[" + ".".join(["a"] * 50000) + "]\n")
open(os.path.join(d, "huge_keys.toml"), "w").write(base + "".join(f"[x{i}]\ny = {i}\n" for i in range(300000)))
open(os.path.join(d, "long_line.toml"), "w").write('description = "' + "x" * 20_000_000 + '"\n' + base)
sph = '[[obstacles]]\nkind = "sphere"\ncenter = [0.0, 0.0, 0.0]\nradius = 0.25\n'
open(os.path.join(d, "many_obstacles.toml"), "w").write(base + sph * 100000)
open(os.path.join(d, "many_tracked.toml"), "w").write(base + '[[tracked]]\nname = "p"\nrest = [0.5, 0.5]\n' * 100000)
open(os.path.join(d, "many_pinned.toml"), "w").write(base + "[cloth]\npinned = [" + ", ".join(["[0.5, 0.5]"] * 100000) + "]\n")
open(os.path.join(d, "name_long.toml"), "w").write('name = "' + "n" * 100000 + '"\n[time]\nduration = 0.01\n')
open(os.path.join(d, "name_nul.toml"), "w").write('name = "a\\u0000b"\n[time]\nduration = 0.01\n')
EOF
for nm in '/tmp/x' '../../escaped' '..' '.' '' 'a/b/../../../c' '~root' 'con:' '/dev/full' '\\\\host\\share'; do
    safe=$(printf '%s' "$nm" | tr -c 'a-z0-9' '_')
    printf 'name = "%s"\n[time]\nduration = 0.01\n' "$nm" >"$IN/name_$safe.toml"
done
mkfifo "$IN/fifo.toml"
# Study files
study() { cat >"$IN/$1.toml"; }
REF='[reference]
resolution = 5
floor = 3
samples = 8'
study st_ok <<EOF
scenes = ["sphere"]
duration = 0.01
$REF
[[runs]]
strategy = "static"
sweep = { "cloth.resolution" = [3, 5] }
EOF
study st_unknown <<EOF
scenes = ["sphere"]
bogus = 1
$REF
[[runs]]
strategy = "static"
wat = 2
EOF
study st_badkey <<EOF
scenes = ["sphere"]
$REF
[[runs]]
strategy = "static"
set = { "cloth.nokey" = 1 }
EOF
study st_nan <<EOF
scenes = ["sphere"]
duration = nan
$REF
[[runs]]
strategy = "static"
dt = nan
EOF
study st_beta <<EOF
scenes = ["sphere"]
$REF
[[runs]]
strategy = "static"
beta = inf
EOF
study st_sweep_type <<EOF
scenes = ["sphere"]
$REF
[[runs]]
strategy = "static"
sweep = { "cloth.resolution" = "many" }
EOF
study st_sweep_empty <<EOF
scenes = ["sphere"]
$REF
[[runs]]
strategy = "static"
sweep = { "cloth.resolution" = [] }
EOF
study st_norun <<EOF
scenes = ["sphere"]
$REF
EOF
study st_noscene <<EOF
scenes = []
$REF
[[runs]]
strategy = "static"
EOF
study st_dev <<EOF
scenes = ["/dev/zero"]
$REF
[[runs]]
strategy = "static"
EOF
study st_scene_dir <<EOF
scenes = ["dir.toml"]
$REF
[[runs]]
strategy = "static"
EOF
study st_fifo <<EOF
scenes = ["fifo.toml"]
$REF
[[runs]]
strategy = "static"
EOF
for nm in '/tmp/x' '../../escaped'; do
    safe=$(printf '%s' "$nm" | tr -c 'a-z0-9' '_')
    study "st_name_$safe" <<EOF
name = "$nm"
scenes = ["sphere"]
duration = 0.01
$REF
[[runs]]
strategy = "static"
EOF
    study "st_label_$safe" <<EOF
scenes = ["sphere"]
duration = 0.01
$REF
[[runs]]
strategy = "static"
label = "$nm"
EOF
    study "st_scene_$safe" <<EOF
scenes = ["name_$safe.toml"]
duration = 0.01
$REF
[[runs]]
strategy = "static"
EOF
done
study st_duplabel <<EOF
scenes = ["sphere"]
$REF
[[runs]]
strategy = "static"
label = "a"
[[runs]]
strategy = "static"
label = "a"
EOF
python3 - "$IN" <<'EOF'
import sys, os
d = sys.argv[1]
ref = '[reference]\nresolution = 5\nfloor = 3\nsamples = 8\n'
head = 'scenes = ["sphere"]\nduration = 0.01\n' + ref
w = lambda n, t: open(os.path.join(d, n + ".toml"), "w").write(t)
vals = ", ".join(str(0.01 + i * 1e-6) for i in range(1_000_000))
w("st_sweep_million", head + '[[runs]]\nstrategy = "bisect48"\nsweep = { "adaptivity.h_min" = [' + vals + '] }\n')
h = ", ".join(str(0.01 + i * 1e-4) for i in range(1000))
w("st_sweep_product", head + '[[runs]]\nstrategy = "bisect48"\nsweep = { "adaptivity.h_min" = [' + h + '], "adaptivity.l_max" = [' + h + '], "adaptivity.c2" = [' + h + '] }\n')
w("st_many_runs", head + '[[runs]]\nstrategy = "static"\n' * 20000)
w("st_many_scenes", 'scenes = [' + ", ".join(['"sphere"'] * 20000) + ']\n' + ref + '[[runs]]\nstrategy = "static"\n')
w("st_ref_huge", 'scenes = ["sphere"]\n[reference]\nresolution = 1000000000\nfloor = 3\n[[runs]]\nstrategy = "static"\n')
w("st_ref_zero", 'scenes = ["sphere"]\n[reference]\nresolution = 0\nfloor = 0\nsamples = 0\n[[runs]]\nstrategy = "static"\n')
w("st_ref_floor", 'scenes = ["sphere"]\n[reference]\nresolution = 5\nfloor = 9\nsamples = 8\n[[runs]]\nstrategy = "static"\n')
w("st_ref_samples", 'scenes = ["sphere"]\n[reference]\nresolution = 5\nfloor = 3\nsamples = 1000000000\n[[runs]]\nstrategy = "static"\n')
w("st_run_res", head + '[[runs]]\nstrategy = "remesh"\nresolution = 0\n')
w("st_run_res_huge", head + '[[runs]]\nstrategy = "remesh"\nresolution = 100000\n')
w("st_strategy", head + '[[runs]]\nstrategy = "magic"\n')
w("st_integrator", head + '[[runs]]\nstrategy = "static"\nintegrator = "leapfrog"\n')
w("st_set_nan", head + '[[runs]]\nstrategy = "static"\nset = { "material.E" = nan }\n')
w("st_set_E", head + '[[runs]]\nstrategy = "static"\nset = { "material.E" = 1e308 }\n')
w("st_top_set", 'scenes = ["sphere"]\nset = { "time.frame_rate" = 1e9 }\n' + ref + '[[runs]]\nstrategy = "static"\n')
w("st_sweep_names", head + '[[runs]]\nstrategy = "static"\nresolution = 3\nsweep = { "name" = ["../../escaped", "/tmp/x", ".."] }\n')
w("st_dt_tiny", head + '[[runs]]\nstrategy = "static"\ndt = 1e-300\n')
EOF
# A comparison folder for `report` and `merge`, and a corrupted copy.
( cd "$WORK" && mkdir -p seed && cd seed && timeout 120 "$BIN" compare --quiet --duration 0.01 \
    --ref-resolution 5 --floor-resolution 3 --samples 8 --runs static@3,static@5 --out cmp \
    >/dev/null 2>&1 ) || echo "warning: the seed comparison failed" >&2
cp -r "$WORK/seed/cmp" "$IN/cmp"
cp -r "$WORK/seed/cmp" "$IN/cmp_csv"
head -c 300 /dev/urandom >"$IN/cmp_csv/comparison.csv"
cp -r "$WORK/seed/cmp" "$IN/cmp_json"
printf '{"not": "a manifest"' >"$IN/cmp_json/comparison.json"
cp -r "$WORK/seed/cmp" "$IN/cmp_nan"
sed -i '2s/,[0-9.e-]*,/,nan,/3' "$IN/cmp_nan/comparison.csv"
mkdir -p "$IN/emptydir"
FRAME=$IN/cmp/runs/static-3-rk4/frames/frame_00000.obj
chmod -R a+rX "$IN"

# ---------------------------------------------------------------------------------------------
# Running and classifying
snap() { # paths, sizes and times of everything under the arguments (folders without times)
    find "$@" \( -type d -printf '%p\td\n' \) -o -printf '%p\t%y\t%s\t%T@\n' 2>/dev/null | sort
}
tmp_snap() { ls -ld --time-style=full-iso /tmp/x* /tmp/escaped* 2>/dev/null; stat -c '%n %F' /dev/full; }
# c NAME [long] [setup=SHELL] [rootsetup=SHELL, after the chown] [allow=REGEX] -- ARGS...   (@IN@: inputs, @FRAME@: an OBJ frame)
c() {
    local name=$1 long=0 setup='' rootsetup=':' allow='' a
    shift
    while [ "$1" != -- ]; do
        case $1 in
            long) long=1 ;;
            setup=*) setup=${1#setup=} ;;
            rootsetup=*) rootsetup=${1#rootsetup=} ;;
            allow=*) allow=${1#allow=} ;;
        esac
        shift
    done
    shift
    N=$((N + 1))
    if [ -n "$ONLY" ] && ! [[ $name =~ $ONLY ]]; then return; fi
    local R=$WORK/c$(printf %03d $N)
    local CWD=$R/d1/d2/cwd
    mkdir -p "$CWD" "$R/sentinel" "$R/home"
    echo keep >"$R/sentinel/keep"
    local args=()
    for a in "$@"; do a=${a//@IN@/$IN}; a=${a//@FRAME@/$FRAME}; args+=("${a//@CWD@/$CWD}"); done
    (cd "$CWD" && eval "$setup")
    [ ${#AS[@]} -gt 0 ] && chown -R 65534:65534 "$R"
    (cd "$CWD" && eval "$rootsetup")
    local before tbefore
    before=$(snap "$R" "$IN")
    tbefore=$(tmp_snap)
    local t0 t1 rc
    t0=$(date +%s.%N)
    (cd "$CWD" && ulimit -v "$MEM_KB" && HOME=$R/home exec "${AS[@]}" timeout -s INT -k 10 \
        "$TIMEOUT" "$BIN" "${args[@]}") >"$WORK/logs/$N.out" 2>"$WORK/logs/$N.err" </dev/null
    rc=$?
    t1=$(date +%s.%N)
    local after new
    after=$(snap "$R" "$IN")
    new=$(comm -13 <(echo "$before") <(echo "$after") | cut -f1 |
        grep -v -E "^$CWD/(out|o)([./]|\$)${allow:+|$allow}" || true)
    [ "$(tmp_snap)" != "$tbefore" ] && new+=$'\n'"$(diff <(echo "$tbefore") <(tmp_snap) | tr '\n' ' ')"
    local err msg class
    err=$WORK/logs/$N.err
    msg=$(grep -v -E '^\s*$' "$err" | grep -v '^adaptcloth: .* -> ' | head -1 | cut -c1-200)
    if grep -q panicked "$err"; then class=panic
    elif [ $rc = 124 ]; then if [ $long = 1 ]; then class='timeout (long run, accepted)'; else class=timeout; fi
    elif [ $rc = 137 ]; then class='hang (interrupt ignored, killed)'
    elif [ $rc -gt 128 ]; then class="abort (signal $((rc - 128)))"
    elif [ $rc = 0 ]; then class='exit 0'
    elif [ $rc = 1 ] || [ $rc = 2 ]; then
        if [ -n "$msg" ]; then class="exit $rc (message)"; else class="exit $rc without a message"; fi
    else class="exit $rc"
    fi
    if [ -n "$(echo "$new" | tr -d '[:space:]')" ]; then
        class=escaped
        msg="wrote: $(echo "$new" | sed "s|$WORK|WORK|g" | tr '\n' ' ' | cut -c1-300)"
    fi
    [ "$(stat -c %F /dev/full)" = "character special file" ] ||
        { class=escaped; msg="/dev/full replaced"; rm -f /dev/full; mknod -m 666 /dev/full c 1 7; }
    local cmd
    cmd="adaptcloth $(printf '%q ' "${args[@]}" | sed "s|$IN|IN|g; s|$CWD|CWD|g" | cut -c1-300)"
    printf '%s\t%s\t%s\t%s\t%.1f\t%s\t%s\n' "$N" "$name" "$class" "$rc" "$(echo "$t1 - $t0" | bc)" \
        "$cmd" "${msg//$'\t'/ }" >>"$WORK/cases.tsv"
    printf '%3d %-34s %-30s %s\n' "$N" "$name" "$class" "${msg:0:110}"
    rm -rf "$R"
}
D=(--duration 0.01 --quiet)

# shellcheck source=tests/hostile/cases.sh
. "$(dirname "$0")/cases.sh"

# ---------------------------------------------------------------------------------------------
# Summary
END=$(date +%s)
SECS=$((END - START))
T=$WORK/cases.tsv
defect_re='^(panic|timeout$|hang|abort|escaped|exit [0-9]+ without|exit [^012])'
echo
echo "sweep: $((N)) cases defined, $(($(wc -l <"$T") - 1)) run, ${SECS} s; log $T"
cut -f3 "$T" | tail -n +2 | sed 's/ (signal.*//' | sort | uniq -c | sort -rn
DEFECTS=$(tail -n +2 "$T" | awk -F'\t' -v re="$defect_re" '$3 ~ re' | wc -l)
if [ -z "$ONLY" ]; then
    {
        echo "# The hostile-input sweep"
        echo
        echo "Generated by \`tests/hostile/sweep.sh\` (issue 15) on $(date -u '+%Y-%m-%d %H:%M UTC'),"
        echo "commit \`$(git -C "$REPO" rev-parse --short HEAD)\`$(git -C "$REPO" diff --quiet HEAD -- src strategies 2>/dev/null || echo ' with uncommitted source changes'),"
        echo "release binary, $(($(wc -l <"$T") - 1)) cases in ${SECS} s on $(nproc) cores; do not edit by hand:"
        echo "rerun the script. Each case runs in a fresh temporary working directory under"
        echo "\`timeout -s INT $TIMEOUT\` (KILL 10 s later) and \`ulimit -v $MEM_KB\` (KiB)$([ ${#AS[@]} -gt 0 ] && echo ', as user nobody')."
        echo "The script's header says how outcomes are classified; a timeout is acceptable only for"
        echo "a case marked as a legitimately long run (it must answer the interrupt)."
        echo
        echo "| outcome | cases |"
        echo "|---|---|"
        cut -f3 "$T" | tail -n +2 | sort | uniq -c | sort -rn | awk '{n=$1; $1=""; sub(/^ /,""); printf "| %s | %d |\n", $0, n}'
        echo
        echo "## Defects (panic, abort, hang, timeout outside a long run, escape, exit without a message)"
        echo
        if [ "$DEFECTS" = 0 ]; then echo "None."; else
            echo "| # | case | outcome | command | stderr / what was written |"
            echo "|---|---|---|---|---|"
            tail -n +2 "$T" | awk -F'\t' -v re="$defect_re" '$3 ~ re {gsub(/\|/, "\\|"); printf "| %s | %s | %s | `%s` | %s |\n", $1, $2, $3, $6, $7}'
        fi
        echo
        echo "## Accepted timeouts: legitimate long runs, accepted and interrupted cleanly"
        echo
        tail -n +2 "$T" | awk -F'\t' '$3 ~ /accepted/ {printf "- %s `%s`: a valid run longer than the timeout; it answered SIGINT\n", $2, $6} END {if (!NR) print ""}'
        grep -q accepted "$T" || echo "None."
        echo
        echo "## Found by the first runs of this script, and fixed"
        echo
        echo "Each with a test that fails without its fix (commits on branch \`hostile\`):"
        echo
        echo "- panic: a box of half extent 1e308 (parry's EPA index out of bounds); obstacle radius,"
        echo "  height and half extents are now lengths in (0, 1e6] m (tests/core/cli.rs)."
        echo "- hang, SIGINT ignored: a FIFO at \`OUT/metrics.csv.partial\` (or an atomic write's"
        echo "  \`NAME.tmp\`) was opened and waited on for ever; a FIFO \`comparison.csv\` or"
        echo "  \`comparison.json\` was read for ever by \`report\`/\`merge\`. Now refused (io, study::table)."
        echo "- escape: a study run \`label = \"/tmp/x\"\` wrote \`/tmp/x-5-rk4\`; a label read from a"
        echo "  hand-written comparison table could leave \`runs/\`; a study \`name = \"../../../../x\"\`"
        echo "  wrote beside the working folder (\`out/study-../../../../x\`). Labels and names are now"
        echo "  plain folder names (tests/core/cli.rs, study::table)."
        echo "- misleading messages: a file in place of \`OUT/frames\` said only \`File exists\`; it now"
        echo "  names the folder. A spin axis of length overflowing or underflowing (\`[1e308; 3]\`) was"
        echo "  called \"zero\" without its line; the scene check now names its key and line."
        echo
        echo "## Found by two reviews of 2026-11-29 (a new user's and a hostile tester's), and fixed"
        echo
        echo "- escape: \`report --write-docs\` wrote a comparison's plots to \`DIR/results/<scene>/\`"
        echo "  with the scene read from its \`comparison.json\` (\`../../x\` left DIR); two comparisons"
        echo "  of one scene overwrote each other's plots. Both refused (tests/core/study_cli.rs)."
        echo "- panic: remesh on an OBJ cloth whose rest pattern overlaps itself (spade's loader)."
        echo "- accepted, then diverged or wrong: start or pinned speeds above \`time.max_speed\`,"
        echo "  gravity of 1e300, centres, translations and OBJ vertices at 1e300 m, a keyframe rotation"
        echo "  of 1e160 rad (the obstacle vanished and the run exited 0), two pins on one vertex with"
        echo "  different velocities, an obstacle mesh of flat faces only, edited reference caches."
        echo "- silent: a newline in an argument broke the resolved scene's rerun; runs without their"
        echo "  folder dropped from plots; an interrupted reference started its floor run anyway."
        echo
        echo "## Every case"
        echo
        echo "<details><summary>$(($(wc -l <"$T") - 1)) cases: outcome, seconds, command, first line of stderr</summary>"
        echo
        echo "| # | case | outcome | s | command | stderr |"
        echo "|---|---|---|---|---|---|"
        tail -n +2 "$T" | awk -F'\t' '{gsub(/\|/, "\\|"); printf "| %s | %s | %s | %s | `%s` | %s |\n", $1, $2, $3, $5, $6, substr($7, 1, 160)}'
        echo
        echo "</details>"
    } >"$DOC"
    echo "wrote $DOC"
fi
rm -rf "$IN/fifo.toml"
[ "$DEFECTS" = 0 ]
