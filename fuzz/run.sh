#!/usr/bin/env bash
# Seed a target's corpus from the repository and fuzz it.
#
#   fuzz/run.sh [TARGET] [SECONDS] [extra libFuzzer args...]
#
# TARGET: front_end (the default), profile, journal, session, glsl, spirv, obj or manifest;
# SECONDS: 600 by default. For
# compatibility, a first argument that is a number is SECONDS for front_end (`fuzz/run.sh 1200`).
#
# Needs cargo-fuzz (`cargo install cargo-fuzz`). Works on a stable toolchain: RUSTC_BOOTSTRAP=1
# unlocks the nightly-only flags cargo-fuzz passes, and `--sanitizer none` avoids needing a
# sanitizer runtime (the fuzzer still finds panics; they abort the run and write the input to
# fuzz/artifacts/TARGET/).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(dirname "$here")"

target=front_end
case "${1:-}" in
    front_end|profile|journal|session|glsl|spirv|obj|manifest) target="$1"; shift ;;
    ''|[0-9]*) ;;
    *) echo "fuzz/run.sh: unknown target '$1' (front_end, profile, journal, session, glsl, spirv, obj, manifest)" >&2; exit 2 ;;
esac
secs="${1:-600}"
shift || true

corpus="$here/corpus/$target"
mkdir -p "$corpus"
seed() { for f in "$@"; do [ -f "$f" ] && cp -n "$f" "$corpus/"; done; return 0; }
# Files under $1 (recursively) whose text names schema $2.
seed_schema() {
    [ -d "$1" ] || return 0
    grep -rlF --include='*.json' "\"$2\"" "$1" | grep -v '/target/' | while read -r f; do
        cp -n "$f" "$corpus/$(echo "${f#"$root"/}" | tr / _)"
    done
}

features=()
dict="$here/json.dict"
case "$target" in
    front_end)
        seed "$root"/shaders/*.wgsl "$root"/crates/reproj-front/tests/fixtures/*.wgsl \
             "$root"/crates/reproj-front/tests/fuzz_regressions/*.wgsl
        dict="$here/wgsl.dict"; max_len=16384 ;;
    profile)
        # The committed profiles, and any in out/ (a local `reproj analyze` run's).
        seed_schema "$root/crates" reproj.profile
        seed_schema "$root/out" reproj.profile
        seed "$root"/crates/reproj-models/tests/fuzz_regressions/*.profile.json
        max_len=65536 ;;
    journal)
        # Journals are deleted once their profile is written: seeds are made from the profiles'
        # measurements (the same JSON), under the header the target expects (key "fuzz").
        for p in $( (grep -rlF --include='*.json' '"reproj.profile"' "$root/crates" "$root/out" 2>/dev/null || true) | grep -v '/target/'); do
            out="$corpus/$(echo "${p#"$root"/}" | tr / _ | sed 's/\.profile\.json$//').journal"
            [ -e "$out" ] || python3 "$here/journal_seed.py" "$p" > "$out" || rm -f "$out"
        done
        seed "$root"/crates/reproj-models/tests/fuzz_regressions/*.journal
        max_len=8192 ;;
    session)
        seed_schema "$root/sessions" reproj.session
        seed_schema "$root/tests" reproj.session
        seed_schema "$root/crates" reproj.session
        seed "$root"/crates/reproj-models/tests/fuzz_regressions/*.session.json
        features=(--features session)
        max_len=65536 ;;
    glsl)
        seed $(find "$root/shaders" "$root/tests/corpus/shaders" "$root/crates/reproj-front/tests" \
            \( -name '*.frag' -o -name '*.glsl' \) 2>/dev/null)
        seed "$root"/crates/reproj-front/tests/fuzz_regressions/*.frag
        dict="$here/glsl.dict"; max_len=16384 ;;
    spirv)
        # glslang's SPIR-V of the GLSL seeds (what reproj reads from it), where it is installed.
        if command -v glslangValidator >/dev/null; then
            for f in $(find "$root/shaders" "$root/tests/corpus/shaders" \( -name '*.frag' -o -name '*.glsl' \) 2>/dev/null); do
                out="$corpus/$(basename "$f").spv"
                [ -e "$out" ] || glslangValidator -V -S frag -o "$out" "$f" >/dev/null 2>&1 || rm -f "$out"
            done
        fi
        seed "$root"/crates/reproj-front/tests/fuzz_regressions/*.spv
        dict="$here/spirv.dict"; max_len=65536 ;;
    obj)
        # Small meshes: a triangle, a quad with normals and uvs, the faces tobj triangulates.
        [ -e "$corpus/tri.obj" ] || printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > "$corpus/tri.obj"
        [ -e "$corpus/quad.obj" ] || printf 'o quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1/1 2/2/1 3/3/1 4/4/1\ng two\nv 0 0 1\nf -1 -2 -3\n' > "$corpus/quad.obj"
        seed $(find "$root/tests" "$root/crates" -name '*.obj' -not -path '*/target/*' 2>/dev/null)
        seed "$root"/crates/reproj-scene/tests/fuzz_regressions/*.obj
        dict="$here/obj.dict"; max_len=8192 ;;
    manifest)
        seed_schema "$root/crates" reproj.manifest
        seed_schema "$root/tests" reproj.manifest
        seed "$root"/crates/reproj-models/tests/fuzz_regressions/*.manifest.json
        max_len=65536 ;;
esac

cd "$root"
RUSTC_BOOTSTRAP=1 exec cargo fuzz run --fuzz-dir fuzz --sanitizer none --debug-assertions \
    "${features[@]}" "$target" "$corpus" -- \
    -max_total_time="$secs" -dict="$dict" -max_len="$max_len" -timeout=10 -rss_limit_mb=4096 "$@"
