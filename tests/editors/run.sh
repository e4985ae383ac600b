#!/usr/bin/env bash
# Runs the editor configurations of docs/editors.md, exactly as printed there, against the
# real server, with the editors that are installed (not part of `.ci/run`):
#
#   bash tests/editors/run.sh [PATH-TO-higraph-lsp]
#
# Each client opens examples/mistakes/ventil.higraph (its workspace root holds higraph.toml)
# and must show HG4102 at `= Ab`; the ALE fixer must format a file. Editors that are missing
# are skipped. Debian/Ubuntu packages: neovim (0.7), vim + vim-ale, emacs-nox + elpa-eglot +
# elpa-lsp-mode.
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)
server=${1:-$repo/target/debug/higraph-lsp}
[ -x "$server" ] || { echo "no server at $server (cargo build -p higraph-lsp)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/bin"
ln -s "$server" "$work/bin/higraph-lsp"
export PATH="$work/bin:$PATH"
failed=0

# snippet LANG HEADING N: the N-th (0-based) ```LANG block after the heading line HEADING.
snippet() {
  python3 - "$repo/docs/editors.md" "$1" "$2" "$3" <<'EOF'
import re, sys
text = open(sys.argv[1]).read()
start = text.index(sys.argv[3])
blocks = re.findall(r"^```" + re.escape(sys.argv[2]) + r"\n(.*?)^```", text[start:], re.S | re.M)
sys.stdout.write(blocks[int(sys.argv[4])])
EOF
}

verdict() { # NAME FILE
  if grep -q "HG4102" "$2"; then
    echo "ok: $1"
  else
    echo "FAILED: $1"; cat "$2"; failed=1
  fi
}

cd "$repo/examples/mistakes"

if command -v nvim >/dev/null && nvim --version | grep -q "NVIM v0.7"; then
  { snippet lua "**Neovim 0.7**" 0; cat <<'EOF'
vim.defer_fn(function()
  vim.wait(20000, function() return #vim.diagnostic.get(0) > 0 end, 100)
  local lines = {}
  for _, d in ipairs(vim.diagnostic.get(0)) do table.insert(lines, d.code .. " " .. d.message) end
  vim.fn.writefile(lines, os.getenv("OUT"))
  vim.cmd("qa!")
end, 100)
EOF
  } > "$work/init.lua"
  OUT="$work/nvim.txt" timeout 60 nvim --headless -u "$work/init.lua" ventil.higraph >/dev/null 2>&1 || true
  touch "$work/nvim.txt"; verdict "Neovim 0.7" "$work/nvim.txt"
else
  echo "skipped: Neovim 0.7"
fi

ale=$(dirname "$(dirname "$(find /usr/share /usr/local/share "$HOME/.vim" -path '*autoload/ale.vim' 2>/dev/null | head -1)")" 2>/dev/null || true)
if command -v vim >/dev/null && command -v script >/dev/null && [ -n "$ale" ] && [ "$ale" != "." ]; then
  rt="$work/vim"
  mkdir -p "$rt/ftdetect" "$rt/ale_linters/higraph" "$rt/after/plugin"
  snippet vim "## Vim with ALE" 0 > "$rt/ftdetect/higraph.vim"
  snippet vim "## Vim with ALE" 1 > "$rt/ale_linters/higraph/higraph_lsp.vim"
  snippet vim "## Vim with ALE" 2 > "$rt/after/plugin/higraph.vim"
  cat > "$work/vimrc" <<EOF
set nocompatible
set runtimepath^=$ale
set runtimepath^=$rt
set runtimepath+=$rt/after
filetype plugin on
function! Report(timer) abort
  let l:out = map(ale#engine#GetLoclist(bufnr('')), 'get(v:val, "code", "?") . " " . v:val.text')
  call writefile(l:out, '$work/ale.txt')
  qa!
endfunction
function! Fixed(timer) abort
  call writefile(getline(1, '\$'), '$work/fixed.txt')
  qa!
endfunction
EOF
  timeout 40 script -qc "vim -N -u $work/vimrc -c 'call timer_start(8000, \"Report\")' ventil.higraph" /dev/null >/dev/null 2>&1 || true
  touch "$work/ale.txt"; verdict "Vim ALE linter" "$work/ale.txt"
  mkdir -p "$work/fmt" && printf '[workspace]\n' > "$work/fmt/higraph.toml"
  printf 'graph G <\nstate 0 < >\n   trans any->0 < U INIT_SD; >\n>\n' > "$work/fmt/a.higraph"
  (cd "$work/fmt" && timeout 40 script -qc "vim -N -u $work/vimrc -c ALEFix -c 'call timer_start(5000, \"Fixed\")' a.higraph" /dev/null >/dev/null 2>&1 || true)
  if grep -q "^  trans any->0 prio 1 < U INIT_SD; >" "$work/fixed.txt" 2>/dev/null; then
    echo "ok: Vim ALE fixer"
  else
    echo "FAILED: Vim ALE fixer"; cat "$work/fixed.txt" 2>/dev/null || true; failed=1
  fi
else
  echo "skipped: Vim ALE"
fi

if command -v emacs >/dev/null; then
  snippet elisp "## Emacs" 0 > "$work/mode.el"
  snippet elisp "## Emacs" 1 > "$work/project.el"
  snippet elisp "### Eglot" 0 > "$work/eglot.el"
  snippet elisp "### lsp-mode" 0 > "$work/lsp.el"
  cat > "$work/report.el" <<'EOF'
(defun higraph-test-report (file lines)
  (with-temp-file file (insert (mapconcat #'identity lines "\n"))))
EOF
  if emacs --batch --eval "(progn (package-initialize) (require 'eglot))" >/dev/null 2>&1; then
    cat > "$work/test-eglot.el" <<EOF
(package-initialize)
(require 'cl-lib)
(require 'project)
(load "$work/report.el")
(load "$work/mode.el")
(load "$work/project.el")
(require 'eglot)
(load "$work/eglot.el")
(remove-hook 'higraph-mode-hook #'eglot-ensure)
(find-file "ventil.higraph")
(apply #'eglot--connect (eglot--guess-contact))
(let ((deadline (+ (float-time) 20)))
  (while (and (< (float-time) deadline) (null (flymake-diagnostics)))
    (accept-process-output nil 0.2)))
(higraph-test-report "$work/eglot.txt" (mapcar #'flymake-diagnostic-text (flymake-diagnostics)))
(kill-emacs 0)
EOF
    timeout 60 emacs --batch -l "$work/test-eglot.el" >/dev/null 2>&1 || true
    touch "$work/eglot.txt"; verdict "Emacs Eglot" "$work/eglot.txt"
  else
    echo "skipped: Emacs Eglot"
  fi
  if emacs --batch --eval "(progn (package-initialize) (require 'lsp-mode))" >/dev/null 2>&1; then
    cat > "$work/test-lsp.el" <<EOF
(package-initialize)
(require 'cl-lib)
(require 'project)
(load "$work/report.el")
(load "$work/mode.el")
(load "$work/project.el")
(require 'lsp-mode)
(setq lsp-auto-guess-root t lsp-enable-file-watchers nil lsp-session-file "$work/lsp-session")
(load "$work/lsp.el")
(remove-hook 'higraph-mode-hook #'lsp-deferred)
(find-file "ventil.higraph")
(lsp)
(let ((deadline (+ (float-time) 25)) (lines nil))
  (while (and (< (float-time) deadline) (null lines))
    (accept-process-output nil 0.2)
    (maphash (lambda (_file diags)
               (dolist (d diags) (push (format "%s %s" (lsp:diagnostic-code? d) (lsp:diagnostic-message d)) lines)))
             (lsp-diagnostics t)))
  (higraph-test-report "$work/lsp.txt" lines))
(kill-emacs 0)
EOF
    timeout 90 emacs --batch -l "$work/test-lsp.el" >/dev/null 2>&1 || true
    touch "$work/lsp.txt"; verdict "Emacs lsp-mode" "$work/lsp.txt"
  else
    echo "skipped: Emacs lsp-mode"
  fi
else
  echo "skipped: Emacs"
fi

exit $failed
