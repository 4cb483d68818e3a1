#!/usr/bin/env bash
# Rebuild the vendored three.js of `clearance view` from the npm registry:
#   tools/three/build.sh
# writes src/clearance/view/static/three.min.js (global THREE) and THREE_LICENSE.
# Pinned versions in package.json; the bundle holds only what entry.js exports.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
out="$here/../../src/clearance/view/static"
cd "$here"
npm install --no-audit --no-fund --silent
mkdir -p "$out"
version="$(node -p "JSON.parse(require('fs').readFileSync('node_modules/three/package.json')).version")"
npx esbuild entry.js --bundle --minify --format=iife --global-name=THREE \
  --legal-comments=none --target=es2020 \
  --banner:js="/* three.js ${version} subset (MIT, Copyright 2010-2026 three.js authors; see THREE_LICENSE), bundled by tools/three/build.sh */" \
  --outfile="$out/three.min.js"
cp node_modules/three/LICENSE "$out/THREE_LICENSE"
ls -l "$out/three.min.js"
