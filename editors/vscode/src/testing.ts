// HiGraph tests in VS Code's Testing view.
//
// Design: one TestController ("HiGraph") holds a file item per .higraph file with tests and a
// test item per `test`. The list comes from the server (custom request `higraph/tests`, every
// test of the workspace with its range); it is fetched when the server starts, when the view
// asks to refresh, and (debounced) after a .higraph document changes or is saved. Running an
// item sends `workspace/executeCommand higraph.runTest` and reads the answer, the test's
// `--format json` object: passed, failed (HG9901/HG9902) or errored (HG9903/HG9904), with
// each failure's message placed at its range (the `expect`, `until` or faulting statement).
// The server's `▶ Run test` code lens runs the same command; the extension intercepts it
// (language client middleware) and runs it through the controller, so a lens click also
// shows in the Testing view and the gutter.
import * as vscode from 'vscode';
import { describeError } from './previewPage';
import { testId, verdict, type LspRange, type TestEntry, type TestJson, type TestList } from './testResult';

/** What the explorer needs from the language client. */
export interface TestBackend {
  listTests(token?: vscode.CancellationToken): Promise<TestList>;
  runTest(uri: string, name: string, token?: vscode.CancellationToken): Promise<TestJson>;
}

const REFRESH_DELAY_MS = 600;

function range(r: LspRange): vscode.Range {
  return new vscode.Range(r.start.line, r.start.character, r.end.line, r.end.character);
}

/** The URI string VS Code uses for a URI string (the server may spell it differently). */
function canonical(uri: string): string {
  return vscode.Uri.parse(uri).toString();
}

export class TestExplorer implements vscode.Disposable {
  readonly controller: vscode.TestController;
  /** The server's entry of each test item, by item id. */
  private readonly entries = new Map<string, TestEntry>();
  private timer: ReturnType<typeof setTimeout> | undefined;
  private readonly disposables: vscode.Disposable[] = [];

  constructor(
    private readonly backend: TestBackend,
    private readonly output: vscode.OutputChannel,
  ) {
    this.controller = vscode.tests.createTestController('higraph', 'HiGraph');
    this.controller.refreshHandler = () => this.refresh();
    this.controller.createRunProfile('Run', vscode.TestRunProfileKind.Run, (request, token) => this.run(request, token), true);
    this.disposables.push(
      this.controller,
      vscode.workspace.onDidChangeTextDocument((e) => {
        if (e.document.languageId === 'higraph' && e.contentChanges.length > 0) this.schedule();
      }),
      vscode.workspace.onDidSaveTextDocument((d) => {
        if (d.languageId === 'higraph') this.schedule();
      }),
      vscode.workspace.onDidCreateFiles(() => this.schedule()),
      vscode.workspace.onDidDeleteFiles(() => this.schedule()),
      vscode.workspace.onDidRenameFiles(() => this.schedule()),
    );
  }

  /** Called after the server (re)started: list the tests again. */
  serverChanged(): void {
    this.schedule(0);
  }

  private schedule(delay = REFRESH_DELAY_MS): void {
    if (this.timer) clearTimeout(this.timer);
    this.timer = setTimeout(() => {
      this.timer = undefined;
      void this.refresh();
    }, delay);
  }

  /** Fetches the list of tests and rebuilds the tree (items keep their ids, so results stay). */
  async refresh(): Promise<void> {
    let list: TestList;
    try {
      list = await this.backend.listTests();
    } catch (err) {
      this.output.appendLine(`[tests] listing the tests failed: ${describeError(err)}`);
      return;
    }
    const files = new Map<string, vscode.TestItem>();
    this.entries.clear();
    for (const entry of list.tests ?? []) {
      const uri = vscode.Uri.parse(entry.uri);
      const fileId = uri.toString();
      let file = files.get(fileId);
      if (!file) {
        file = this.controller.createTestItem(fileId, vscode.workspace.asRelativePath(uri), uri);
        files.set(fileId, file);
      }
      const id = testId(fileId, entry.name);
      if (file.children.get(id)) continue; // a duplicate name (HG9002): the first one counts
      const item = this.controller.createTestItem(id, entry.name, uri);
      item.range = range(entry.range);
      file.children.add(item);
      this.entries.set(id, entry);
    }
    this.controller.items.replace([...files.values()]);
    this.output.appendLine(`[tests] ${this.entries.size} test(s) in ${files.size} file(s)`);
  }

