// Finds the graph, group or chart that contains a position, from the text alone (the
// preview must work even when the server does not answer). Items do not nest, so the item
// under the cursor is the last item header that starts before it; before the first header,
// the first item of the file is taken.
//
// Comments and strings are blanked first, so `// graph X` or `"chart Y"` never count. A
// header is an item keyword followed by a name: `graph NAME`, `group NAME`, `chart NAME`,
// `chart type NAME` (`type` is the keyword only when a name follows it, so `chart type <`
// is a chart called `type`). A keyword used as a variable name (`graph : BOOL;`, `U graph;`)
// is not followed by a name and does not count.

export type ItemKind = 'graph' | 'group' | 'chart';

export interface Item {
  kind: ItemKind;
  name: string;
  /** Offset of the item keyword in the text. */
  offset: number;
}

/** Replaces the content of `//` comments and of `"..."` / `'...'` literals by spaces (same length). */
export function blankCommentsAndStrings(text: string): string {
  let out = '';
  let i = 0;
  const n = text.length;
  while (i < n) {
    const c = text[i];
    if (c === '/' && text[i + 1] === '/') {
      while (i < n && text[i] !== '\n' && text[i] !== '\r') {
        out += ' ';
        i++;
      }
    } else if (c === '"' || c === "'") {
      // a string ends at its closing quote or at the end of the line (no escapes; in a
      // character constant '' is one quote and simply reads as two adjacent literals)
      out += ' ';
      i++;
      while (i < n && text[i] !== c && text[i] !== '\n' && text[i] !== '\r') {
        out += ' ';
        i++;
      }
      if (i < n && text[i] === c) {
        out += ' ';
        i++;
      }
    } else {
      out += c;
      i++;
    }
  }
  return out;
}

const IDENT = String.raw`[\p{L}_][\p{L}\p{N}_]*`;
const HEADER = new RegExp(
  String.raw`(?<![\p{L}\p{N}_#.])(graph|group|chart)\s+(?:(type)\s+(?=[\p{L}_]))?(${IDENT})`,
  'giu',
);

/** All item headers of a text, in order. */
export function findItems(text: string): Item[] {
  const blank = blankCommentsAndStrings(text);
  const items: Item[] = [];
  for (const m of blank.matchAll(HEADER)) {
    const name = m[3];
    // `graph : BOOL` cannot match (a name must follow); `graph x := ...` is no header either
    const after = blank.slice((m.index ?? 0) + m[0].length);
    if (/^\s*:/.test(after)) continue;
    items.push({ kind: m[1].toLowerCase() as ItemKind, name, offset: m.index ?? 0 });
  }
  return items;
}

/** The graph, group or chart containing `offset`, or undefined when the text has none. */
export function itemAt(text: string, offset: number): Item | undefined {
  const items = findItems(text);
  let found: Item | undefined;
  for (const item of items) {
    if (item.offset <= offset) found = item;
    else break;
  }
  return found ?? items[0];
}

// After blanking, a test's description string is white space between its name and `<`.
const TEST_HEADER = new RegExp(String.raw`(?<![\p{L}\p{N}_#.])test\s+(${IDENT})\s*<`, 'giu');

/** The name of the `test` item whose header is the last one before `offset`, if any. */
export function testAt(text: string, offset: number): string | undefined {
  let found: string | undefined;
  for (const m of blankCommentsAndStrings(text).matchAll(TEST_HEADER)) {
    if ((m.index ?? 0) <= offset) found = m[1];
    else break;
  }
  return found;
}
