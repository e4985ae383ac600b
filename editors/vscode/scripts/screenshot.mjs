#!/usr/bin/env node
// Makes images/screenshot.png for the README: tokenizes a .higraph file with the extension's
// grammar (the test harness, i.e. the real TextMate engine), colours the token scopes with
// the colours of VS Code's "Dark+" theme into an HTML page, and photographs the page with
// headless Chromium (Debian: apt-get install -y chromium).
//
//   node scripts/screenshot.mjs [FILE.higraph] [--out images/screenshot.png] [--lines A-B] [--html page.html]
//
// Default file: the drilling example's valve graph.
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { basename, join, relative, resolve } from 'node:path';
import { pathToFileURL } from 'node:url';
import { extensionRoot, tokenize } from '../test/harness.mjs';

const args = process.argv.slice(2);
const opt = (name) => {
  const i = args.indexOf(name);
  if (i < 0) return undefined;
  const v = args[i + 1];
  args.splice(i, 2);
  return v;
};
const out = resolve(opt('--out') ?? join(extensionRoot, 'images', 'screenshot.png'));
const htmlOut = opt('--html');
const range = opt('--lines');
const file = resolve(args[0] ?? join(extensionRoot, '..', '..', 'examples', 'drilling', 'graphs', 'ventil_2e.higraph'));

// Dark+ colours, by scope prefix; the innermost scope that has a rule wins.
const THEME = [
  ['invalid', '#f44747'],
  ['comment', '#6a9955'],
  ['string', '#ce9178'],
  ['constant.numeric', '#b5cea8'],
  ['constant.other.pointer', '#b5cea8'],
  ['constant.other.rule-code', '#4fc1ff'],
  ['constant.language', '#569cd6'],
  ['keyword.control', '#c586c0'],
  ['keyword.operator', '#d4d4d4'],
  ['keyword.other.directive', '#c586c0'],
  ['keyword', '#569cd6'],
  ['storage', '#569cd6'],
  ['support.function', '#dcdcaa'],
  ['support.variable', '#4fc1ff'],
  ['support.constant', '#4fc1ff'],
  ['entity.name.type', '#4ec9b0'],
  ['entity.name.function', '#dcdcaa'],
  ['entity.name.variable', '#9cdcfe'],
  ['entity.name.label', '#c8c8c8'],
  ['variable.language', '#569cd6'],
  ['variable', '#9cdcfe'],
];

function colourOf(scopes) {
  for (let i = scopes.length - 1; i >= 0; i--) {
    const s = scopes[i];
    for (const [prefix, colour] of THEME) {
      if (s === prefix || s.startsWith(prefix + '.')) return colour;
    }
  }
  return null;
}

const esc = (s) => s.replace(/&/g, '&amp;').replace(/</g, '&lt;').replace(/>/g, '&gt;');

const fullText = readFileSync(file, 'utf8').replace(/\n$/, '');
const allLines = await tokenize(fullText);
let [first, last] = [1, allLines.length];
if (range) [first, last] = range.split('-').map(Number);
// tokenize the whole file (the state of each line depends on the lines before), show a range
const lines = allLines.slice(first - 1, last);
const text = fullText.split('\n').slice(first - 1, last).join('\n');
const LINE_HEIGHT = 19;
const body = lines
  .map((tokens, i) => {
    const code = tokens
      .map((t) => {
        const c = colourOf(t.scopes);
        const italic = t.scopes.some((s) => s.startsWith('comment')) ? 'font-style:italic;' : '';
        return c ? `<span style="color:${c};${italic}">${esc(t.text)}</span>` : esc(t.text);
      })
      .join('');
    return `<div class="l"><span class="n">${first + i}</span><span class="c">${code || ' '}</span></div>`;
  })
  .join('\n');

const longest = Math.max(...text.split('\n').map((l) => l.length));
const width = Math.min(1400, Math.max(760, Math.ceil(longest * 8.45) + 110));
const height = lines.length * LINE_HEIGHT + 35 + 24 + 22;
const title = basename(file);

const html = `<!DOCTYPE html>
<html><head><meta charset="utf-8"><style>
  html, body { margin: 0; background: #1e1e1e; }
  .tabs { height: 35px; background: #252526; display: flex; }
  .tab { background: #1e1e1e; color: #ffffff; font: 13px "DejaVu Sans", sans-serif; padding: 0 16px;
         line-height: 35px; border-top: 1px solid #007acc; }
  .tab .dot { color: #519aba; margin-right: 6px; }
  .editor { padding: 6px 0 10px 0; font: 14px/${LINE_HEIGHT}px "DejaVu Sans Mono", monospace; color: #d4d4d4; }
  .l { white-space: pre; height: ${LINE_HEIGHT}px; }
  .n { display: inline-block; width: 44px; padding-right: 22px; text-align: right; color: #858585; }
  .status { position: fixed; bottom: 0; left: 0; right: 0; height: 22px; background: #007acc; color: #fff;
            font: 12px/22px "DejaVu Sans", sans-serif; padding: 0 10px; display: flex; justify-content: space-between; }
</style></head><body>
<div class="tabs"><div class="tab"><span class="dot">&#9670;</span>${esc(title)}</div></div>
<div class="editor">
${body}
</div>
<div class="status"><span>HiGraph</span><span>UTF-8 &nbsp; LF &nbsp; HiGraph</span></div>
</body></html>
`;

if (htmlOut) writeFileSync(htmlOut, html);

const chromium = ['/usr/bin/chromium', '/usr/bin/chromium-browser', '/usr/bin/google-chrome'].find((p) => existsSync(p));
if (!chromium) {
  console.error('Chromium not found: apt-get install -y chromium');
  process.exit(2);
}
const tmp = mkdtempSync(join(tmpdir(), 'higraph-shot-'));
try {
  const page = join(tmp, 'page.html');
  writeFileSync(page, html);
  execFileSync(
    chromium,
    [
      '--no-sandbox',
      '--disable-gpu',
      '--disable-quic',
      '--no-first-run',
      '--disable-background-networking',
      '--disable-component-update',
      '--disable-sync',
      '--headless',
      '--hide-scrollbars',
      '--force-device-scale-factor=1',
      `--user-data-dir=${join(tmp, 'profile')}`,
      `--window-size=${width},${height}`,
      `--screenshot=${out}`,
      pathToFileURL(page).href,
    ],
    { stdio: ['ignore', 'ignore', 'pipe'], timeout: 60_000 },
  );
} finally {
  rmSync(tmp, { recursive: true, force: true });
}
console.log(`wrote ${relative(process.cwd(), out)} (${width}x${height}) from ${relative(process.cwd(), file)}`);
