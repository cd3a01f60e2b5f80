# The cases of tests/hostile/sweep.sh (sourced by it; see its header for `c` and the inputs).
# shellcheck shell=bash disable=SC2154

# --- Non-finite and extreme floats in every float key (nan, 1e308; -inf in some) ------------------------
for k in material.rho material.T material.kappa material.E material.alpha material.k_b \
    material.k_bd material.mu integrator.cg_tolerance collision.margin collision.restitution \
    collision.penalty \
    obstacles.0.radius obstacles.0.friction obstacles.0.restitution time.beta time.dt_initial \
    time.dt_min time.dt_max time.frame_rate time.metrics_rate time.max_speed; do
    for v in nan 1e308; do c "float $k=$v" -- run "${D[@]}" --set "$k=$v"; done
done
for v in nan -inf 1e308; do
    c "float material.A0=$v" -- run "${D[@]}" --set 'material.stiffness="seed"' --set "material.A0=$v"
    c "float time.dt=$v" -- run "${D[@]}" --set 'time.mode="fixed"' --set "time.dt=$v"
    c "float time.duration=$v" -- run --quiet --set "time.duration=$v"
    c "float --duration $v" -- run --quiet --duration "$v"
done
for k in compression_c cos_refine cos_simplify l_min l_max h_min c2 t_simplify flat_contact_cos \
    interval; do
    for v in nan 1e308; do
        c "float adaptivity.$k=$v" -- run "${D[@]}" --strategy bisect48 --set "adaptivity.$k=$v"
    done
done
for k in density_refine density_simplify remesh_min_angle curvature_exponent; do
    for v in nan -inf 1e308; do
        c "float adaptivity.$k=$v" -- run "${D[@]}" --strategy remesh --set "adaptivity.$k=$v"
    done
done
for v in nan -inf 1e308; do
    c "float adaptivity.depth_factor=$v" -- run "${D[@]}" --strategy simnett --set "adaptivity.depth_factor=$v"
done
for k in size_angle size_velocity size_compression size_proximity; do
    for v in nan 1e308; do
        c "float adaptivity.$k=$v" -- run "${D[@]}" --strategy bisect48 \
            --set 'adaptivity.criteria="sizing"' --set "adaptivity.$k=$v"
    done
done
# Vectors: one bad component
for k in cloth.size cloth.center cloth.rotation_deg cloth.velocity forces.g obstacles.0.center \
    tracked.0.rest; do
    for v in nan inf 1e308; do
        case $k in
            cloth.size | tracked.0.rest) vec="[1.0, $v]" ;;
            *) vec="[0.0, $v, 0.0]" ;;
        esac
        c "vector $k=$vec" -- run "${D[@]}" --set "$k=$vec"
    done
done
c "vector cloth.size=[0,0]" -- run "${D[@]}" --set 'cloth.size=[0.0, 0.0]'
c "vector cloth.size=[-1,1]" -- run "${D[@]}" --set 'cloth.size=[-1.0, 1.0]'
c "vector cloth.size 3 items" -- run "${D[@]}" --set 'cloth.size=[1.0, 1.0, 1.0]'
c "vector cloth.pinned nan" -- run "${D[@]}" --set 'cloth.pinned=[[nan, 0.0]]'
c "vector cloth.pinned_velocity nan" -- run "${D[@]}" --set 'cloth.pinned=[[0.0, 0.0]]' \
    --set 'cloth.pinned_velocity=[[0.0, nan, 0.0]]'
c "vector cloth.pinned_velocity 1e308" -- run "${D[@]}" --set 'cloth.pinned=[[0.0, 0.0]]' \
    --set 'cloth.pinned_velocity=[[0.0, 1e308, 0.0]]'
c "vector pinned_velocity count" -- run "${D[@]}" --set 'cloth.pinned_velocity=[[0.0, 1.0, 0.0]]'

# --- Obstacle fields ----------------------------------------------------------------------------
for v in '[0.1, nan, 0.1]' '[0.1, inf, 0.1]' '[0.0, 0.0, 0.0]' '[-0.1, 0.1, 0.1]' '[1e308, 1e308, 1e308]' \
    '[1e6, 1e6, 1e6]' '[1e6, 1e-6, 1e6]'; do
    c "box half_extents=$v" -- run "@IN@/box.toml" --quiet --set "obstacles.0.half_extents=$v"
