// The shapes the server answers for tests, and how a result becomes what the Testing view
// shows (no `vscode` import, so it is unit-tested).
//
// `higraph/tests` lists the workspace's tests; `workspace/executeCommand higraph.runTest`
// answers one test's object of `higraph-lsp test --format json`, whose files are relative to
// the workspace root the server found (the folder of `higraph.toml`).

export const TESTS_METHOD = 'higraph/tests';
export const RUN_TEST_COMMAND = 'higraph.runTest';
export const SIMULATE_METHOD = 'higraph/simulate';

export interface LspPosition {
  line: number;
  character: number;
}

export interface LspRange {
  start: LspPosition;
  end: LspPosition;
}

/** One entry of `higraph/tests`. */
export interface TestEntry {
  name: string;
  uri: string;
  range: LspRange;
  nameRange: LspRange;
}

export interface TestList {
  tests: TestEntry[];
}

/** One failure of a `--format json` test object. */
export interface TestFailure {
  code: string;
  message: string;
  file: string;
  range: LspRange;
  cycle: number;
  time_ms: number;
  values: Record<string, unknown>;
}

/** A test object of `--format json`. */
export interface TestJson {
  name: string;
  file: string;
  range: LspRange;
  result: 'passed' | 'failed' | 'error';
  cycles: number;
  time_ms: number;
  failures: TestFailure[];
}

/** A failure placed in a file: its URI string, range and text. */
export interface PlacedMessage {
  uri: string;
  range: LspRange;
  message: string;
}

/** What the Testing view shows of a run. */
export interface Verdict {
  state: 'passed' | 'failed' | 'errored';
  messages: PlacedMessage[];
  /** A one-line summary, for the output of the run. */
  summary: string;
}

/**
 * The URI of a workspace-relative file, given the URI of the test's own file and its
 * workspace-relative name: the root is what precedes that name in the test's URI.
 */
export function fileUri(testUri: string, testFile: string, file: string): string {
  const suffix = '/' + testFile.split('/').map(encodeURIComponent).join('/');
  const plainSuffix = '/' + testFile;
  let root: string | undefined;
  if (testUri.endsWith(suffix)) root = testUri.slice(0, -suffix.length);
  else if (testUri.endsWith(plainSuffix)) root = testUri.slice(0, -plainSuffix.length);
  if (root === undefined) return testUri; // cannot tell: stay in the test's file
  return root + '/' + file.split('/').map(encodeURIComponent).join('/');
}

/** The verdict of a test's JSON object; failures are placed at their ranges (the `expect`). */
export function verdict(testUri: string, result: TestJson): Verdict {
  const state = result.result === 'passed' ? 'passed' : result.result === 'failed' ? 'failed' : 'errored';
  const messages = (result.failures ?? []).map((f) => ({
    uri: fileUri(testUri, result.file, f.file),
    range: f.range,
    message: `${f.code}: ${f.message}`,
  }));
  const cycles = `${result.cycles} cycle${result.cycles === 1 ? '' : 's'}, ${result.time_ms} ms`;
  const summary =
    state === 'passed'
      ? `test ${result.name} ... ok (${cycles})`
      : `test ${result.name} ... ${state === 'failed' ? 'FAILED' : 'ERROR'} (${cycles})${messages.map((m) => `\n  ${m.message}`).join('')}`;
  return { state, messages, summary };
}

/** The id of a test item: its file's URI and its name (names are case-insensitive). */
export function testId(uri: string, name: string): string {
  return `${uri}#${name.toUpperCase()}`;
}
