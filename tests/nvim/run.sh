#!/usr/bin/env bash
# Runs the headless Neovim end-to-end test (tests/nvim/rename.lua) against the language
# server: a real editor's LSP client on a copy of examples/drilling. Needs `nvim` (Debian's
# neovim 0.7.2 is enough); `.ci/run` installs it. The cargo test suite does not need Neovim.
#
#   tests/nvim/run.sh            builds higraph-lsp (debug) if needed, then runs the test
#   HIGRAPH_LSP=path run.sh      uses that binary
set -euo pipefail
repo="$(cd "$(dirname "$0")/../.." && pwd)"

if ! command -v nvim >/dev/null 2>&1; then
  echo "tests/nvim/run.sh: nvim is not installed" >&2
  exit 1
fi

server="${HIGRAPH_LSP:-}"
if [ -z "$server" ]; then
  cargo build --quiet --manifest-path "$repo/Cargo.toml" -p higraph-lsp
  server="${CARGO_TARGET_DIR:-$repo/target}/debug/higraph-lsp"
fi

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cp -R "$repo/examples/drilling" "$work/drilling"
# A workspace file with a syntax error that the test never opens.
printf 'graph Kaputt <\n  state 0 < >\n> $\n' > "$work/drilling/graphs/kaputt.higraph"

HIGRAPH_LSP="$server" HIGRAPH_WS="$work/drilling" \
  timeout 300 nvim --headless -u NONE -i NONE -n \
  -c "luafile $repo/tests/nvim/rename.lua"
