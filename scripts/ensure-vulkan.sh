#!/usr/bin/env bash
# Make sure a Vulkan driver is present: on a machine without a GPU driver, install Mesa's software
# Vulkan driver (lavapipe, Debian package mesa-vulkan-drivers). Needs root (or sudo) for apt-get.
set -euo pipefail
if ls /usr/share/vulkan/icd.d/*.json >/dev/null 2>&1 && ldconfig -p 2>/dev/null | grep -q 'libvulkan.so.1'; then
    exit 0
fi
echo "reproj: no Vulkan driver found; installing mesa-vulkan-drivers (lavapipe)" >&2
SUDO=""
if [ "$(id -u)" != "0" ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq mesa-vulkan-drivers libvulkan1 >/dev/null
