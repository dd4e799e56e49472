#!/usr/bin/env bash
# Install the shader compilers that reproj runs to read GLSL (glslangValidator, Debian package
# glslang-tools; spirv-opt from spirv-tools freezes specialization constants used in constant
# expressions) and that scripts/check-portability.sh (and the tests that run it) use to compile
# reproj's output independently: glslangValidator and spirv-val (spirv-tools), and the headless browser the `reproj report` test loads the page in
# (chromium), when they are missing and apt-get can install them. Never fails: without them the
# portability test and the report test print that they skipped those tools. naga
# (`cargo install naga-cli`) and tint (built from Dawn) are not installed here.
set -uo pipefail
missing=()
# nv-flip (the ꟻLIP metric) builds NVIDIA's C++ reference with the `cc` crate: the build needs a
# C++ compiler.
command -v c++ >/dev/null 2>&1 || missing+=(g++)
command -v glslangValidator >/dev/null 2>&1 || missing+=(glslang-tools)
{ command -v spirv-val >/dev/null 2>&1 && command -v spirv-opt >/dev/null 2>&1; } || missing+=(spirv-tools)
# Khronos' Vulkan validation layer: a test draws every strategy under it (lavapipe draws what
# Vulkan leaves undefined; the layer names it).
[ -e /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json ] || missing+=(vulkan-validationlayers)
command -v chromium >/dev/null 2>&1 || command -v chromium-browser >/dev/null 2>&1 || missing+=(chromium)
if [ ${#missing[@]} -eq 0 ]; then
    exit 0
fi
if ! command -v apt-get >/dev/null 2>&1; then
    echo "reproj: ${missing[*]} not installed and no apt-get here; the checks that need them will skip them" >&2
    exit 0
fi
SUDO=""
if [ "$(id -u)" != "0" ]; then
    if command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
        SUDO="sudo -n"
    else
        echo "reproj: ${missing[*]} not installed and no root to install them; the checks that need them will skip them" >&2
        exit 0
    fi
fi
echo "reproj: installing ${missing[*]} for the portability and report checks" >&2
export DEBIAN_FRONTEND=noninteractive
if ! { $SUDO apt-get update -qq && $SUDO apt-get install -y -qq "${missing[@]}" >/dev/null; }; then
    echo "reproj: could not install ${missing[*]}; the checks that need them will skip them" >&2
fi
exit 0
