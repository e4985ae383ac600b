// Grammar tests: tokenizes every .higraph file of the repository's examples/ and of
// test/fixtures/ with the real engine (vscode-textmate + vscode-oniguruma) and compares the
// tokens with the snapshots in test/snapshots/ (one line per token: `text<TAB>scopes`).
//
//   npm test                        # compare
//   UPDATE_SNAPSHOTS=1 npm test     # write new / changed snapshots, delete obsolete ones
//
// With CI set, a missing snapshot is a failure too (never written).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { existsSync, mkdirSync, readdirSync, readFileSync, statSync, unlinkSync, writeFileSync } from 'node:fs';
import { join, relative, sep } from 'node:path';
import { extensionRoot, snapshot, tokenize } from './harness.mjs';
import { generate, grammarPath } from '../scripts/grammar.mjs';

const update = !!process.env.UPDATE_SNAPSHOTS && process.env.UPDATE_SNAPSHOTS !== '0';
const repoRoot = join(extensionRoot, '..', '..');
const snapshotDir = join(extensionRoot, 'test', 'snapshots');
const fixtureDir = join(extensionRoot, 'test', 'fixtures');
const examplesDir = join(repoRoot, 'examples');

function higraphFiles(dir) {
  if (!existsSync(dir)) return [];
  const out = [];
  for (const name of readdirSync(dir).sort()) {
    const p = join(dir, name);
    if (statSync(p).isDirectory()) out.push(...higraphFiles(p));
    else if (name.endsWith('.higraph')) out.push(p);
  }
  return out;
}

/** `examples/drilling/graphs/motor.higraph` -> `examples-drilling-graphs-motor.snap` */
function snapshotName(file, base, prefix) {
  const rel = relative(base, file).split(sep).join('-').replace(/\.higraph$/, '');
  return `${prefix}-${rel}.snap`;
}

const cases = [
  ...higraphFiles(examplesDir).map((f) => ({ file: f, snap: snapshotName(f, examplesDir, 'examples') })),
  ...higraphFiles(fixtureDir).map((f) => ({ file: f, snap: snapshotName(f, fixtureDir, 'fixtures') })),
];

test('the grammar JSON is generated from scripts/grammar.mjs', () => {
  assert.equal(
    readFileSync(grammarPath, 'utf8'),
    generate(),
    'syntaxes/higraph.tmLanguage.json is stale: edit scripts/grammar.mjs and run `npm run grammar`',
  );
});

test('there are example files and fixtures to tokenize', () => {
  assert.ok(cases.some((c) => c.snap.startsWith('examples-')), `no .higraph files under ${examplesDir}`);
  assert.ok(cases.some((c) => c.snap.startsWith('fixtures-')), `no .higraph files under ${fixtureDir}`);
});

for (const { file, snap } of cases) {
  test(`snapshot ${relative(repoRoot, file)}`, async () => {
    const actual = await snapshot(readFileSync(file, 'utf8'));
    const snapPath = join(snapshotDir, snap);
    if (update) {
      mkdirSync(snapshotDir, { recursive: true });
      if (!existsSync(snapPath) || readFileSync(snapPath, 'utf8') !== actual) writeFileSync(snapPath, actual);
      return;
    }
    assert.ok(
      existsSync(snapPath),
      `missing snapshot ${relative(extensionRoot, snapPath)}: run \`UPDATE_SNAPSHOTS=1 npm test\` and review it`,
    );
    const expected = readFileSync(snapPath, 'utf8');
    if (expected !== actual) {
      assert.equal(actual, expected, `tokens of ${relative(repoRoot, file)} differ from ${snap} (UPDATE_SNAPSHOTS=1 npm test to accept)`);
    }
  });
}

test('no obsolete snapshots', () => {
  if (!existsSync(snapshotDir)) return;
  const wanted = new Set(cases.map((c) => c.snap));
  const obsolete = readdirSync(snapshotDir).filter((n) => n.endsWith('.snap') && !wanted.has(n));
  if (update) {
    for (const n of obsolete) unlinkSync(join(snapshotDir, n));
    return;
  }
  assert.deepEqual(obsolete, [], 'snapshots without a source file (UPDATE_SNAPSHOTS=1 npm test deletes them)');
});

test('example files contain no invalid tokens', async () => {
  for (const file of higraphFiles(examplesDir)) {
    const lines = await tokenize(readFileSync(file, 'utf8'));
    lines.forEach((tokens, i) => {
      for (const t of tokens) {
        assert.ok(
          !t.scopes.some((s) => s.startsWith('invalid.') || s.includes('unclosed')),
          `${relative(repoRoot, file)}:${i + 1}: "${t.text}" is ${t.scopes.join(' ')}`,
        );
      }
    });
  }
});