done
c "box center nan" -- run "@IN@/box.toml" --quiet --set 'obstacles.0.center=[nan, 0.0, 0.0]'
for kv in radius=nan radius=1e308 radius=1e6 radius=0 height=inf height=0 height=-1 'center=[0.0, 0.0, 1e308]'; do
    c "cylinder $kv" -- run "@IN@/cyl.toml" --quiet --set "obstacles.0.$kv"
done
for kv in height=nan height=1e308 height=-1e308; do
    c "ground $kv" -- run "@IN@/ground.toml" --quiet --set "obstacles.0.$kv"
done
for kv in scale=nan scale=0 scale=-1 scale=1e308 scale=1e-308 'translation=[nan, 0.0, 0.0]' \
    'translation=[0.0, inf, 0.0]' 'translation=[0.0, 0.0, 1e308]'; do
    c "mesh $kv" -- run "@IN@/mesh.toml" --quiet --set "obstacles.0.$kv"
done
c "obstacle sphere without fields" -- run "@IN@/sphere_nofields.toml" --quiet
c "obstacle unknown kind" -- run "@IN@/kind.toml" --quiet
c "obstacles.99.radius" -- run "${D[@]}" --set obstacles.99.radius=1
c "obstacles.-1.radius" -- run "${D[@]}" --set obstacles.-1.radius=1

# --- Obstacle motion ----------------------------------------------------------------------------
for v in '[0.0, nan, 0.0]' '[0.0, inf, 0.0]' '[0.0, 1e308, 0.0]'; do
    c "linear velocity=$v" -- run "@IN@/lin.toml" --quiet --set "obstacles.0.motion.velocity=$v"
done
for kv in 'axis=[0.0, 0.0, 0.0]' 'axis=[nan, 0.0, 1.0]' 'axis=[1e-320, 0.0, 0.0]' \
    'axis=[1e308, 1e308, 1e308]' 'axis_point=[inf, 0.0, 0.0]' angular_velocity=nan \
    angular_velocity=inf angular_velocity=1e308; do
    c "spin $kv" -- run "@IN@/spin.toml" --quiet --set "obstacles.0.motion.$kv"
done
for kv in 'times=[0.0, nan]' 'times=[0.0, inf]' 'times=[0.0, 1e308]' 'times=[1.0, 0.0]' \
    'times=[0.0, 0.0]' 'times=[-1e308, 1e308]' 'times=[0.0, 1e-300]' 'times=[]' 'times=[0.0]' \
    'positions=[[0.0, 0.0, 0.0], [nan, 0.0, 0.0]]' 'positions=[[0.0, 0.0, 0.0], [1e308, 0.0, 0.0]]' \
    'positions=[[0.0, 0.0, 0.0]]' 'rotations=[[0.0, 0.0, 0.0], [0.0, 0.0, nan]]' \
    'rotations=[[0.0, 0.0, 0.0], [0.0, 0.0, 1e308]]' 'rotations=[[0.0, 0.0, 0.0], [0.0, 0.0, 3.14159265358979]]' \
    'rotations=[[0.0, 0.0, 0.0]]' 'pivot=[nan, 0.0, 0.0]' 'pivot=[0.0, 1e308, 0.0]'; do
    c "keyframes $kv" -- run "@IN@/kf.toml" --quiet --set "obstacles.0.motion.$kv"
done
c "motion on the ground" -- run "@IN@/ground_moving.toml" --quiet
c "motion unknown kind" -- run "@IN@/lin.toml" --quiet --set 'obstacles.0.motion.kind="teleport"'
c "moving_sphere scene, speed 1e308" -- run moving_sphere "${D[@]}" --set 'obstacles.0.motion.velocity=[0.0, 1e308, 0.0]'
c "turntable scene, spin nan" -- run turntable "${D[@]}" --set obstacles.0.motion.angular_velocity=nan

# --- Resolutions --------------------------------------------------------------------------------
# 2000 x 2000 is the 4-million-vertex bound itself: accepted, it builds for about 40 s and steps
# at about 10 s a step, so it outlasts the timeout (a legitimate long run, interrupted cleanly).
c "cloth.resolution=2000 (the vertex bound)" long -- run "${D[@]}" --set cloth.resolution=2000
for v in 0 1 -1 2001 1000000000 18446744073709551615 99999999999999999999 5.5 '"5"'; do
    c "cloth.resolution=$v" -- run "${D[@]}" --set "cloth.resolution=$v"
