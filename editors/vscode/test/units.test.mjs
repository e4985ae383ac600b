// Unit tests of the extension's editor-independent parts (finding the item under the cursor,
// finding the server, the preview page, the report of a build). The TypeScript sources are bundled with esbuild into
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
  ['itemAtCursor', 'serverPath', 'previewPage', 'testResult', 'build']
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

test('the player page runs only its own script (nonce) and shows the SVG inline', () => {
  const svg = '<svg xmlns="http://www.w3.org/2000/svg"><script>alert(1)</script><circle data-state="0"/></svg>';
  const trace = { test: 'T</script>', result: 'passed', cycle_ms: 10, run: ['G'], initial: { watch: {} }, cycles: [] };
  const html = m.playerPage({ kind: 'graph', name: 'Ventil', offset: 0 }, svg, trace, 'abc123');
  assert.match(html, /script-src 'nonce-abc123';/);
  assert.ok(!html.includes('alert(1)'), 'the SVG\'s script is removed');
  assert.ok(html.includes('<circle data-state="0"/>'));
  // the trace cannot close its <script> element
  const data = /<script id="trace" type="application\/json">([^]*?)<\/script>/.exec(html);
  assert.ok(data);
  assert.equal(JSON.parse(data[1]).test, 'T</script>');
  assert.equal((html.match(/<script nonce="abc123">/g) ?? []).length, 1);
  // the player's script is valid JavaScript (compiled, not run: it needs the webview's DOM)
  const script = /<script nonce="abc123">([^]*?)<\/script>/.exec(html)[1];
  assert.doesNotThrow(() => new Function(script));
  assert.equal((html.match(/<script/g) ?? []).length, 2);
});

test('a fired transition is found by its data-trans key', () => {
  assert.equal(m.firedKey({ kind: 'normal', from: 1, to: 2, prio: 3 }), '1->2:3');
  assert.equal(m.firedKey({ kind: 'any', from: 5, to: 9, prio: 2 }), 'any->9:2');
  assert.equal(m.firedKey({ kind: 'startup', from: 3, to: 0, prio: 1 }), 'any->0:1');
  assert.equal(m.firedKey({ kind: 'return', from: 5, to: 1, prio: 1 }), '5->return:1');
  assert.equal(m.firedKey({ kind: 'initial', from: null, to: 0, prio: null }), undefined);
  assert.equal(m.firedKey(null), undefined);
});

// ---- tests ---------------------------------------------------------------------------------

test('testAt finds the test header above the cursor, not in comments or strings', () => {
  const text = '// test Nope <\ngraph G < >\ntest Erster "desc" <\n  expect x;\n>\ntest Zweiter <\n  expect "test Falsch <";\n>\n';
  assert.equal(m.testAt(text, text.indexOf('graph')), undefined);
  assert.equal(m.testAt(text, text.indexOf('expect x')), 'Erster');
  assert.equal(m.testAt(text, text.indexOf('Falsch')), 'Zweiter');
});

test('failures are placed in their files, relative to the workspace root', () => {
  assert.equal(m.fileUri('file:///ws/tests/t.higraph', 'tests/t.higraph', 'graphs/g.higraph'), 'file:///ws/graphs/g.higraph');
  assert.equal(m.fileUri('file:///w%20s/a%20b.higraph', 'a b.higraph', 'c d.higraph'), 'file:///w%20s/c%20d.higraph');
  assert.equal(m.fileUri('file:///elsewhere/x.higraph', 'tests/t.higraph', 'g.higraph'), 'file:///elsewhere/x.higraph');
  const range = { start: { line: 3, character: 9 }, end: { line: 3, character: 20 } };
  const failed = m.verdict('file:///ws/t.higraph', {
    name: 'T', file: 't.higraph', range, result: 'failed', cycles: 3, time_ms: 30,
    failures: [{ code: 'HG9901', message: 'expect failed: at cycle 3 (t = 30 ms): X = FALSE', file: 't.higraph', range, cycle: 3, time_ms: 30, values: { X: false } }],
  });
  assert.equal(failed.state, 'failed');
  assert.deepEqual(failed.messages, [{ uri: 'file:///ws/t.higraph', range, message: 'HG9901: expect failed: at cycle 3 (t = 30 ms): X = FALSE' }]);
  assert.match(failed.summary, /^test T \.\.\. FAILED \(3 cycles, 30 ms\)\n  HG9901/);
  const passed = m.verdict('file:///ws/t.higraph', { name: 'T', file: 't.higraph', range, result: 'passed', cycles: 1, time_ms: 10, failures: [] });
  assert.deepEqual([passed.state, passed.messages, passed.summary], ['passed', [], 'test T ... ok (1 cycle, 10 ms)']);
  assert.equal(m.verdict('file:///ws/t.higraph', { name: 'T', file: 't.higraph', range, result: 'error', cycles: 0, time_ms: 0, failures: [] }).state, 'errored');
  assert.equal(m.testId('file:///ws/t.higraph', 'Bohr'), 'file:///ws/t.higraph#BOHR');
});

