#!/usr/bin/env bash
# Set everything up and run reproj on the bundled marble sample: list the nodes, profile them over
# the marble session and a faster one (analyze), then pick and write the fastest variant at four error budgets (emit),
# each checked by re-rendering (--verify), and write the HTML report. Results, charts and the report
# land in out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/ensure-vulkan.sh
# The ꟻLIP metric (nv-flip) builds C++: install a compiler (and the check tools) when none is here.
command -v c++ >/dev/null 2>&1 || bash scripts/ensure-tools.sh
# Headless: keep Mesa's device-select layer from looking for a display.
export NODEVICE_SELECT="${NODEVICE_SELECT:-1}"
# lavapipe runs shaders on the CPU: give it the machine's cores.
export LP_NUM_THREADS="${LP_NUM_THREADS:-$(nproc)}"
cargo build --release --locked -p reproj-cli
REPROJ=target/release/reproj
mkdir -p out
echo "== reproj nodes shaders/marble.wgsl (first lines)"
$REPROJ nodes shaders/marble.wgsl | head -12
echo
echo "== reproj analyze shaders/marble.wgsl --session sessions/marble.json --session sessions/marble_fast.json"
# Two motions of one scene: a profile each (out/marble.profile.json, out/marble.marble_fast.profile.json).
$REPROJ analyze shaders/marble.wgsl --session sessions/marble.json \
    --session sessions/marble_fast.json --out out/marble.profile.json
for budget in 0.002 0.01 0.03 0.1; do
    echo
    echo "== reproj emit --max-error $budget --verify"
    # Exit 4: the verified error is over the budget on this session (the warning says by how much
    # and names a tighter budget); the demo goes on to the next budget.
    rc=0
    # Both profiles: the choice holds the budget on both motions (the worst case); verified on
    # the faster one.
    $REPROJ emit --max-error "$budget" --profile out/marble.profile.json \
        --profile out/marble.marble_fast.profile.json --out "out/marble_$budget" \
        --verify --session sessions/marble_fast.json || rc=$?
    if [ "$rc" -ne 0 ] && [ "$rc" -ne 4 ]; then exit "$rc"; fi
done
echo
echo "== reproj report out/marble.profile.json"
$REPROJ report out/marble.profile.json --out out/marble.report.html
echo
echo "charts: out/marble.tradeoff.png (error vs frame time per node, the four selections marked), out/marble.hitrate.png, out/marble.models.png"
echo "report: out/marble.report.html (open it in a browser; move the budget slider)"
