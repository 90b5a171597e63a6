#!/usr/bin/env bash
# Makes sure a Vulkan driver is there for wgpu: a machine without a GPU gets Mesa's lavapipe
# (software Vulkan, Debian package mesa-vulkan-drivers). Needs root to install; otherwise warns.
if ldconfig -p 2>/dev/null | grep -q libvulkan.so.1 && ls /usr/share/vulkan/icd.d/*.json >/dev/null 2>&1; then
  exit 0
fi
if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
  echo "== installing Mesa's lavapipe (software Vulkan) for GPU code and pictures"
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq mesa-vulkan-drivers libvulkan1 >/dev/null
else
  echo "warning: no Vulkan driver found; install mesa-vulkan-drivers and libvulkan1 (Debian) for GPU code and pictures" >&2
fi
