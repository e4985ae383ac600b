// Checks of the declarative parts: package.json contributions, the language configuration
// and the snippets (expanded with their default texts, they tokenize without invalid tokens).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { existsSync, readFileSync } from 'node:fs';
import { join } from 'node:path';
import { extensionRoot, tokenize } from './harness.mjs';

const read = (p) => JSON.parse(readFileSync(join(extensionRoot, p), 'utf8'));
const pkg = read('package.json');

test('package.json: identity, engine, activation, entry point', () => {
  assert.equal(pkg.name, 'higraph');
  assert.ok(pkg.publisher);
  assert.ok(pkg.repository);
  assert.equal(pkg.engines.vscode, '^1.91.0');
  assert.deepEqual(pkg.activationEvents, ['onLanguage:higraph']);
  assert.equal(pkg.main, './dist/extension.js');
  assert.deepEqual(pkg.categories, ['Programming Languages', 'Linters', 'Formatters']);
  assert.equal(pkg.devDependencies['@vscode/vsce'], '3.9.2');
  assert.equal(pkg.devDependencies['@types/vscode'], '1.91.0');
  assert.ok(existsSync(join(extensionRoot, 'LICENSE')));
  assert.ok(existsSync(join(extensionRoot, pkg.icon)));
});

test('package.json: language, grammar, snippets', () => {
  const c = pkg.contributes;
  assert.deepEqual(c.languages.map((l) => [l.id, l.extensions]), [['higraph', ['.higraph']]]);
  assert.ok(existsSync(join(extensionRoot, c.languages[0].configuration)));
  assert.deepEqual(c.grammars.map((g) => [g.language, g.scopeName]), [['higraph', 'source.higraph']]);
  assert.equal(read(c.grammars[0].path).scopeName, 'source.higraph');
  // `->`, chart comparisons and `>I` contain `<`/`>` but are no brackets
  assert.deepEqual(c.grammars[0].unbalancedBracketScopes, [
    'keyword.operator.arrow.higraph',
    'keyword.operator.comparison.higraph',
    'support.function.stl.comparison.higraph',
  ]);
  assert.ok(existsSync(join(extensionRoot, c.snippets[0].path)));
});

test('package.json: settings and commands', () => {
  const props = pkg.contributes.configuration.properties;
  assert.equal(props['higraph.server.path'].type, 'string');
  assert.equal(props['higraph.server.path'].default, '');
  assert.deepEqual(props['higraph.trace.server'].enum, ['off', 'messages', 'verbose']);
  assert.equal(props['higraph.trace.server'].default, 'off');
  const titles = Object.fromEntries(pkg.contributes.commands.map((c) => [c.command, `${c.category}: ${c.title}`]));
  assert.deepEqual(titles, {
    'higraph.restartServer': 'HiGraph: Restart Server',
    'higraph.showGraphPreview': 'HiGraph: Show Graph Preview',
    'higraph.playTrace': 'HiGraph: Play Test Trace',
    'higraph.buildWorkspace': 'HiGraph: Build',
    // the command of the count lenses (hidden from the palette): opens the references view
    'higraph.showReferences': 'HiGraph: Show References',
  });
  // the palette's build command must not be the server's `higraph.build`: the language client
  // registers that one itself (the server announces it), and a second registration fails
  assert.ok(!('higraph.build' in titles));
  // every command registered in the sources is declared, and the other way round
  const source = readFileSync(join(extensionRoot, 'src', 'extension.ts'), 'utf8');
  const registered = [...source.matchAll(/registerCommand\('([^']+)'/g)].map((m) => m[1]).sort();
  assert.deepEqual(registered, Object.keys(titles).sort());
  assert.deepEqual(pkg.contributes.menus['testing/item/context'].map((m) => m.command), ['higraph.playTrace']);
});

test('language configuration: comments, brackets, indentation', () => {
  const lc = read('language-configuration.json');
  assert.equal(lc.comments.lineComment, '//');
  assert.deepEqual(lc.brackets, [['<', '>'], ['(', ')'], ['[', ']']]);
  assert.ok(lc.autoClosingPairs.some((p) => p.open === '"' && p.close === '"'));
  const inc = new RegExp(lc.indentationRules.increaseIndentPattern);
  const dec = new RegExp(lc.indentationRules.decreaseIndentPattern);
  for (const line of ['graph X "v" <', '  state 1 <', '  trans 1->2 prio 1 <  // comment']) assert.ok(inc.test(line), line);
  for (const line of ['  state 1 < C: = x; >', '  U x; // a <']) assert.ok(!inc.test(line), line);
  for (const line of ['>', '  >', '  > // end']) assert.ok(dec.test(line), line);
  for (const line of ['  >I ;', '  >=D;', '  U x;']) assert.ok(!dec.test(line), line);
  new RegExp(lc.wordPattern); // compiles
});

/** A snippet body with every placeholder replaced by its default (or first choice). */
function expand(body) {
  let text = body.join('\n');
  for (let i = 0; i < 5; i++) {
    text = text
      .replace(/\$\{\d+\|([^,|]*)[^|]*\|\}/g, '$1')
      .replace(/\$\{\d+:([^{}]*)\}/g, '$1')
      .replace(/\$\d+/g, '');
  }
  return text.replace(/\t/g, '  ');
}

test('snippets: the expected ones, and they tokenize cleanly', async () => {
  const snippets = read('snippets/higraph.json');
  assert.deepEqual(
    Object.values(snippets).map((s) => s.prefix).sort(),
    ['block', 'chart', 'graph', 'group', 'instance', 'state', 'step', 'symbols', 'trans'],
  );
  for (const [name, s] of Object.entries(snippets)) {
    const text = expand(s.body);
    assert.ok(!/\$\{|\$\d/.test(text), `${name}: unexpanded placeholder in\n${text}`);
    const lines = await tokenize(text);
    for (const t of lines.flat()) {
      assert.ok(!t.scopes.some((sc) => sc.startsWith('invalid') || sc.includes('unclosed')), `${name}: ${t.text} ${t.scopes}`);
    }
  }
});
