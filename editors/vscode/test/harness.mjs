// Tokenizes text with the extension's TextMate grammar using the engine VS Code runs
// (vscode-textmate + vscode-oniguruma). Shared by the grammar tests and the screenshot script.
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import vsctm from 'vscode-textmate';
import oniguruma from 'vscode-oniguruma';

const require = createRequire(import.meta.url);
export const extensionRoot = join(dirname(fileURLToPath(import.meta.url)), '..');
export const grammarFile = join(extensionRoot, 'syntaxes', 'higraph.tmLanguage.json');

let grammarPromise;

/** The `source.higraph` grammar, loaded once. */
export function loadGrammar() {
  grammarPromise ??= (async () => {
    const wasm = readFileSync(join(dirname(require.resolve('vscode-oniguruma')), 'onig.wasm'));
    await oniguruma.loadWASM(wasm.buffer.slice(wasm.byteOffset, wasm.byteOffset + wasm.byteLength));
    const registry = new vsctm.Registry({
      onigLib: Promise.resolve({
        createOnigScanner: (patterns) => new oniguruma.OnigScanner(patterns),
        createOnigString: (s) => new oniguruma.OnigString(s),
      }),
      loadGrammar: async (scopeName) => {
        if (scopeName !== 'source.higraph') return null;
        return vsctm.parseRawGrammar(readFileSync(grammarFile, 'utf8'), grammarFile);
      },
    });
    const grammar = await registry.loadGrammar('source.higraph');
    if (!grammar) throw new Error('grammar source.higraph did not load');
    return grammar;
  })();
  return grammarPromise;
}

/**
 * Tokenizes `text` line by line, as VS Code does.
 * @returns {Promise<Array<Array<{text: string, scopes: string[]}>>>} tokens per line
 */
export async function tokenize(text) {
  const grammar = await loadGrammar();
  let ruleStack = vsctm.INITIAL;
  const lines = text.split(/\r\n|\r|\n/);
  const out = [];
  for (const line of lines) {
    const result = grammar.tokenizeLine(line, ruleStack, 5000);
    if (result.stoppedEarly) throw new Error(`tokenizing stopped early (time limit) on line: ${line}`);
    const tokens = [];
    for (let i = 0; i < result.tokens.length; i++) {
      const t = result.tokens[i];
      const end = i + 1 < result.tokens.length ? result.tokens[i + 1].startIndex : line.length;
      tokens.push({ text: line.slice(t.startIndex, end), scopes: t.scopes });
    }
    out.push(tokens);
    ruleStack = result.ruleStack;
  }
  return out;
}

/**
 * The snapshot text of a file: one line per token, `text<TAB>scopes` (scopes separated by
 * spaces, outermost first, the root `source.higraph` left out; `-` when it is the only one).
 * Tokens of white space only are left out (they carry no colour), and an empty line separates the source lines, so
 * a diff points at the right place.
 */
export async function snapshot(text) {
  const lines = await tokenize(text);
  const out = [];
  lines.forEach((tokens, i) => {
    if (i > 0) out.push('');
    for (const t of tokens) {
      if (/^\s*$/.test(t.text)) continue;
      const scopes = t.scopes.filter((s) => s !== 'source.higraph');
      // white space around an uncoloured token carries no information: trim it
      const text = scopes.length ? t.text : t.text.trim();
      const shown = text.replace(/\\/g, '\\\\').replace(/\t/g, '\\t');
      out.push(`${shown}\t${scopes.length ? scopes.join(' ') : '-'}`);
    }
  });
  return out.join('\n') + '\n';
}