// ---- build ---------------------------------------------------------------------------------

test('a build report: the summary as notification, one output line per file written', () => {
  const r = m.describeBuild({ files: ['build/Bohrmaschine.awl', 'build/symbols.sdf'], refused: false, message: 'built 1 group, 0 charts: 2 files written' });
  assert.equal(r.severity, 'info');
  assert.equal(r.notification, 'HiGraph: built 1 group, 0 charts: 2 files written');
  assert.deepEqual(r.lines, [
    'build of the workspace: built 1 group, 0 charts: 2 files written',
    '  wrote build/Bohrmaschine.awl',
    '  wrote build/symbols.sdf',
  ]);
  assert.deepEqual(
    m.describeBuild({ files: ['build/Anlage.awl'], unchanged: ['build/symbols.sdf'], refused: false, message: 'built 1 group: 1 file written, 1 unchanged' }).lines,
    ['build of the workspace: built 1 group: 1 file written, 1 unchanged', '  wrote build/Anlage.awl', '  unchanged build/symbols.sdf'],
  );
  assert.deepEqual(m.describeBuild({ files: [], refused: false, message: 'nothing to build' }).lines, [
    'build of the workspace: nothing to build',
    '  no file written',
  ]);
});

test('a refused build is an error that points to the Problems panel; files are not listed', () => {
  const r = m.describeBuild({ files: ['ignored.awl'], refused: true, message: 'build refused: 2 errors in bohrmaschine.higraph' }, 'group Anlage');
  assert.equal(r.severity, 'error');
  assert.equal(r.notification, 'HiGraph: build refused: 2 errors in bohrmaschine.higraph');
  assert.equal(r.lines[0], 'build of group Anlage: build refused: 2 errors in bohrmaschine.higraph');
  assert.match(r.lines[1], /nothing was written.*Problems/);
  assert.equal(r.lines.length, 2);
});

test('a malformed answer is reported, never thrown', () => {
  for (const bad of [null, undefined, 42, 'text', {}, { files: 'x', message: 3 }]) {
    const r = m.describeBuild(bad);
    assert.equal(r.severity, 'error', JSON.stringify(bad));
    assert.match(r.notification, /no answer the extension understands/);
  }
  // non-string file entries are dropped, a missing `refused` means false
  assert.deepEqual(m.parseBuildAnswer({ files: ['a.awl', 7, null], message: 'ok' }), { files: ['a.awl'], unchanged: [], refused: false, message: 'ok' });
});

test('the build argument names a group or chart; none is the workspace', () => {
  assert.equal(m.buildTarget(undefined), 'the workspace');
  assert.equal(m.buildTarget([]), 'the workspace');
  assert.equal(m.buildTarget([{ kind: 'group', name: 'Anlage' }]), 'group Anlage');
  assert.equal(m.buildTarget([{ kind: 'chart', name: 'Dosierer' }]), 'chart Dosierer');
  assert.equal(m.buildTarget([{ kind: 'graph', name: 'X' }]), 'the workspace');
  assert.equal(m.BUILD_COMMAND, 'higraph.build');
  assert.equal(m.BUILD_WORKSPACE_COMMAND, 'higraph.buildWorkspace');
});