done
for v in 0 1 1000000000; do c "cloth.resolution_v=$v" -- run "${D[@]}" --set "cloth.resolution_v=$v"; done
c "resolution 3 x resolution_v 2000000" -- run "${D[@]}" --set cloth.resolution=3 --set cloth.resolution_v=2000000
c "disk resolution 1e9" -- run "@IN@/disk_huge.toml" --quiet
c "disk resolution 2" -- run "@IN@/disk_2.toml" --quiet

# --- Step counts (runs that could never finish) -------------------------------------------------
c "fixed dt=1e-300" -- run "${D[@]}" --set 'time.mode="fixed"' --set time.dt=1e-300
c "metrics_rate=1e20" -- run "${D[@]}" --set time.metrics_rate=1e20
c "frame_rate=1e9" -- run "${D[@]}" --set time.frame_rate=1e9
c "duration=1e300" -- run --quiet --set time.duration=1e300
c "duration=1e300 --force" -- run --quiet --force --set time.duration=1e300
c "dt_initial=1e-300" -- run "${D[@]}" --set time.dt_initial=1e-300
c "beta=1e-300" -- run "${D[@]}" --set time.dt_initial=0 --set time.beta=1e-300
c "material.E=1e308" -- run "${D[@]}" --set material.E=1e308
c "material.E=1e308 dt_initial 0" -- run "${D[@]}" --set material.E=1e308 --set time.dt_initial=0
c "material.E=1e308 --force" long -- run --quiet --force --set material.E=1e308 --set time.dt_initial=0
c "material.rho=1e-300" -- run "${D[@]}" --set material.rho=1e-300 --set time.dt_initial=0
c "cg_max_iterations huge" -- run "${D[@]}" --integrator implicit_euler --set integrator.cg_max_iterations=18446744073709551615
c "relaxation_passes huge" -- run "${D[@]}" --integrator verlet_relaxation --set integrator.relaxation_passes=1000000000
c "implicit dt=1e3 fixed" -- run "${D[@]}" --integrator implicit_euler --set 'time.mode="fixed"' --set time.dt=1000
c "max_speed=1e-300" -- run "${D[@]}" --set time.max_speed=1e-300
c "long valid run answers SIGINT" long -- run --quiet --set cloth.resolution=65 --duration 100 --set time.frame_rate=1 --set time.metrics_rate=1

# --- Adaptivity extremes ------------------------------------------------------------------------
for s in remesh simnett bisect48; do
    c "$s l_min=1e-9" -- run "${D[@]}" --strategy "$s" --set adaptivity.l_min=1e-9
    c "$s h_min=1e-12" -- run "${D[@]}" --strategy "$s" --set adaptivity.h_min=1e-12
    c "$s max_vertices=0" -- run "${D[@]}" --strategy "$s" --set adaptivity.max_vertices=0
    c "$s max_vertices huge" -- run "${D[@]}" --strategy "$s" --set adaptivity.max_vertices=18446744073709551615
    c "$s h_min tiny interval 0 rounds 16" -- run "${D[@]}" --strategy "$s" --set adaptivity.h_min=1e-9 \
        --set adaptivity.interval=0 --set adaptivity.rounds=16 --set adaptivity.cos_refine=0.0
done
for s in simnett bisect48; do
    c "$s max_depth=40" -- run "${D[@]}" --strategy "$s" --set adaptivity.max_depth=40 --set adaptivity.l_min=1e-12
    c "$s max_depth=u32 max" -- run "${D[@]}" --strategy "$s" --set adaptivity.max_depth=4294967295
done
c "rounds=0" -- run "${D[@]}" --strategy bisect48 --set adaptivity.rounds=0
c "rounds=1000" -- run "${D[@]}" --strategy bisect48 --set adaptivity.rounds=1000
c "remesh_min_angle=90" -- run "${D[@]}" --strategy remesh --set adaptivity.remesh_min_angle=90
c "l_min > l_max" -- run "${D[@]}" --strategy remesh --set adaptivity.l_min=1 --set adaptivity.l_max=0.1
c "strategy key on static" -- run "${D[@]}" --set adaptivity.remesh_min_angle=10

