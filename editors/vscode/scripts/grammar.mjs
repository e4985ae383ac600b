#!/usr/bin/env node
// Source of the TextMate grammar `source.higraph`.
//
// The grammar is written here with readable regular expressions (String.raw, shared
// fragments, comments) and generated into ../syntaxes/higraph.tmLanguage.json:
//
//   npm run grammar          # regenerate the JSON
//
// `npm test` fails when the JSON is not what this script generates, so edit this file, not
// the JSON. The regular expressions are Oniguruma's (what VS Code runs).
//
// Design: the language's lexer is context-free and its blocks are `<` ... `>`, but `<` and `>`
// are also comparison operators in chart expressions, so the grammar does not try to match
// blocks (one wrong guess would colour the rest of the file wrongly). Instead it colours
// tokens from local context on one line:
//   * an STL operation is the first word of a statement: at the start of a line, after `;`
//     or `<`, or after a block label `E: C-: C: X: ?: !:`;
//   * item and member headers (`graph NAME`, `state 3 "x" fault`, `trans 1->2 prio 1 auto`,
//     `step NAME`, ...) are matched as a whole, so a keyword used as a name stays a name;
//   * inside the condition block of a chart transition / jump / loop / start and on the
//     right of `:=`, `<` `>` `<=` `>=` `<>` `=` are comparisons.
import { writeFileSync, readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { dirname, join } from 'node:path';

const r = String.raw;

// ---- shared fragments -------------------------------------------------------------------

/** An identifier (the language allows Unicode letters; HG0009 reports them). */
const ID = r`[\p{L}_][\p{L}\p{N}_]*`;
/** Not preceded by a character that would make the match part of a longer word/operand. */
const NB = r`(?<![\p{L}\p{N}_#.])`;
/** Not followed by an identifier character. */
const NA = r`(?![\p{L}\p{N}_])`;
/**
 * Start of a statement: start of the line, after `;` or `<`, or after a block label. The
 * match may then consume white space before the operation (the white space gets no scope).
 */
const SS = r`(?:^|(?<=[;<])|(?<=[^\p{L}\p{N}_#.][ECXecx]:|^[ECXecx]:|[?!]:|-:))`;

/** STL operations spelled as words, of both mnemonic sets (facts-stl.md §2.1). */
const STL_WORDS = [
  // bit logic, RLO, edges
  'UN', 'U', 'ON', 'O', 'XN', 'X', 'AN', 'SET', 'CLR', 'FP', 'FN', 'S', 'R',
  // word logic
  'UW', 'AW', 'OW', 'XOW', 'UD', 'AD', 'OD', 'XOD',
  // timers, counters, load (T and A are handled separately: they are also areas)
  'SI', 'SP', 'SV', 'SE', 'SS', 'SA', 'SF', 'SD', 'FR', 'LC', 'L', 'ZV', 'CU', 'ZR', 'CD',
  // address registers
  'TAR1', 'TAR2', 'TAR', 'CAR1', 'CAR2', 'CAR',
  // arithmetic
  'MOD', 'ABS', 'SQRT', 'SQR', 'EXP', 'LN', 'SIN', 'COS', 'TAN', 'ASIN', 'ACOS', 'ATAN',
  // shift / rotate
  'SLW', 'SRW', 'SLD', 'SRD', 'SSI', 'SSD', 'RLDA', 'RRDA', 'RLD', 'RRD',
  // accumulator
  'INC', 'DEC', 'TAK', 'PUSH', 'POP', 'TAD', 'CAD', 'TAW', 'CAW',
  // conversion
  'BTI', 'BTD', 'ITB', 'DTB', 'ITD', 'DTR', 'INVI', 'INVD', 'NEGI', 'NEGD', 'NEGR', 'TRUNC', 'RND',
  // calls
  'CALL', 'CC',
];

const TYPES = [
  'BOOL', 'BYTE', 'WORD', 'DWORD', 'INT', 'DINT', 'REAL', 'S5TIME', 'TIME_OF_DAY', 'TIME',
  'DATE_AND_TIME', 'DATE', 'TOD', 'DT', 'CHAR', 'STRING', 'TIMER', 'COUNTER', 'POINTER', 'ANY',
  'BLOCK_FC', 'BLOCK_FB', 'BLOCK_DB',
];

/** Predefined variables of every graph (language.md §3.1). */
const PREDEFINED = [
  'ManualMode', 'AutomaticMode', 'UsrMsgQuit', 'INIT_SD', 'CurrentState', 'PreviousState',
  'StateChange', 'ST_ExpiredPrev', 'ST_Expired', 'WT_Expired', 'ST_Stop', 'WT_Stop',
  'ST_CurrValue', 'WT_CurrValue', 'ST_Valid', 'WT_Valid', 'UsrMsgSend', 'UsrMsgStat',
];

const alt = (words) => words.join('|');

// ---- scopes -----------------------------------------------------------------------------

const S = {
  item: 'keyword.control.item.higraph',
  member: 'keyword.control.member.higraph',
  section: 'keyword.control.section.higraph',
  stmtKw: 'keyword.control.statement.higraph',
  other: 'keyword.other.higraph',
  attr: 'storage.modifier.attribute.higraph',
  type: 'storage.type.higraph',
  graphName: 'entity.name.type.graph.higraph',
  groupName: 'entity.name.type.group.higraph',
  chartName: 'entity.name.type.chart.higraph',
  stepName: 'entity.name.function.step.higraph',
  transName: 'entity.name.function.transition.higraph',
  seqName: 'entity.name.function.sequencer.higraph',
  actionName: 'entity.name.function.action.higraph',
  flow: 'keyword.control.flow.higraph',
  instName: 'entity.name.variable.instance.higraph',
  declName: 'entity.name.variable.higraph',
  label: 'entity.name.label.higraph',
  op: 'support.function.stl.higraph',
  // its own scope so that package.json can exclude it from bracket matching (`>I`)
  opCompare: 'support.function.stl.comparison.higraph',
  qualifier: 'support.function.qualifier.higraph',
  predefined: 'support.variable.predefined.higraph',
  address: 'variable.language.address.higraph',
  blockAddress: 'variable.language.address.block.higraph',
  local: 'variable.other.local.higraph',
  arrow: 'keyword.operator.arrow.higraph',
  assign: 'keyword.operator.assignment.higraph',
  comparison: 'keyword.operator.comparison.higraph',
  logical: 'keyword.operator.logical.higraph',
  arith: 'keyword.operator.arithmetic.higraph',
  number: 'constant.numeric.decimal.higraph',
  bool: 'constant.language.boolean.higraph',
  langConst: 'constant.language.higraph',
  option: 'support.constant.option.higraph',
};

// ---- rules ------------------------------------------------------------------------------

const repository = {
  comment: {
    patterns: [
      {
        // `// higraph-allow: HG2105, HG4xxx` (inline suppression, diagnostics.md §1.4b)
        begin: r`(//)\s*(?i:(higraph-allow))(:)`,
        beginCaptures: {
          1: { name: 'punctuation.definition.comment.higraph' },
          2: { name: 'keyword.other.directive.higraph' },
          3: { name: 'punctuation.separator.colon.higraph' },
        },
        end: r`$`,
        name: 'comment.line.double-slash.higraph',
        patterns: [
          { match: r`(?i)\bHG[0-9x]{4}\b`, name: 'constant.other.rule-code.higraph' },
        ],
      },
      {
        match: r`(//).*$`,
        name: 'comment.line.double-slash.higraph',
        captures: { 1: { name: 'punctuation.definition.comment.higraph' } },
      },
    ],
  },

  string: {
    patterns: [
      {
        // "a quoted name or text": no escapes, ends at the end of the line if unclosed (HG0004)
        match: r`(")[^"\r\n]*(")`,
        name: 'string.quoted.double.higraph',
        captures: {
          1: { name: 'punctuation.definition.string.begin.higraph' },
          2: { name: 'punctuation.definition.string.end.higraph' },
        },
      },
      {
        match: r`(")[^"\r\n]*$`,
        name: 'string.quoted.double.unclosed.higraph',
        captures: { 1: { name: 'punctuation.definition.string.begin.higraph' } },
      },
      {
        // character / string constant 'A', 'AB', '' '' is one quote
        match: r`(')(?:[^'\r\n]|'')*(')`,
        name: 'string.quoted.single.higraph',
        captures: {
          1: { name: 'punctuation.definition.string.begin.higraph' },
          2: { name: 'punctuation.definition.string.end.higraph' },
        },
      },
      {
        match: r`(')(?:[^'\r\n]|'')*$`,
        name: 'string.quoted.single.unclosed.higraph',
        captures: { 1: { name: 'punctuation.definition.string.begin.higraph' } },
      },
    ],
  },

  // ---- items ------------------------------------------------------------------------------
  items: {
    patterns: [
      {
        match: r`(?i)\b(mnemonic)\s+(simatic|international)\b`,
        captures: { 1: { name: S.item }, 2: { name: S.langConst } },
      },
      {
        match: r`(?i)\b(graph)\s+(${ID})`,
        captures: { 1: { name: S.item }, 2: { name: S.graphName } },
      },
      {
        // group NAME [fc block] [db block] ["comment"] <
        begin: r`(?i)\b(group)\s+(${ID})`,
        beginCaptures: { 1: { name: S.item }, 2: { name: S.groupName } },
        end: r`(?=<)|$`,
        patterns: [
          { include: '#comment' },
          { include: '#string' },
          { match: r`(?i)\b(fc|db)\b(?=\s+(?!\d))`, name: S.other },
          { include: '#address' },
        ],
      },
      {
        // chart [type] NAME — `type` is the keyword only when a name follows it
        match: r`(?i)\b(chart)\s+(?:(type)\s+(?=[\p{L}_]))?(${ID})`,
        captures: { 1: { name: S.item }, 2: { name: 'storage.modifier.chart-type.higraph' }, 3: { name: S.chartName } },
      },
      { match: r`(?i)\b(symbols)\b(?=\s*<)`, name: S.item },
      {
        // test NAME ["description"] <
        match: r`(?i)\b(test)\s+(${ID})(?=\s*(?:"[^"\r\n]*"\s*)?<)`,
        captures: { 1: { name: S.item }, 2: { name: 'entity.name.function.test.higraph' } },
      },
      { match: r`(?i)\b(block)\b(?=\s+[\p{L}_"])(?!\s*:)`, name: S.item },
    ],
  },

  // ---- members of graphs, groups and charts -------------------------------------------------
  members: {
    patterns: [
      {
        match: r`(?i)\b(in_out|in|out|stat)\b(?=\s*<)`,
        name: S.section,
      },
      {
        match: r`(?i)\b(msg)\s+(in|out)\b`,
        captures: { 1: { name: S.other }, 2: { name: 'storage.modifier.message.higraph' } },
      },
      {
        match: r`(?i)\b(activate)\b(?=\s+[\p{L}_])(?!\s*:)`,
        name: S.member,
      },
      { match: r`(?i)\b(permanent|parallel|alt|branch)\b(?=\s*<)`, name: S.member },
      {
        // state N ["name"] {fault | message} <
        begin: r`(?i)\b(state)\s+(\d+)`,
        beginCaptures: { 1: { name: S.member }, 2: { name: 'constant.numeric.integer.state.higraph' } },
        end: r`(?=[<;>])|$`,
        patterns: [
          { include: '#comment' },
          { include: '#string' },
          { match: r`(?i)\b(fault|message)\b`, name: S.attr },
        ],
      },
      {
        // trans A->B {prio N | auto | manual | waits | fault | "name"} <
        begin: r`(?i)\b(trans)\s+(?:(\d+)|(any|return))\s*(->)\s*(?:(\d+)|(any|return)\b)`,
        beginCaptures: {
          1: { name: S.member },
          2: { name: 'constant.numeric.integer.state.higraph' },
          3: { name: S.langConst },
          4: { name: S.arrow },
          5: { name: 'constant.numeric.integer.state.higraph' },
          6: { name: S.langConst },
        },
        end: r`(?=[<;>])|$`,
        patterns: [
          { include: '#comment' },
          { include: '#string' },
          { include: '#prio' },
          { match: r`(?i)\b(auto|manual|waits|fault)\b`, name: S.attr },
        ],
      },
      {
        // chart transition / jump / loop with its condition block on the same line
        begin: r`(?i)\b(?:(trans)\s+(${ID})|(jump|loop)\s+(${ID})\s*(->)\s*(${ID}))(\s*"[^"\r\n]*")?\s*(<)`,
        beginCaptures: {
          1: { name: S.member },
          2: { name: S.transName },
          3: { name: S.member },
          4: { name: S.transName },
          5: { name: S.arrow },
          6: { name: S.stepName },
          7: { patterns: [{ include: '#string' }] },
          8: { name: 'punctuation.section.block.begin.higraph' },
        },
        end: r`(?:^|(?<=[;<]))\s*(>)|(>)(?=\s*(?:$|//|>))`,
        endCaptures: {
          1: { name: 'punctuation.section.block.end.higraph' },
          2: { name: 'punctuation.section.block.end.higraph' },
        },
        name: 'meta.condition.higraph',
        patterns: [{ include: '#expression' }],
      },
      {
        // start < conditions >
        begin: r`(?i)\b(start)\s*(<)`,
        beginCaptures: { 1: { name: S.section }, 2: { name: 'punctuation.section.block.begin.higraph' } },
        end: r`(?:^|(?<=[;<]))\s*(>)|(>)(?=\s*(?:$|//|>))`,
        endCaptures: {
          1: { name: 'punctuation.section.block.end.higraph' },
          2: { name: 'punctuation.section.block.end.higraph' },
        },
        name: 'meta.condition.higraph',
        patterns: [{ include: '#expression' }],
      },
      {
        match: r`(?i)\b(trans)\s+(${ID})`,
        captures: { 1: { name: S.member }, 2: { name: S.transName } },
      },
      {
        match: r`(?i)\b(jump|loop)\s+(${ID})\s*(->)\s*(${ID})`,
        captures: { 1: { name: S.member }, 2: { name: S.transName }, 3: { name: S.arrow }, 4: { name: S.stepName } },
      },
      {
        match: r`(?i)\b(step)\s+(${ID})`,
        captures: { 1: { name: S.member }, 2: { name: S.stepName } },
      },
      {
        match: r`(?i)\b(sequencer)\s+(${ID})`,
        captures: { 1: { name: S.member }, 2: { name: S.seqName } },
      },
      {
        match: r`(?i)\b(instance)\s+(${ID})\s*(:)\s*(${ID})`,
        captures: {
          1: { name: S.member },
          2: { name: S.instName },
          3: { name: 'punctuation.separator.colon.higraph' },
          4: { name: S.graphName },
        },
      },
      {
        match: r`(?i)\b(option)\s+(${ID})`,
        captures: { 1: { name: S.member }, 2: { name: S.option } },
      },
      { include: '#prio' },
      // state items and step items
      { match: r`(?i)\b(wait|supervise|min|max)\b(?=\s+[^\s;:=])`, name: S.stmtKw },
      { match: r`(?i)\b(confirm)\b(?=\s*;)`, name: S.stmtKw },
      // test statements (at the start of a line; `step;` / `step N;` of a test)
      { match: r`(?i)^\s*\b(expect|until|set|cycle|command)\b(?=\s+[^\s;:=,)])`, captures: { 1: { name: S.stmtKw } } },
      { match: r`(?i)\b(within)\b(?=\s+T#)`, name: S.stmtKw },
      { match: r`(?i)^\s*\b(confirm)\b(?=\s+[^\s;])`, captures: { 1: { name: S.stmtKw } } },
      { match: r`(?i)^\s*\b(step)\b(?=\s*(?:\d+\s*)?;)`, captures: { 1: { name: S.stmtKw } } },
      {
        match: r`(?i)^\s*\b(restart)\s+(cold|warm)\b`,
        captures: { 1: { name: S.stmtKw }, 2: { name: S.langConst } },
      },
      // step phases and sequencer pre/post blocks
      { match: r`(?i)\b(init|run|term|pre|post)\b(?=\s*<)`, name: S.section },
      // chart properties
      {
        match: r`(?i)\b(mode)\s+(auto|manual)\b`,
        captures: { 1: { name: S.other }, 2: { name: S.langConst } },
      },
      {
        match: r`(?i)\b(profile)\s+(iec|pcs7)\b`,
        captures: { 1: { name: S.other }, 2: { name: S.langConst } },
      },
      // IEC charts (docs/iec.md): named actions and structured text
      {
        match: r`(?i)\b(action)\s+(${ID})(?=\s*(?:"[^"]*"\s*)?<)`,
        captures: { 1: { name: S.member }, 2: { name: S.actionName } },
      },
      { match: r`(?i)\b(IF|THEN|ELSIF|ELSE|END_IF|CASE|OF|END_CASE)\b(?!\s*(?::=|\.))`, name: S.flow },
      {
        match: r`(?i)\b(switching)\s+(T_or_B|T_and_B|T|B|step)\b`,
        captures: { 1: { name: S.other }, 2: { name: S.langConst } },
      },
      {
        match: r`(?i)\b(run)\s+(cyclic|time_monitoring|autostart)(?=\s*;)`,
        captures: { 1: { name: S.other }, 2: { name: S.option } },
      },
      // a test's run list: one or several groups and charts
      {
        match: r`(?i)^\s*\b(run)\b(?=\s+(?!(?:cyclic|time_monitoring|autostart)\s*;)${ID}\s*[,;])`,
        captures: { 1: { name: S.stmtKw } },
      },
    ],
  },

  prio: {
    match: r`(?i)\b(prio)\s+(-?\d+)`,
    captures: { 1: { name: S.other }, 2: { name: 'constant.numeric.integer.higraph' } },
  },

  label: {
    // block labels E: C-: C: X: ?: !: (`C:=` is the label C: followed by `=`)
    patterns: [
      { match: r`(?i)${NB}(?:C-|[ECX])(:)(?!:)`, name: S.label },
      { match: r`[?!](:)`, name: S.label },
    ],
  },

  // ---- STL -------------------------------------------------------------------------------
  operation: {
    patterns: [
      {
        // nesting: U( UN( O( ON( X( XN( A( AN( (white space before `(` allowed)
        match: r`(?i)${SS}\s*((?:[UOXA]N?)\s*\()`,
        captures: { 1: { name: S.op } },
      },
      {
        // comparisons ==I <>I >I <I >=I <=I (and D, R): the letter is a whole identifier
        match: r`(?i)${SS}\s*((?:==|<>|>=|<=|>|<)[IDR])${NA}`,
        captures: { 1: { name: S.opCompare } },
      },
      {
        // arithmetic +I -I *I /I, +D ..., +R ...
        match: r`(?i)${SS}\s*([-+*/][IDR])${NA}`,
        captures: { 1: { name: S.op } },
      },
      {
        // RND+ RND-, `+ constant`, `)` closing a nesting, `=` assignment
        match: r`(?i)${SS}\s*(RND[+-]|\+|\)|=(?!=))`,
        captures: { 1: { name: S.op } },
      },
      {
        // A (international AND) and T (transfer) are also address areas (`A 1.0`, `T 5`)
        match: r`(?i)${SS}\s*(A|T)\b(?!\s*[\d:.]|#)`,
        captures: { 1: { name: S.op } },
      },
      {
        // NOT takes no operand (a chart's `not x` is the logical operator)
        match: r`(?i)${SS}\s*(NOT)\b(?=\s*(?:;|//|$))`,
        captures: { 1: { name: S.op } },
      },
      {
        match: r`(?i)${SS}\s*(${alt(STL_WORDS)})\b(?!\s*[:.]|#)`,
        captures: { 1: { name: S.op } },
      },
      {
        // IEC action qualifiers of chart steps that are not STL operations (N P D DS SL);
        // S R L SD are coloured as the operations above
        match: r`(?i)${SS}\s*(N|P1|P0|P|DL|D|DS|SL)\b(?=\s+[\p{L}_"#])`,
        captures: { 1: { name: S.qualifier } },
      },
    ],
  },

  // ---- operands --------------------------------------------------------------------------
  'typed-constant': {
    patterns: [
      { match: r`(?i)\b(?:S5TIME|S5T|TIME|T)#-?[\p{N}][\p{L}\p{N}_.]*`, name: 'constant.numeric.time.higraph' },
      { match: r`(?i)\b(?:DATE_AND_TIME|DT|TIME_OF_DAY|TOD|DATE|D)#[\d:.\-]+`, name: 'constant.numeric.date.higraph' },
      { match: r`(?i)\b(?:BYTE|B)#\(\s*\d+(?:\s*,\s*\d+)*\s*\)`, name: 'constant.numeric.bytes.higraph' },
      { match: r`(?i)\b(?:(?:DWORD|WORD|BYTE|DW|W|B)#)?16#[\dA-F_]+`, name: 'constant.numeric.hex.higraph' },
      { match: r`(?i)\b2#[01_]+`, name: 'constant.numeric.binary.higraph' },
      { match: r`(?i)\bL#-?\d+`, name: 'constant.numeric.integer.higraph' },
      { match: r`(?i)\bC#\d+`, name: 'constant.numeric.bcd.higraph' },
      { match: r`(?i)\bP#[\p{L}\p{N}_.]*`, name: 'constant.other.pointer.higraph' },
      // any other `prefix#body` is still one typed-constant token for the lexer
      { match: r`(?i)\b(?:${ID}|\d+)#[^\s;,<>()\[\]"']*`, name: 'constant.numeric.other.higraph' },
    ],
  },

  address: {
    // absolute addresses of both mnemonic sets (language.md §3.5); the space after the area
    // is optional, there is none around the `.`
    patterns: [
      { match: r`(?i)${NB}DB\d+\.DB[XBWD]\s*\d+(?:\.\d+)?${NA}`, name: S.address },
      { match: r`(?i)${NB}(?:[EIAQML]|DBX|DIX)\s*\d+\.\d+${NA}`, name: S.address },
      { match: r`(?i)${NB}(?:P[EIAQ]|[EIAQML]|DB|DI)[BWD]\s*\d+${NA}(?!\.\d)`, name: S.address },
      { match: r`(?i)${NB}[TZC]\s*\d+${NA}(?!\.\d)`, name: S.address },
      { match: r`(?i)${NB}(?:OB|FB|FC|SFB|SFC|DB|UDT)\s*\d+${NA}(?!\.\d)`, name: S.blockAddress },
    ],
  },

  'local-variable': {
    match: r`(#)(${ID})`,
    captures: { 1: { name: 'punctuation.definition.variable.higraph' } },
    name: S.local,
  },

  words: {
    patterns: [
      { match: r`(?i)\b(?:TRUE|FALSE)\b(?!#)`, name: S.bool },
      { match: r`(?i)\b(?:${alt(TYPES)})\b(?!#)(?!\s*->)`, name: S.type },
      { match: r`(?i)\b(?:${alt(PREDEFINED)})\b`, name: S.predefined },
      { match: r`(?i)\b(?:and|or|xor|not)\b(?!\s*:)`, name: S.logical },
      { match: r`(?i)\bmod\b(?!\s*:)`, name: S.arith },
    ],
  },

  number: {
    // a `-` right before the digits belongs to the number unless it follows an operand
    match: r`(?:(?<![\p{L}\p{N}_)\]'"])-)?${NB}\d+(?:\.\d+)?(?:[eE][+-]?\d+)?${NA}`,
    name: S.number,
  },

  declaration: {
    // NAME : (a variable, a symbol, a formal of a block interface); not NAME :=
    match: r`${NB}(${ID})(?=\s*:(?!=))`,
    captures: { 1: { name: S.declName } },
  },

  operator: {
    patterns: [
      { match: r`:=`, name: S.assign },
      { match: r`->`, name: S.arrow },
      // `<>` right before the end of a line is an empty block, not a comparison
      { match: r`<>(?=\s*(?:$|//))`, name: 'punctuation.section.block.empty.higraph' },
      { match: r`<>|<=|>=`, name: S.comparison },
      { match: r`=`, name: S.comparison },
      { match: r`[-+*/]`, name: S.arith },
    ],
  },

  punctuation: {
    patterns: [
      { match: r`<`, name: 'punctuation.section.block.begin.higraph' },
      { match: r`>`, name: 'punctuation.section.block.end.higraph' },
      { match: r`;`, name: 'punctuation.terminator.statement.higraph' },
      { match: r`,`, name: 'punctuation.separator.comma.higraph' },
      { match: r`\.`, name: 'punctuation.accessor.higraph' },
      { match: r`:`, name: 'punctuation.separator.colon.higraph' },
      { match: r`[()]`, name: 'punctuation.parenthesis.higraph' },
      { match: r`[\[\]]`, name: 'punctuation.bracket.higraph' },
      { match: r`#`, name: 'punctuation.definition.variable.higraph' },
    ],
  },

  invalid: {
    // any character that is not a token of the language (HG0009); a leading BOM is trivia
    match: r`[^\s\p{L}\p{N}_<>;:,.()\[\]=\-+*/?!#"'\x{FEFF}]`,
    name: 'invalid.illegal.character.higraph',
  },

  // operands and operators of an expression (shared by the condition blocks and `:=`)
  operand: {
    patterns: [
      { include: '#comment' },
      { include: '#string' },
      { include: '#typed-constant' },
      { include: '#address' },
      { include: '#local-variable' },
      { include: '#words' },
      { include: '#number' },
    ],
  },

  // a chart condition block or the right-hand side of `:=`: `<` `>` compare
  expression: {
    patterns: [
      { include: '#comment' },
      { include: '#string' },
      { match: r`<>|<=|>=|<|>|=`, name: S.comparison },
      { include: '$self' },
    ],
  },

  assignment: {
    // NAME := value;  the value runs to `;`, or to a `>` that closes the block, or to the
    // end of the line
    begin: r`:=`,
    beginCaptures: { 0: { name: S.assign } },
    end: r`(?=;)|(?=>\s*(?:$|//|>|<))|$`,
    patterns: [{ include: '#expression' }],
  },
};

const grammar = {
  $schema: 'https://raw.githubusercontent.com/martinring/tmlanguage/master/tmlanguage.json',
  name: 'HiGraph',
  scopeName: 'source.higraph',
  fileTypes: ['higraph'],
  comment: 'Generated by scripts/grammar.mjs — edit that file, then run `npm run grammar`.',
  patterns: [
    { include: '#comment' },
    { include: '#string' },
    { include: '#items' },
    { include: '#members' },
    { include: '#label' },
    { include: '#operation' },
    { include: '#typed-constant' },
    { include: '#address' },
    { include: '#local-variable' },
    { include: '#words' },
    { include: '#number' },
    { include: '#declaration' },
    { include: '#assignment' },
    { include: '#operator' },
    { include: '#punctuation' },
    { include: '#invalid' },
  ],
  repository,
};

export function generate() {
  return JSON.stringify(grammar, null, 2) + '\n';
}

export const grammarPath = join(dirname(fileURLToPath(import.meta.url)), '..', 'syntaxes', 'higraph.tmLanguage.json');

if (process.argv[1] && fileURLToPath(import.meta.url) === process.argv[1]) {
  const text = generate();
  let old = null;
  try {
    old = readFileSync(grammarPath, 'utf8');
  } catch {
    // first generation
  }
  if (old === text) {
    console.log(`${grammarPath} is up to date`);
  } else {
    writeFileSync(grammarPath, text);
    console.log(`wrote ${grammarPath}`);
  }
}