// Independent of the snapshots: the scopes that matter, stated explicitly.

/** The innermost scope of the first token whose text is `text` (after trimming) on the only line of `source`. */
async function scopeOf(source, text, nth = 0) {
  const [tokens] = await tokenize(source);
  const hits = tokens.filter((t) => t.text.trim() === text);
  assert.ok(hits.length > nth, `"${text}" is not a token of: ${source}\n${tokens.map((t) => JSON.stringify(t.text)).join(' ')}`);
  return hits[nth].scopes.at(-1);
}

const expectations = [
  // [source line, token, expected innermost scope, nth occurrence]
  ['graph Ventil_2E "valve" <', 'graph', 'keyword.control.item.higraph'],
  ['graph Ventil_2E "valve" <', 'Ventil_2E', 'entity.name.type.graph.higraph'],
  ['  state 2 "Ab" < C: = #Ab; supervise T#10S; >', 'state', 'keyword.control.member.higraph'],
  ['  state 2 "Ab" < C: = #Ab; supervise T#10S; >', 'C:', 'entity.name.label.higraph'],
  ['  state 2 "Ab" < C: = #Ab; supervise T#10S; >', '=', 'support.function.stl.higraph'],
  ['  state 2 "Ab" < C: = #Ab; supervise T#10S; >', 'Ab', 'variable.other.local.higraph', 1],
  ['  state 2 "Ab" < C: = #Ab; supervise T#10S; >', 'supervise', 'keyword.control.statement.higraph'],
  ['  state 2 "Ab" < C: = #Ab; supervise T#10S; >', 'T#10S', 'constant.numeric.time.higraph'],
  ['  state 1 < C-: U E 1.0; X: R OM; E: S M 10.7; >', 'C-:', 'entity.name.label.higraph'],
  ['  state 1 < C-: U E 1.0; X: R OM; E: S M 10.7; >', 'X:', 'entity.name.label.higraph'],
  ['  state 1 < C-: U E 1.0; X: R OM; E: S M 10.7; >', 'E:', 'entity.name.label.higraph'],
  ['  state 1 < C-: U E 1.0; X: R OM; E: S M 10.7; >', 'E 1.0', 'variable.language.address.higraph'],
  ['  state 1 < C-: U E 1.0; X: R OM; E: S M 10.7; >', 'M 10.7', 'variable.language.address.higraph'],
  ['  trans 1->2 < U IM_Ab; !: R IM_Ab; >', '!:', 'entity.name.label.higraph'],
  ['  trans 1->2 < ?: U IM_Ab; >', '?:', 'entity.name.label.higraph'],
  ['  trans 1->2 < ?: U IM_Ab; >', 'U', 'support.function.stl.higraph'],
  ['  C: L MW10; T DB10.DBW 4; = DB10.DBX 5.1;', 'MW10', 'variable.language.address.higraph'],
  ['  C: L MW10; T DB10.DBW 4; = DB10.DBX 5.1;', 'T', 'support.function.stl.higraph'],
  ['  C: L MW10; T DB10.DBW 4; = DB10.DBX 5.1;', 'DB10.DBW 4', 'variable.language.address.higraph'],
  ['  C: L MW10; T DB10.DBW 4; = DB10.DBX 5.1;', 'DB10.DBX 5.1', 'variable.language.address.higraph'],
  ['  C: L T 5; L B#16#FF; L S5T#1H_1M_0S; L 2#0101; L C#998;', 'T 5', 'variable.language.address.higraph'],
  ['  C: L T 5; L B#16#FF; L S5T#1H_1M_0S; L 2#0101; L C#998;', 'B#16#FF', 'constant.numeric.hex.higraph'],
  ['  C: L T 5; L B#16#FF; L S5T#1H_1M_0S; L 2#0101; L C#998;', 'S5T#1H_1M_0S', 'constant.numeric.time.higraph'],
  ['  C: L T 5; L B#16#FF; L S5T#1H_1M_0S; L 2#0101; L C#998;', '2#0101', 'constant.numeric.binary.higraph'],
  ['  C: L T 5; L B#16#FF; L S5T#1H_1M_0S; L 2#0101; L C#998;', 'C#998', 'constant.numeric.bcd.higraph'],
  // international mnemonics: A is AND, A 1.0 is the SIMATIC output address
  ['  E: A I 1.0; = Q 4.0;', 'A', 'support.function.stl.higraph'],
  ['  E: A I 1.0; = Q 4.0;', 'I 1.0', 'variable.language.address.higraph'],
  ['  E: U A 1.0;', 'A 1.0', 'variable.language.address.higraph'],
  ['  Ventil_A : A 1.0 BOOL "valve";', 'A 1.0', 'variable.language.address.higraph'],
  ['  Ventil_A : A 1.0 BOOL "valve";', 'Ventil_A', 'entity.name.variable.higraph'],
  // STL comparisons at statement start; `>Init` is the end of the block
  ['  trans 1->2 < L 5; >I; >', '>I', 'support.function.stl.comparison.higraph'],
  ['  trans 1->2 < U x; >Init; >', '>', 'punctuation.section.block.end.higraph'],
  ['  C: U( ; O x; ) ; +I; RND+;', 'U(', 'support.function.stl.higraph'],
  ['  C: U( ; O x; ) ; +I; RND+;', ')', 'support.function.stl.higraph'],
  ['  C: U( ; O x; ) ; +I; RND+;', '+I', 'support.function.stl.higraph'],
  ['  C: U( ; O x; ) ; +I; RND+;', 'RND+', 'support.function.stl.higraph'],
  // strings, comments
  ['  state 0 "unclosed < >', 'unclosed < >', 'string.quoted.double.unclosed.higraph'],
  ['  x := \'A\';', 'A', 'string.quoted.single.higraph'],
  ['  U x; // a "comment" < >', 'a "comment" < >', 'comment.line.double-slash.higraph'],
  ['  // higraph-allow: HG2105', 'HG2105', 'constant.other.rule-code.higraph'],
  // keywords used as names stay names
  ['  in < start : BOOL; state : BOOL; >', 'start', 'entity.name.variable.higraph'],
  ['  in < start : BOOL; state : BOOL; >', 'in', 'keyword.control.section.higraph'],
  // charts
  ['chart type Mischer <', 'type', 'storage.modifier.chart-type.higraph'],
  ['chart type Mischer <', 'Mischer', 'entity.name.type.chart.higraph'],
  ['    trans T1 < Fuellstand > 10; >', 'T1', 'entity.name.function.transition.higraph'],
  ['    trans T1 < Fuellstand > 10; >', '>', 'keyword.operator.comparison.higraph'],
  ['    trans T1 < Fuellstand > 10; >', '>', 'punctuation.section.block.end.higraph', 1],
  ['    loop L1 -> START < Fuellstand < 5.0; >', 'START', 'entity.name.function.step.higraph'],
  ['    loop L1 -> START < Fuellstand < 5.0; >', '<', 'keyword.operator.comparison.higraph', 1],
  ['      run < Heizung := Temperatur < Soll_Temp; >', '<', 'keyword.operator.comparison.higraph', 1],
  ['      run < Heizung := Temperatur < Soll_Temp; >', 'run', 'keyword.control.section.higraph'],
  ['      L Ventil_Ab, T#30S;', 'T#30S', 'constant.numeric.time.higraph'],
  ['      N Heizung;', 'N', 'support.function.qualifier.higraph'],
  ['    start < Freigabe and not Aus; >', 'not', 'keyword.operator.logical.higraph'],
  ['    step START < max T#10M; confirm; >', 'START', 'entity.name.function.step.higraph'],
  ['  switching T;', 'T', 'constant.language.higraph'],
  // groups
  ['group Bohrmaschine fc FC1 db DB 1 <', 'fc', 'keyword.other.higraph'],
  ['group Bohrmaschine fc FC1 db DB 1 <', 'FC1', 'variable.language.address.block.higraph'],
  ['  instance Vorschub : Ventil_2E <', 'Ventil_2E', 'entity.name.type.graph.higraph'],
  ['  trans any->0 prio 1 "startup" < U INIT_SD; >', 'INIT_SD', 'support.variable.predefined.higraph'],
  ['  trans any->0 prio 1 "startup" < U INIT_SD; >', 'any', 'constant.language.higraph'],
];

test('scopes of the important tokens', async () => {
  for (const [source, text, scope, nth] of expectations) {
    assert.equal(await scopeOf(source, text, nth ?? 0), scope, `"${text}" in: ${source}`);
  }
});

test('an unclosed string ends at the end of its line', async () => {
  const lines = await tokenize('  state 0 "unclosed <\n  state 1 < C: = x; >\n');
  assert.ok(lines[1].every((t) => !t.scopes.some((s) => s.startsWith('string'))), 'the next line is not a string');
  assert.equal(lines[1].find((t) => t.text === 'state').scopes.at(-1), 'keyword.control.member.higraph');
});

test('a condition block left open does not colour the rest of the file', async () => {
  const lines = await tokenize('    trans T1 < Fuellstand > 10;\n    step S2 < >\n    step S3 < N x; >\n');
  assert.ok(lines[2].every((t) => !t.scopes.includes('meta.condition.higraph')), 'step S3 is outside the condition');
});