# --- Paths: scene names, --out ------------------------------------------------------------------
for f in "$IN"/name_*.toml; do
    c "scene name $(head -c 60 "$f" | head -1 | cut -c8-40)" -- run "$f" --quiet
done
c "--set name=/tmp/x" -- run "${D[@]}" --set 'name="/tmp/x"'
c "--set name=../../escaped" -- run "${D[@]}" --set 'name="../../escaped"'
c "--out /dev/full" -- run "${D[@]}" --out /dev/full
c "--out /dev/null" -- run "${D[@]}" --out /dev/null
c "--out a file" setup='echo x > o' -- run "${D[@]}" --out o
c "--out read-only dir" rootsetup='mkdir -p o && chown 0:0 o && chmod 555 o' -- run "${D[@]}" --out o/run
c "--out a FIFO" setup='mkfifo o' -- run "${D[@]}" --out o
c "--out under a FIFO" setup='mkfifo o' -- run "${D[@]}" --out o/run
c "--out empty" -- run "${D[@]}" --out ''
c "--out /" -- run "${D[@]}" --out /
c "--out /proc/self" -- run "${D[@]}" --out /proc/self
c "--out the scene file" -- run "@IN@/base.toml" --quiet --out "@IN@/base.toml"
c "--out frames is a file" setup='mkdir -p o && echo x > o/frames' -- run "${D[@]}" --out o
c "--out summary.json is a dir" setup='mkdir -p o/summary.json' -- run "${D[@]}" --out o
c "--out metrics.csv is a FIFO" setup='mkdir -p o && mkfifo o/metrics.csv.partial' -- run "${D[@]}" --out o
c "--out summary.json.tmp is a FIFO" setup='mkdir -p o && mkfifo o/summary.json.tmp' -- run "${D[@]}" --out o
c "--out a frame's .tmp is a FIFO" setup='mkdir -p o/frames && mkfifo o/frames/frame_00000.obj.tmp' -- run "${D[@]}" --out o
c "--out symlink to the sentinel (the user's own link: followed)" allow='.*/sentinel(/|$)' setup='ln -s ../../../sentinel o' -- run "${D[@]}" --out o

# --- Mesh obstacle files and OBJ cloths ---------------------------------------------------------
for m in dir missing dev abs up tet nan inf huge range zero neg bigidx twovert degen nov short \
    noface empty garbage flat; do
    c "mesh obstacle file $m" -- run "@IN@/mesh_$m.toml" --quiet
done
for m in tet nan range empty garbage dev far; do c "obj cloth $m" -- run "@IN@/cloth_$m.toml" --quiet; done

# --- Scene files --------------------------------------------------------------------------------
for f in empty comment garbage utf8 unterminated dup type_res type_size type_obst unknown \
    unknown_adapt deep_array deep_table deep_dotted huge_keys long_line \
    many_tracked many_pinned; do
    c "scene file $f" -- run "@IN@/$f.toml" --quiet
done
# 100,000 sphere obstacles: a valid run whose every step tests each vertex against each obstacle's
# box (no broad phase over obstacles), 25-30 ms a step: its 0.01 s took 24.5 s on a quiet machine
# and outlasted the 30 s timeout on a busy one (interrupted cleanly).
c "scene file many_obstacles" long -- run "@IN@/many_obstacles.toml" --quiet
c "scene is a directory" -- run "@IN@/dir.toml" --quiet
c "scene is a FIFO" -- run "@IN@/fifo.toml" --quiet
c "scene /dev/zero" -- run /dev/zero --quiet
c "scene /dev/urandom" -- run /dev/urandom --quiet
c "scene missing" -- run "@IN@/nope.toml" --quiet
c "scene unknown name" -- run sphree --quiet
c "scene name with a slash" -- run 'sphere/../sphere' --quiet

# --- --set syntax -------------------------------------------------------------------------------
for s in 'cloth.resolution' '=5' 'cloth.resolution=' 'cloth..resolution=5' '.=1' 'cloth=5' \
    'cloth.resolution.x=5' 'a.b.c.d.e.f=1' 'cloth.resolution=5=6' 'cloth.size=[[[[[[' \
    'cloth.size=[1.0, "a"]' 'obstacles=[]' 'obstacles.0=5' 'obstacles.0.kind="box"' \
    'tracked.0.name=5' 'name=5' 'time.mode="sideways"' "cloth.size=$(printf '[%.0s' $(seq 3000))"; do
    c "--set ${s:0:40}" -- run "${D[@]}" --set "$s"
