#!/usr/bin/env bash
# Makes sure a headless OpenGL 4 driver is there for tessella-gl: EGL with Mesa (llvmpipe runs
# the GL 4.5 tessellation stages in software on machines without a GPU). Debian packages libegl1
# (the EGL loader), libegl-mesa0 (Mesa's EGL) and libgl1-mesa-dri (llvmpipe). Needs root to
# install; otherwise warns.
if ldconfig -p 2>/dev/null | grep -q libEGL.so.1 && ldconfig -p 2>/dev/null | grep -q libEGL_mesa.so.0 \
  && { compgen -G "/usr/lib/*/dri/swrast_dri.so" || compgen -G "/usr/lib*/dri/swrast_dri.so"; } >/dev/null; then
  exit 0
fi
if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
  echo "== installing EGL and Mesa's llvmpipe (software OpenGL 4.5) for tessella-gl"
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libegl1 libegl-mesa0 libgl1-mesa-dri >/dev/null
else
  echo "warning: no EGL/Mesa OpenGL driver found; install libegl1 libegl-mesa0 libgl1-mesa-dri (Debian) for tessella-gl" >&2
fi
