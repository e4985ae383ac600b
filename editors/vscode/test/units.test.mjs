// Unit tests of the extension's editor-independent parts (finding the item under the cursor,
// finding the server, the preview page). The TypeScript sources are bundled with esbuild into
// a temporary ES module first; `vscode` is not needed for these.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { chmodSync, mkdirSync, mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';
import * as esbuild from 'esbuild';
import { extensionRoot } from './harness.mjs';

const work = mkdtempSync(join(tmpdir(), 'higraph-vscode-test-'));
after(() => rmSync(work, { recursive: true, force: true }));

writeFileSync(
  join(work, 'entry.ts'),
  ['itemAtCursor', 'serverPath', 'previewPage']
    .map((m) => `export * from ${JSON.stringify(join(extensionRoot, 'src', m))};`)
    .join('\n'),
);
await esbuild.build({
  entryPoints: [join(work, 'entry.ts')],
  outfile: join(work, 'units.mjs'),
  bundle: true,
  platform: 'node',
  format: 'esm',
  logLevel: 'silent',
});
const m = await import(pathToFileURL(join(work, 'units.mjs')).href);

// ---- itemAt --------------------------------------------------------------------------------

const SOURCE = `// graph NotThis < >   (a comment)
symbols < X : E 0.0 BOOL "graph Nope"; >

graph Ventil "valve" <
  in < graph : BOOL; >
  state 0 < C: = graph; >
>

GROUP Anlage fc FC 1 <
  instance V : Ventil < >
>
chart type Dosierer <
  sequencer S < step A < > >
>
chart type <
>
`;

const at = (needle, text = SOURCE) => {
  const offset = text.indexOf(needle);
  assert.ok(offset >= 0, needle);
  const item = m.itemAt(text, offset);
  return item && `${item.kind} ${item.name}`;
};

test('itemAt finds the graph, group or chart around the cursor', () => {
  assert.equal(at('state 0'), 'graph Ventil');
  assert.equal(at('in < graph'), 'graph Ventil');
  assert.equal(at('instance V'), 'group Anlage');
  assert.equal(at('sequencer S'), 'chart Dosierer');
  assert.equal(at('chart type <'), 'chart type');
});

test('itemAt ignores comments, strings and keywords used as names', () => {
  assert.deepEqual(
    m.findItems(SOURCE).map((i) => `${i.kind} ${i.name}`),
    ['graph Ventil', 'group Anlage', 'chart Dosierer', 'chart type'],
  );
});

test('itemAt before the first item takes the first item; no item gives undefined', () => {
  assert.equal(at('symbols'), 'graph Ventil');
  assert.equal(m.itemAt('symbols < >', 3), undefined);
});

test('blanking keeps offsets', () => {
  const text = 'a "b // c" // d\n\'x\' e "unclosed\nf';
  const blank = m.blankCommentsAndStrings(text);
  assert.equal(blank.length, text.length);
  assert.equal(blank, 'a ' + ' '.repeat(8) + ' ' + ' '.repeat(4) + '\n' + '   ' + ' e ' + ' '.repeat(9) + '\nf');
});

// ---- resolveServer -------------------------------------------------------------------------

function fakeBinary(dir, name, executable = true) {
  mkdirSync(dir, { recursive: true });
  const p = join(dir, name);
  writeFileSync(p, '#!/bin/sh\nexit 0\n');
  chmodSync(p, executable ? 0o755 : 0o644);
  return p;
}

const posix = process.platform !== 'win32';

test('the setting wins, relative to the workspace folder, with ~ expanded', { skip: !posix }, () => {
  const ws = join(work, 'ws');
  const bin = fakeBinary(join(ws, 'bin'), 'higraph-lsp');
  const ext = join(work, 'ext1');
  fakeBinary(join(ext, 'server'), 'higraph-lsp');
  assert.deepEqual(m.resolveServer({ setting: 'bin/higraph-lsp', extensionPath: ext, workspaceFolder: ws, env: { PATH: '' } }), {
    command: bin,
    source: 'setting',
  });
  assert.deepEqual(m.resolveServer({ setting: '~/bin/higraph-lsp', extensionPath: ext, homedir: ws, env: { PATH: '' } }), {
    command: bin,
    source: 'setting',
  });
});

test('a wrong setting is an error that names the setting', { skip: !posix }, () => {
  const ext = join(work, 'ext2');
  fakeBinary(join(ext, 'server'), 'higraph-lsp');
  assert.throws(
    () => m.resolveServer({ setting: '/nope/higraph-lsp', extensionPath: ext, env: { PATH: '' } }),
    (e) => e instanceof m.ServerNotFoundError && e.settingIsWrong && /higraph\.server\.path/.test(e.message) && /does not exist/.test(e.message),
  );
  const notExec = fakeBinary(join(work, 'noexec'), 'higraph-lsp', false);
  assert.throws(
    () => m.resolveServer({ setting: notExec, extensionPath: ext, env: { PATH: '' } }),
    (e) => e instanceof m.ServerNotFoundError && /not an executable file/.test(e.message),
  );
});

test('then the bundled server, then PATH', { skip: !posix }, () => {
  const ext = join(work, 'ext3');
  const bundled = fakeBinary(join(ext, 'server'), 'higraph-lsp');
  const pathDir = join(work, 'pathdir');
  const onPath = fakeBinary(pathDir, 'higraph-lsp');
  const env = { PATH: `/nonexistent:${pathDir}` };
  assert.deepEqual(m.resolveServer({ setting: '', extensionPath: ext, env }), { command: bundled, source: 'bundled' });
  chmodSync(bundled, 0o644); // present but not executable: skipped
  assert.deepEqual(m.resolveServer({ setting: '  ', extensionPath: ext, env }), { command: onPath, source: 'path' });
});

test('nothing found: a clear error', () => {
  assert.throws(
    () => m.resolveServer({ setting: '', extensionPath: join(work, 'empty'), env: { PATH: '' } }),
    (e) => e instanceof m.ServerNotFoundError && !e.settingIsWrong && /higraph-lsp/.test(e.message) && /PATH/.test(e.message),
  );
});

// ---- preview page --------------------------------------------------------------------------

test('the preview page is self-contained: strict CSP, SVG as a data: image, no scripts', () => {
  const svg = '<svg xmlns="http://www.w3.org/2000/svg"><script>alert(1)</script><text>x</text></svg>';
  const html = m.page({ kind: 'graph', name: 'Ventil', offset: 0 }, { svg });
  assert.match(html, /Content-Security-Policy" content="default-src 'none'; img-src data:; style-src 'unsafe-inline';"/);
  assert.ok(html.includes(`src="data:image/svg+xml;base64,${Buffer.from(svg).toString('base64')}"`));
  assert.ok(!/<script/i.test(html));
  assert.ok(!/https?:\/\//.test(html.replace(/http:\/\/www\.w3\.org/g, '')), 'no external resources');
});

test('the preview page shows errors escaped; MethodNotFound is explained', () => {
  const html = m.page({ kind: 'chart', name: 'M<x>', offset: 0 }, { error: m.describeError({ code: -32601, message: 'Method not found' }) });
  assert.ok(html.includes('chart M&lt;x&gt;'));
  assert.ok(html.includes('does not support higraph/render'));
  assert.equal(m.describeError(new Error('boom')), 'boom');
  assert.equal(m.describeError({ code: -32803, message: 'no such graph' }), 'no such graph (error -32803)');
});