done
c "--strategy magic" -- run "${D[@]}" --strategy magic
c "--integrator ''" -- run "${D[@]}" --integrator ''
c "--duration abc" -- run --quiet --duration abc
c "--duration 0" -- run --quiet --duration 0
c "run two scenes" -- run sphere bunny --quiet
c "unknown command" -- fly
c "no command" --
c "unknown option" -- run --warp 9

# --- Studies ------------------------------------------------------------------------------------
for f in ok unknown badkey nan beta sweep_type sweep_empty norun noscene dev scene_dir fifo \
    name__tmp_x name_______escaped label__tmp_x label_______escaped scene__tmp_x \
    scene_______escaped duplabel sweep_million sweep_product many_runs many_scenes ref_huge \
    ref_zero ref_floor ref_samples run_res run_res_huge strategy integrator set_nan set_E \
    top_set dt_tiny; do
    c "study $f" -- study "@IN@/st_$f.toml" --quiet
done
c "study sweep of names with slashes" -- study "@IN@/st_sweep_names.toml" --quiet --out o
c "study name ../../../../escaped (default out)" setup='sed "s|^name = .*|name = \"../../../../escaped\"|" "$IN/st_name__tmp_x.toml" > s.toml' -- study s.toml --quiet
c "study missing file" -- study "@IN@/nope.toml"
c "study a scene file" -- study "@IN@/base.toml" --quiet
c "study --jobs 0" -- study "@IN@/st_ok.toml" --quiet --jobs 0
c "study --jobs huge" -- study "@IN@/st_ok.toml" --quiet --jobs 18446744073709551615
c "study --shard 0/1" -- study "@IN@/st_ok.toml" --quiet --shard 0/1
c "study --shard 3/2" -- study "@IN@/st_ok.toml" --quiet --shard 3/2
c "study --shard 1/0" -- study "@IN@/st_ok.toml" --quiet --shard 1/0
c "study --shard x" -- study "@IN@/st_ok.toml" --quiet --shard x
c "study --out /dev/full" -- study "@IN@/st_ok.toml" --quiet --out /dev/full
c "study --out a file" setup='echo x > o' -- study "@IN@/st_ok.toml" --quiet --out o
c "study --cache /dev/full" -- study "@IN@/st_ok.toml" --quiet --cache /dev/full --out o
c "study --cache read-only" rootsetup='mkdir -p o && chown 0:0 o && chmod 555 o' -- study "@IN@/st_ok.toml" --quiet --cache o/cache --out out/s
c "study --write-docs /dev/full" -- study "@IN@/st_ok.toml" --quiet --out o --write-docs /dev/full
c "study --docs-notes dir" -- study "@IN@/st_ok.toml" --quiet --out o --write-docs o/docs --docs-notes "@IN@/emptydir"
c "study --docs-notes FIFO" -- study "@IN@/st_ok.toml" --quiet --out o --write-docs o/docs --docs-notes "@IN@/fifo.toml"
c "study --references-only" -- study "@IN@/st_ok.toml" --quiet --references-only --out o
c "study /dev/zero" -- study /dev/zero

# --- compare ------------------------------------------------------------------------------------
CR=(--quiet --duration 0.01 --ref-resolution 5 --floor-resolution 3 --samples 8 --out o)
for r in '' ',' 'magic@5' 'static@0' 'static@1' 'static@-1' 'static@' 'static@5.5' \
    'static@1000000000' 'static@18446744073709551616' '@5' 'remesh@5@5' 'static@3,static@3'; do
    c "compare --runs '$r'" -- compare "${CR[@]}" --runs "$r"
