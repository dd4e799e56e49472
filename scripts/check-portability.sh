#!/usr/bin/env bash
# Portability check: compile what reproj emits with compilers that are not reproj's own.
#
# For every sample shader in shaders/ (or the ones given), writes variants with `reproj instance`
# (the root and a few cacheable nodes spread over the cost range, in every strategy, plus the root
# with nearest reconstruction and a 16-bit cache, and with Catmull-Rom reconstruction) into a temporary directory, then runs on every
# emitted .wgsl file:
#
#   naga          validation (`naga FILE`)
#   tint          Dawn's WGSL compiler (`tint FILE --format wgsl`)
#   glslang es300, glslang 330, glslang 450
#                 naga's GLSL for each fragment entry point (`naga FILE out.frag --entry-point E
#                 --profile es300|core330|core450`) compiled by glslangValidator: WebGL2 / GLSL ES
#                 3.0 and desktop OpenGL
#   spirv-val     naga's SPIR-V of the module, checked by SPIRV-Tools
#
# and on what `reproj instance --lang glsl,spv` itself writes beside the WGSL (reproj's own
# backend options, not the naga CLI's):
#
#   reproj glsl   each pass's .frag (GLSL 4.50) compiled for Vulkan by glslangValidator -V
#   reproj spv    each pass's .spv checked by spirv-val
#
# and prints per tool how many passed (`glslang es300: 66/66`). A tool that is not installed is
# skipped with a line saying so. Exit status: 0 when everything that ran passed, 1 on any failure,
# 2 on a usage error.
#
# Usage: scripts/check-portability.sh [--reproj BIN] [--nodes N] [--strategies 3pass,2pass,fused]
#                                     [--keep DIR] [SHADER.wgsl ...]
#   --reproj BIN   the reproj binary (default: $REPROJ, else build and use target/debug/reproj)
#   --nodes N      cacheable nodes per shader besides the root (default 3)
#   --strategies   strategies to write (default: all three)
#   --keep DIR     write the variants and compiler outputs into DIR and keep them
#
# Install the compilers on Debian/Ubuntu with scripts/ensure-tools.sh (glslang-tools, spirv-tools);
# naga is `cargo install naga-cli`, tint is built from Dawn.
set -euo pipefail
cd "$(dirname "$0")/.."

usage() {
    sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'
}

reproj="${REPROJ:-}"
nodes=3
strategies="3pass,2pass,fused"
keep=""
shaders=()
while [ $# -gt 0 ]; do
    case "$1" in
        --reproj) reproj="${2:?--reproj needs a path}"; shift 2 ;;
        --nodes) nodes="${2:?--nodes needs a number}"; shift 2 ;;
        --strategies) strategies="${2:?--strategies needs a list}"; shift 2 ;;
        --keep) keep="${2:?--keep needs a directory}"; shift 2 ;;
        -h|--help) usage; exit 0 ;;
        -*) echo "check-portability: unknown option $1" >&2; usage >&2; exit 2 ;;
        *) shaders+=("$1"); shift ;;
    esac
done
case "$nodes" in ''|*[!0-9]*) echo "check-portability: --nodes must be a number, got '$nodes'" >&2; exit 2 ;; esac
IFS=',' read -r -a strategy_list <<<"$strategies"
for s in "${strategy_list[@]}"; do
    case "$s" in 3pass|2pass|fused) ;; *) echo "check-portability: unknown strategy '$s' (3pass, 2pass, fused)" >&2; exit 2 ;; esac
