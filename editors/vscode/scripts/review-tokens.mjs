// A compact view of how the grammar tokenizes a file, for reviewing snapshot changes: each
// source line, then its tokens as text[scopes] (the `.higraph` suffix left out).
//   node scripts/review-tokens.mjs FILE.higraph
import { tokenize } from '../test/harness.mjs';
import { readFileSync } from 'node:fs';
const text = readFileSync(process.argv[2], 'utf8');
const lines = await tokenize(text);
const src = text.split(/\r?\n/);
lines.forEach((toks, i) => {
  console.log(`${String(i+1).padStart(3)}| ${src[i]}`);
  const parts = toks.filter(t => t.text.trim()).map(t => {
    const sc = t.scopes.slice(1).map(s => s.replace('.higraph','')).join(' ');
    return sc ? `${t.text.trim()}[${sc}]` : t.text.trim();
  });
  console.log('   > ' + parts.join('  '));
});