  /** The test items a request covers, in order, without the excluded ones. */
  private collect(request: vscode.TestRunRequest): vscode.TestItem[] {
    const excluded = new Set((request.exclude ?? []).map((t) => t.id));
    const out: vscode.TestItem[] = [];
    const add = (item: vscode.TestItem) => {
      if (excluded.has(item.id)) return;
      if (this.entries.has(item.id)) out.push(item);
      else item.children.forEach(add);
    };
    if (request.include) request.include.forEach(add);
    else this.controller.items.forEach(add);
    return out;
  }

  private async run(request: vscode.TestRunRequest, token: vscode.CancellationToken): Promise<void> {
    const tests = this.collect(request);
    const run = this.controller.createTestRun(request);
    try {
      for (const item of tests) run.enqueued(item);
      for (const item of tests) {
        if (token.isCancellationRequested) {
          run.skipped(item);
          continue;
        }
        const entry = this.entries.get(item.id);
        if (!entry) continue;
        await this.runOne(run, item, () => this.backend.runTest(entry.uri, entry.name, token));
      }
    } finally {
      run.end();
    }
  }

  /** Runs one test through `execute` and reports it to `run`; returns the server's answer. */
  private async runOne(run: vscode.TestRun, item: vscode.TestItem, execute: () => Promise<unknown>): Promise<unknown> {
    run.started(item);
    const started = Date.now();
    let answer: unknown;
    try {
      answer = await execute();
    } catch (err) {
      run.errored(item, new vscode.TestMessage(describeError(err)), Date.now() - started);
      return undefined;
    }
    const duration = Date.now() - started;
    const result = answer as TestJson | undefined;
    if (!result || typeof result.result !== 'string') {
      run.errored(item, new vscode.TestMessage('the server answered higraph.runTest without a test result'), duration);
      return answer;
    }
    const uri = item.uri?.toString() ?? '';
    const v = verdict(uri, result);
    run.appendOutput(v.summary.replace(/\n/g, '\r\n') + '\r\n', undefined, item);
    const messages = v.messages.map((m) => {
      const message = new vscode.TestMessage(m.message);
      message.location = new vscode.Location(vscode.Uri.parse(m.uri), range(m.range));
      return message;
    });
    if (v.state === 'passed') run.passed(item, duration);
    else if (v.state === 'failed') run.failed(item, messages, duration);
    else run.errored(item, messages.length > 0 ? messages : [new vscode.TestMessage('the test could not run')], duration);
    return answer;
  }

  /**
   * A click on the server's code lens: runs the command through the Testing view when the
   * test is listed there, else simply runs it. Answers what the server answered.
   */
  async runFromLens(argument: unknown, execute: () => Promise<unknown>): Promise<unknown> {
    const arg = argument as { uri?: string; name?: string } | undefined;
    const item = arg?.uri && arg.name ? this.find(testId(canonical(arg.uri), arg.name)) : undefined;
    if (!item) return execute();
    const run = this.controller.createTestRun(new vscode.TestRunRequest([item]), `${item.label}`, false);
    try {
      return await this.runOne(run, item, execute);
    } finally {
      run.end();
    }
  }

  private find(id: string): vscode.TestItem | undefined {
    let found: vscode.TestItem | undefined;
    this.controller.items.forEach((file) => {
      found ??= file.children.get(id);
    });
    return found;
  }

  /** The server's entry of a test item (for the preview's trace player). */
  entryOf(item: vscode.TestItem): TestEntry | undefined {
    return this.entries.get(item.id);
  }

  /** Every listed test. */
  allEntries(): TestEntry[] {
    return [...this.entries.values()];
  }

  dispose(): void {
    if (this.timer) clearTimeout(this.timer);
    for (const d of this.disposables) d.dispose();
  }
}