done
if [ ${#shaders[@]} -eq 0 ]; then
    shaders=(shaders/*.wgsl)
fi
for s in "${shaders[@]}"; do
    [ -f "$s" ] || { echo "check-portability: no shader $s" >&2; exit 2; }
done
if [ -z "$reproj" ]; then
    cargo build --quiet --locked -p reproj-cli
    reproj="${CARGO_TARGET_DIR:-target}/debug/reproj"
fi
[ -x "$reproj" ] || { echo "check-portability: $reproj is not an executable" >&2; exit 2; }

if [ -n "$keep" ]; then
    mkdir -p "$keep"
    work="$keep"
else
    work=$(mktemp -d)
    trap 'rm -rf "$work"' EXIT
fi

have() { command -v "$1" >/dev/null 2>&1; }
tools=()
have naga && tools+=("naga") || echo "skipped: naga (not installed: cargo install naga-cli); glslang and spirv-val need its output"
have tint && tools+=("tint") || echo "skipped: tint (not installed)"
if have naga && have glslangValidator; then
    tools+=("glslang es300" "glslang 330" "glslang 450")
else
    have glslangValidator || echo "skipped: glslang (glslangValidator not installed: apt-get install glslang-tools)"
fi
if have naga && have spirv-val; then
    tools+=("spirv-val")
else
    have spirv-val || echo "skipped: spirv-val (not installed: apt-get install spirv-tools)"
fi
have glslangValidator && tools+=("reproj glsl")
have spirv-val && tools+=("reproj spv")

declare -A ok total
for t in "${tools[@]}"; do ok[$t]=0; total[$t]=0; done
failures=0
fail_log="$work/failures.txt"
: >"$fail_log"

# Record one check: tool name, what was checked, the command as a person would type it, then the
# command to run.
check() {
    local tool="$1" what="$2" how="$3"
    shift 3
    total[$tool]=$((${total[$tool]} + 1))
    local out
    if out=$("$@" 2>&1); then
        ok[$tool]=$((${ok[$tool]} + 1))
    else
        failures=$((failures + 1))
        {
            echo "FAIL [$tool] $what"
            echo "  \$ $how"
            printf '%s\n' "$out" | head -n 15 | sed 's/^/  | /'
        } >>"$fail_log"
    fi
}

# The cacheable nodes of a shader (not the root), `nodes` of them spread over the list sorted by
# cost, the costliest first.
pick_nodes() {
    "$reproj" nodes "$1" --json |
        awk '/"id":/ { gsub(/[^0-9]/, "", $2); id = $2 }
             /"cost":/ { gsub(/,/, "", $2); cost = $2 }
             /"root":/ { if ($2 !~ /true/) print cost, id }' |
        sort -k1,1gr -k2,2n |
        awk -v n="$nodes" '{ ids[NR] = $2 }
             END { if (n == 0 || NR == 0) exit;
                   step = NR / n; if (step < 1) step = 1;
                   for (i = 0; i < n && int(i * step) + 1 <= NR; i++) print ids[int(i * step) + 1] }'
}

variants=0
for shader in "${shaders[@]}"; do
    stem=$(basename "$shader" .wgsl)
    mapfile -t ids < <(pick_nodes "$shader")
    specs=()
    for s in "${strategy_list[@]}"; do
        for n in root "${ids[@]}"; do
            specs+=("$n $s")
        done
    done
    specs+=("root ${strategy_list[0]} --reconstruct nearest --cache-format f16")
    specs+=("root ${strategy_list[0]} --reconstruct catmull-rom")
    for spec in "${specs[@]}"; do
        read -r node strategy extra <<<"$spec"
        dir="$work/$stem/${node}_${strategy}${extra:+_nearest_f16}"
        # shellcheck disable=SC2086
        if ! msg=$("$reproj" instance "$shader" --node "$node" --strategy "$strategy" $extra --lang glsl,spv --out "$dir" 2>&1); then
            failures=$((failures + 1))
            printf 'FAIL [reproj instance] %s node %s %s %s\n%s\n' "$shader" "$node" "$strategy" "$extra" "$msg" >>"$fail_log"
            continue
        fi
        variants=$((variants + 1))
        # Compiler outputs go elsewhere, so that a kept directory can be checked again.
        outdir="$work/compiled/$stem/$(basename "$dir")"
        mkdir -p "$outdir"
        for f in "$dir"/*.frag; do
            have glslangValidator || break
            # Vulkan GLSL: -V refuses a resource without layout(binding) (the manifest lists them).
            check "reproj glsl" "$stem/$(basename "$dir")/$(basename "$f")" \
                "glslangValidator -V -S frag $f" \
                glslangValidator -V -S frag "$f" -o "$outdir/$(basename "$f").vk.spv"
        done
        for f in "$dir"/*.spv; do
            have spirv-val || break
            check "reproj spv" "$stem/$(basename "$dir")/$(basename "$f")" "spirv-val $f" spirv-val "$f"
        done
        for f in "$dir"/*.wgsl; do
            what="$stem/$(basename "$dir")/$(basename "$f")"
            o="$outdir/$(basename "$f" .wgsl)"
            if have naga; then
                check "naga" "$what" "naga $f" naga "$f"
                if have spirv-val; then
                    check "spirv-val" "$what" "naga $f $o.spv && spirv-val $o.spv" \
                        bash -c 'naga "$1" "$2" && spirv-val "$2"' _ "$f" "$o.spv"
                fi
            fi
            if have tint; then
                check "tint" "$what" "tint $f --format wgsl" tint "$f" --format wgsl -o "$o.tint.wgsl"
            fi
            if have naga && have glslangValidator; then
                # Every fragment entry point (the pass's and, in a first pass, reproj_classify).
                mapfile -t entries < <(grep -A1 '^@fragment' "$f" | sed -n 's/^fn \([A-Za-z0-9_]*\).*/\1/p')
                for e in "${entries[@]}"; do
                    for p in es300:es300 330:core330 450:core450; do
                        name=${p%%:*}
                        profile=${p#*:}
                        out="$o.$e.$name.frag"
                        check "glslang $name" "$what ($e)" \
                            "naga $f $out --entry-point $e --profile $profile && glslangValidator -S frag $out" \
                            bash -c \
                            'naga "$1" "$2" --entry-point "$3" --profile "$4" && glslangValidator -S frag "$2"' \
                            _ "$f" "$out" "$e" "$profile"
                    done
                done
            fi
        done
    done
done

echo "check-portability: $variants variants of ${#shaders[@]} shaders ($strategies, root + up to $nodes nodes each, the root with nearest reconstruction and a 16-bit cache, and with Catmull-Rom)"
for t in "${tools[@]}"; do
    printf '  %-14s %s/%s\n' "$t:" "${ok[$t]}" "${total[$t]}"
done
if [ "$failures" -gt 0 ]; then
    echo
    cat "$fail_log"
    if [ -n "$keep" ]; then
        echo "check-portability: $failures failure(s) (the files are in $keep)"
    else
        echo "check-portability: $failures failure(s) (rerun with --keep DIR to keep the files)"
    fi
    exit 1
fi
if [ ${#tools[@]} -eq 0 ]; then
    echo "check-portability: no compiler installed, nothing was checked (the variants were written)"
else
    echo "check-portability: all passed"
fi