done
for o in '--integrators leapfrog' '--integrators ,' '--jobs 0' '--shard 2/1' '--ref-resolution 0' \
    '--ref-resolution 1' '--ref-resolution 100000' '--floor-resolution 0' '--floor-resolution 9' \
    '--samples 0' '--samples 1' '--samples 100000000' '--ref-beta nan' '--ref-beta -1' \
    '--ref-beta 1e308' '--ref-beta x' '--ref-dt-initial nan' '--ref-dt-initial 1e-300' \
    '--ref-dt nan' '--ref-dt 0' '--ref-dt x' '--ref-dt 1e-300' \
    '--ref-integrator leapfrog' '--duration nan' '--duration 1e300' '--cache /dev/full' \
    '--write-docs /dev/full' '--docs-notes /dev/zero' '--set cloth.resolution=1'; do
    # shellcheck disable=SC2086
    c "compare $o" -- compare "${CR[@]}" --runs static@3 $o
done
c "compare --out a file" setup='echo x > p' -- compare "${CR[@]}" --runs static@3 --out p
c "compare two scenes --out /dev/full" -- compare sphere hanging --quiet --duration 0.01 --ref-resolution 5 --floor-resolution 3 --samples 8 --runs static@3 --out /dev/full
c "compare a missing scene" -- compare "${CR[@]}" nope.toml
c "compare a bad scene file" -- compare "${CR[@]}" "@IN@/garbage.toml"
c "compare default out, scene /tmp/x" -- compare --quiet --duration 0.01 --ref-resolution 5 --floor-resolution 3 --samples 8 --runs static@3 "@IN@/name__tmp_x.toml"
c "compare default out, scene ../../escaped" -- compare --quiet --duration 0.01 --ref-resolution 5 --floor-resolution 3 --samples 8 --runs static@3 "@IN@/name_______escaped.toml"
c "compare ok" -- compare "${CR[@]}" --runs static@3,remesh

