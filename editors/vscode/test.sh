#!/usr/bin/env bash
# Builds, tests and packages the VS Code extension from a clean checkout (what CI runs):
#   bash editors/vscode/test.sh
# Needs Node 20+ with npm and the npm registry. Leaves higraph-<version>.vsix here.
set -euo pipefail
cd "$(dirname "$0")"

export npm_config_audit=false npm_config_fund=false npm_config_update_notifier=false

echo "== npm ci"
npm ci --no-progress

echo "== npm run typecheck"
npm run typecheck

echo "== npm run build"
npm run build

echo "== npm test"
npm test

echo "== npm run package"
rm -f ./*.vsix
npm run package </dev/null

vsix=$(ls ./*.vsix)
echo "== packaged ${vsix#./}"

# The package holds what the installed extension needs, never tests, end-to-end scripts,
# fixtures, build scripts or sources (`.vscodeignore`).
echo "== checking the package listing"
listing=$(npx vsce ls --no-dependencies)
if unwanted=$(grep -E '(^|/)(test|tests|e2e|fixtures|scripts|src)/|\.(test\.[a-z]+|mjs|sh|ts|map)$' <<<"$listing"); then
  echo "the package must not contain these files:" >&2
  echo "$unwanted" >&2
  exit 1
fi
grep -qx 'dist/extension.js' <<<"$listing" || { echo "dist/extension.js is missing from the package" >&2; exit 1; }
