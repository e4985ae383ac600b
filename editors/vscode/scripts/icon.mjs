#!/usr/bin/env node
// Renders images/icon.svg to images/icon.png (256x256, the marketplace icon) with headless
// Chromium (Debian: apt-get install -y chromium).
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';
import { extensionRoot } from '../test/harness.mjs';

const SIZE = 256;
const svg = readFileSync(join(extensionRoot, 'images', 'icon.svg'), 'utf8');
const tmp = mkdtempSync(join(tmpdir(), 'higraph-icon-'));
try {
  const page = join(tmp, 'icon.html');
  writeFileSync(page, `<!DOCTYPE html><html><body style="margin:0;background:transparent">${svg.replace(/width="128" height="128"/, `width="${SIZE}" height="${SIZE}"`)}</body></html>`);
  execFileSync('/usr/bin/chromium', [
    '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
    '--disable-component-update', '--disable-sync', '--headless', '--hide-scrollbars',
    '--force-device-scale-factor=1', '--default-background-color=00000000',
    `--user-data-dir=${join(tmp, 'profile')}`, `--window-size=${SIZE},${SIZE}`,
    `--screenshot=${join(extensionRoot, 'images', 'icon.png')}`, pathToFileURL(page).href,
  ], { stdio: ['ignore', 'ignore', 'pipe'], timeout: 60_000 });
} finally {
  rmSync(tmp, { recursive: true, force: true });
}
console.log('wrote images/icon.png');
