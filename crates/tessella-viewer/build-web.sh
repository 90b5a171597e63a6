#!/usr/bin/env bash
# Builds the viewer's engine for the browser into OUT_DIR (default web/dist/pkg/); see
# build-web.mjs, which does the work (shared tool setup with js/scripts/build.js).
set -euo pipefail
exec node "$(dirname "$0")/build-web.mjs" "$@"
