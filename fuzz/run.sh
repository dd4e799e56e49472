#!/usr/bin/env bash
# Seed the corpus with the repository's shaders and fuzz the front end.
#
#   fuzz/run.sh [SECONDS] [extra libFuzzer args...]     (default 600 seconds)
#
# Needs cargo-fuzz (`cargo install cargo-fuzz`). Works on a stable toolchain: RUSTC_BOOTSTRAP=1
# unlocks the nightly-only flags cargo-fuzz passes, and `--sanitizer none` avoids needing a
# sanitizer runtime (the fuzzer still finds panics; they abort the run and write the input to
# fuzz/artifacts/front_end/).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(dirname "$here")"
secs="${1:-600}"
shift || true

corpus="$here/corpus/front_end"
mkdir -p "$corpus"
for f in "$root"/shaders/*.wgsl "$root"/crates/reproj-front/tests/fixtures/*.wgsl \
         "$root"/crates/reproj-front/tests/fuzz_regressions/*.wgsl; do
    [ -e "$f" ] && cp -n "$f" "$corpus/"
done

cd "$root"
RUSTC_BOOTSTRAP=1 exec cargo fuzz run --fuzz-dir fuzz --sanitizer none --debug-assertions front_end "$corpus" -- \
    -max_total_time="$secs" -dict="$here/wgsl.dict" -max_len=16384 -timeout=10 -rss_limit_mb=4096 "$@"
