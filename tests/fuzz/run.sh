#!/usr/bin/env bash
# Fuzzes the scene-file reader (parse_scene) with libFuzzer.
#
#   tests/fuzz/run.sh SRC_DIR WORK_DIR SECONDS
#
# Builds WORK_DIR/fuzz_scene with clang++ and AddressSanitizer +
# UndefinedBehaviorSanitizer (rebuilt only when a source is newer), seeds
# WORK_DIR/corpus with examples/scenes/*.toml and a few small scenes, and
# fuzzes for SECONDS seconds. Exits non-zero on any finding: a crash, a
# sanitizer report, an exception other than lagrangian::Error, a hang of more
# than 5 s on one input or more than 2 GB of memory. Reproducers are kept in
# WORK_DIR/artifacts; re-run one with `WORK_DIR/fuzz_scene <file>`.
#
# Without clang++ (or its libFuzzer runtime) it prints why and exits 0 with
# "skipped". Needs the Debian packages clang and libclang-rt-dev (or
# libclang-rt-14-dev), plus libtomlplusplus-dev and libeigen3-dev.
set -euo pipefail

if [ $# -ne 3 ]; then
  echo "usage: $0 SRC_DIR WORK_DIR SECONDS" >&2
  exit 2
fi
src=$(cd "$1" && pwd)
work=$2
seconds=$3
cxx=${FUZZ_CXX:-clang++}

mkdir -p "$work"
work=$(cd "$work" && pwd)

if ! command -v "$cxx" > /dev/null 2>&1; then
  echo "fuzz.scene_parser: skipped: $cxx not found (install the Debian packages clang and libclang-rt-dev)"
  exit 0
fi

flags=(-std=c++20 -O1 -gline-tables-only -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all
       -I"$src/include" -I"$src/models" -I/usr/include/eigen3 -DTOML_HEADER_ONLY=0 -DTOML_SHARED_LIB=1)

# The libFuzzer runtime ships separately from the compiler.
probe="$work/probe.cpp"
printf '#include <cstdint>\n#include <cstddef>\nextern "C" int LLVMFuzzerTestOneInput(const std::uint8_t*, std::size_t) { return 0; }\n' > "$probe"
if ! "$cxx" -fsanitize=fuzzer,address,undefined "$probe" -o "$work/probe" > "$work/probe.log" 2>&1; then
  echo "fuzz.scene_parser: skipped: $cxx cannot link -fsanitize=fuzzer (install libclang-rt-dev):"
  sed -n 1,5p "$work/probe.log"
  exit 0
fi

sources=(
  "$src/tests/fuzz/fuzz_scene.cpp"
  "$src/src/scene/scene_messages.cpp"
  "$src/src/scene/scene_gas_fill.cpp"
  "$src/src/scene/scene_validate_fields.cpp"
  "$src/src/scene/scene_validate_initial.cpp"
  "$src/src/scene/toml_scene.cpp"
  "$src/src/scene/toml_document.cpp"
  "$src/src/scene/model_catalog.cpp"
  "$src/src/scene/text_model_spec.cpp"
  "$src/src/text/parse.cpp"
  "$src/src/text/read.cpp"
  "$src/src/text/formula.cpp"
  "$src/src/integrate/report.cpp"
  "$src/src/integrate/report_json.cpp"
  "$src/src/integrate/method.cpp"
  "$src/src/core/params.cpp"
  "$src/src/core/nearest_name.cpp"
)
bin="$work/fuzz_scene"
stale=0
if [ ! -x "$bin" ]; then
  stale=1
else
  for f in "${sources[@]}" "$src"/include/lagrangian/*.hpp "$src"/include/lagrangian/*/*.hpp "$src"/include/lagrangian/*/detail/*.hpp \
           "$src"/src/scene/scene_*.hpp "$src"/models/lagrangian/models/*.hpp "$0"; do
    if [ "$f" -nt "$bin" ]; then stale=1; break; fi
  done
fi
if [ "$stale" = 1 ]; then
  echo "fuzz.scene_parser: building $bin"
  mkdir -p "$work/obj"
  objs=()
  pids=()
  for f in "${sources[@]}"; do
    o="$work/obj/$(basename "$f" .cpp).o"
    objs+=("$o")
    "$cxx" "${flags[@]}" -c "$f" -o "$o" &
    pids+=($!)
    # two compilers at a time
    if [ ${#pids[@]} -ge 2 ]; then wait "${pids[0]}"; pids=("${pids[@]:1}"); fi
  done
  for p in "${pids[@]}"; do wait "$p"; done
  "$cxx" "${flags[@]}" "${objs[@]}" -ltomlplusplus -o "$bin.new"
  mv "$bin.new" "$bin"
fi

# Corpus: the example scenes, a few small scenes of our own, and whatever
# earlier runs found interesting (kept in WORK_DIR/corpus).
corpus="$work/corpus"
mkdir -p "$corpus" "$work/artifacts"
if compgen -G "$src/examples/scenes/*.toml" > /dev/null; then
  cp -f "$src"/examples/scenes/*.toml "$corpus"/
fi
seed() { cat > "$corpus/seed_$1.toml"; }
seed ball << 'EOF'
name = "ball"
[run]
t_end = 2
[[bodies]]
name = "ball"
mass = 0.2
radius = 0.05
position = [0, 0, 1]
velocity = [1, 0, 2]
[gravity]
[[contacts.planes]]
name = "floor"
restitution = 0.8
EOF
seed gas << 'EOF'
[contacts.box]
min = [0, 0, 0]
max = [1, 1, 1]
[contacts.spheres]
restitution = 1
[gas]
count = 20
radius = 0.05
speed = 1.5
seed = 3
[run]
engine = "event_driven"
[[bodies]]
name = "heavy"
mass = 5
radius = 0.1
position = [0.275, 0.275, 0.725]
EOF
seed pendulum << 'EOF'
[[bodies]]
name = "bob"
mass = 1
position = [1, 0, 0]
velocity = [0, 0, 1]
[[links]]
a = "bob"
anchor = [0, 0, 0]
length = 1
[[surfaces]]
body = "bob"
kind = "sphere"
centre = [0, 0, 0]
radius = 1
[[springs]]
a = "bob"
anchor = [0, 0, -1]
stiffness = 10
[[linear_drag]]
coefficient = 0.1
[[quadratic_drag]]
coefficient = 0.01
bodies = ["bob"]
[newtonian_gravity]
G = 1
[run]
stabilization = "baumgarte"
method = "rk4"
EOF
seed model << 'EOF'
[model]
name = "double_pendulum"
q = [0.5, 0.1]
qd = [0, 0]
[model.parameters]
m1 = 2
[output]
directory = "out"
formats = ["png"]
plots = true
trajectory = false
EOF

# A dictionary of the format's words helps the mutator reach deep keys.
dict="$work/scene.dict"
{
  for w in name description run method engine t0 t_end dt rtol atol output_interval max_steps stabilization \
           baumgarte_omega output directory trajectory plots formats bodies mass radius position velocity gas count \
           speed seed prefix gravity g newtonian_gravity G springs a b anchor stiffness rest_length linear_drag \
           quadratic_drag coefficient links length surfaces body kind point centre normal contacts spheres planes \
           box min max restitution model parameters q qd dopri5 rk4 event_driven ode auto none baumgarte projection \
           plane sphere png svg double_pendulum nan inf true false; do
    printf '"%s"\n' "$w"
  done
  printf '"[[bodies]]"\n"[contacts.box]"\n"[[contacts.planes]]"\n"[model.parameters]"\n" = "\n"[0, 0, 0]"\n'
  printf '"\\x0A"\n"1e308"\n"-0.0"\n"9223372036854775807"\n'
} > "$dict"

echo "fuzz.scene_parser: fuzzing for $seconds s"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
status=0
"$bin" "$corpus" -dict="$dict" -max_total_time="$seconds" -timeout=5 -rss_limit_mb=2048 -max_len=8192 \
  -artifact_prefix="$work/artifacts/" -print_final_stats=1 > "$work/fuzz.log" 2>&1 || status=$?
grep -E "^stat::number_of_executed_units|^stat::peak_rss_mb|^#[0-9]+.*DONE" "$work/fuzz.log" || true
if [ "$status" -ne 0 ]; then
  echo "fuzz.scene_parser: FINDING (exit $status); reproducers in $work/artifacts:"
  ls -1 "$work/artifacts" || true
  grep -E "ERROR|runtime error|SUMMARY|deadly|uncaught|Timeout|out-of-memory|became invalid" "$work/fuzz.log" | head -20 || true
  echo "full log: $work/fuzz.log"
  exit 1
fi
echo "fuzz.scene_parser: no findings"