# --- render -------------------------------------------------------------------------------------
for f in missing.obj dir.obj /dev/zero empty.obj nan.obj inf.obj huge.obj range.obj zero.obj \
    neg.obj bigidx.obj twovert.obj degen.obj nov.obj short.obj noface.obj garbage.obj tet.obj; do
    case $f in /*) p=$f ;; *) p=@IN@/$f ;; esac
    c "render $f" -- render "$p" --out o.png
done
c "render --out /dev/full" -- render @FRAME@ --out /dev/full
c "render --out a dir" setup='mkdir o' -- render @FRAME@ --out o
c "render --out missing dir" -- render @FRAME@ --out o/a/b/c.png
c "render --out read-only dir" rootsetup='mkdir -p o && chown 0:0 o && chmod 555 o' -- render @FRAME@ --out o/x.png
c "render --out FIFO" setup='mkfifo o.png' -- render @FRAME@ --out o.png
c "render --width 0" -- render @FRAME@ --out o.png --width 0
c "render --height 0" -- render @FRAME@ --out o.png --height 0
c "render --width 1e9" -- render @FRAME@ --out o.png --width 1000000000
c "render 100000 x 100000" -- render @FRAME@ --out o.png --width 100000 --height 100000
c "render --width -1" -- render @FRAME@ --out o.png --width -1
c "render --scene garbage" -- render @FRAME@ --out o.png --scene "@IN@/garbage.toml"
c "render --scene nan mesh" -- render @FRAME@ --out o.png --scene "@IN@/mesh_nan.toml"
c "render --scene huge box" -- render @FRAME@ --out o.png --scene "@IN@/box.toml"
c "render no --out" -- render @FRAME@
c "render ok" -- render @FRAME@ --out o.png
c "render 16384 x 16384" -- render @FRAME@ --out o.png --width 16384 --height 16384

# --- report, merge ------------------------------------------------------------------------------
c "report no args" -- report
c "report missing dir" -- report "@IN@/nope"
c "report a file" -- report "@IN@/base.toml"
c "report an empty dir" -- report "@IN@/emptydir"
c "report garbage csv" setup='cp -r "$IN/cmp_csv" o' -- report o
c "report bad manifest" setup='cp -r "$IN/cmp_json" o' -- report o
c "report nan in csv" setup='cp -r "$IN/cmp_nan" o' -- report o
c "report read-only comparison" -- report "@IN@/cmp"
c "report comparison.csv is a FIFO" setup='cp -r "$IN/cmp" o && rm o/comparison.csv && mkfifo o/comparison.csv' -- report o
c "report comparison.json is a FIFO" setup='cp -r "$IN/cmp" o && rm o/comparison.json && mkfifo o/comparison.json' -- report o
c "report a label leaving runs/" setup='cp -r "$IN/cmp" o && sed -i "s|static-3-rk4|../../../../sentinel/esc|" o/comparison.csv' -- report o
c "merge a label leaving runs/" setup='cp -r "$IN/cmp" p && sed -i "s|static-3-rk4|../../../../sentinel/esc|" p/comparison.csv' -- merge p --out o
c "report ok" setup='cp -r "$IN/cmp" o' -- report o
c "report --write-docs /dev/full" setup='cp -r "$IN/cmp" o' -- report o --write-docs /dev/full
c "report --docs-notes /dev/zero" setup='cp -r "$IN/cmp" o' -- report o --write-docs o/docs --docs-notes /dev/zero
c "report a scene leaving docs/" setup='cp -r "$IN/cmp" o && sed -i "s|\"scene\": \"sphere\"|\"scene\": \"../../../../../../sentinel/esc\"|" o/comparison.json' -- report o --write-docs o/docs
c "report two comparisons of one scene" setup='mkdir o && cp -r "$IN/cmp" o/a && cp -r "$IN/cmp" o/b' -- report o/a o/b --write-docs o/docs
c "report --docs-notes without --write-docs" setup='cp -r "$IN/cmp" o' -- report o --docs-notes "@IN@/base.toml"
c "merge no args" -- merge
c "merge no --out" -- merge "@IN@/cmp"
c "merge the same dir twice" -- merge "@IN@/cmp" "@IN@/cmp" --out o
c "merge garbage" -- merge "@IN@/cmp_csv" --out o
c "merge --out /dev/full" -- merge "@IN@/cmp" --out /dev/full

# --- stability, reference, frame-diff -----------------------------------------------------------
c "stability --quick --out /dev/full" -- stability --quick --out /dev/full
c "stability --quick --out a dir" setup='mkdir o' -- stability --quick --out o
c "stability --quick --out missing dir (created: a valid long run)" long -- stability --quick --out o/a/b.md
c "stability --quick --out read-only" rootsetup='mkdir -p o && chown 0:0 o && chmod 555 o' -- stability --quick --out o/x.md
c "stability --quick --out FIFO" setup='mkfifo o.md' -- stability --quick --out o.md
c "stability --quick --out empty" -- stability --quick --out ''
c "reference --samples 0" -- reference --samples 0 --ref-resolution 5 --floor-resolution 3 --duration 0.01
c "reference --ref-resolution 1e9" -- reference --ref-resolution 1000000000 --duration 0.01
c "reference --cache a file" setup='echo x > o' -- reference --ref-resolution 5 --floor-resolution 3 --samples 8 --duration 0.01 --cache o
c "frame-diff different meshes" -- frame-diff @FRAME@ "@IN@/tet.obj"
c "frame-diff nan" -- frame-diff "@IN@/nan.obj" "@IN@/nan.obj"
c "frame-diff missing" -- frame-diff "@IN@/nope.obj" @FRAME@
c "integrators --write-docs /dev/full" -- integrators --write-docs /dev/full
c "integrators --docs without --write-docs" -- integrators --docs o.md
c "run an embedded scene beside a folder of its name" setup='mkdir sphere' -- run sphere --duration 0.01 --quiet --out o
c "run --set cloth.resolution.x (below a value)" -- run "${D[@]}" --set cloth.resolution.x=5
c "mesh obstacle scale 1e300" -- run "@IN@/mesh_tet.toml" --quiet --set obstacles.0.scale=1e300
c "mesh obstacle translation 1e300" -- run "@IN@/mesh_tet.toml" --quiet --set 'obstacles.0.translation=[1e300, 0.0, 0.0]'
c "gravity 1e300" -- run "${D[@]}" --set 'forces.g=[0.0, 0.0, -1e300]'
c "start speed above max_speed" -- run "${D[@]}" --set 'cloth.velocity=[0.0, 0.0, 1e10]'
c "duration 1e300" -- run --quiet --out o --set time.duration=1e300
c "key of 100000 characters" setup='python3 -c "print(\"[cloth]\\n\" + \"k\" * 100000 + \" = 1\")" > s.toml' -- run s.toml --quiet
c "compare --integrators rk4,rk4" -- compare --integrators rk4,rk4 --runs static@3 --out o
