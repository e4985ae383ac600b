// The HiGraph extension: starts the `higraph-lsp` language server for .higraph files and
// adds the commands "HiGraph: Restart Server", "HiGraph: Show Graph Preview", "HiGraph:
// Play Test Trace" and "HiGraph: Build", and the tests of the workspace to the Testing view (testing.ts). Colouring
// (TextMate grammar), the language configuration and the snippets are declarative
// (package.json) and work without the server.
import * as vscode from 'vscode';
import {
  ExecuteCommandRequest,
  LanguageClient,
  State,
  type Executable,
  type LanguageClientOptions,
  type Location as LspLocation,
  type Position as LspPosition,
  type ServerOptions,
} from 'vscode-languageclient/node';
import { BUILD_COMMAND, buildTarget, describeBuild } from './build';
import { testAt } from './itemAtCursor';
import { GraphPreview, RENDER_METHOD, type RenderParams, type RenderResult } from './preview';
import type { Trace } from './previewPage';
import { resolveServer, ServerNotFoundError } from './serverPath';
import { TestExplorer } from './testing';
import { RUN_TEST_COMMAND, SIMULATE_METHOD, TESTS_METHOD, type TestJson, type TestList } from './testResult';

const CLIENT_ID = 'higraph'; // also the prefix of the setting `higraph.trace.server`
const CLIENT_NAME = 'HiGraph Language Server';

let client: LanguageClient | undefined;
let watchers: vscode.FileSystemWatcher[] = [];
let output: vscode.LogOutputChannel;
let preview: GraphPreview | undefined;
let explorer: TestExplorer | undefined;

/** The running client, or an error that says what to do. */
function runningClient(): LanguageClient {
  if (!client || client.state !== State.Running) {
    throw new Error(
      'The HiGraph language server is not running. See the "HiGraph" output channel, or run "HiGraph: Restart Server".',
    );
  }
  return client;
}
/** Serialises start/stop/restart so that two restarts never overlap. */
let lifecycle: Promise<void> = Promise.resolve();

export function activate(context: vscode.ExtensionContext): void {
  output = vscode.window.createOutputChannel('HiGraph', { log: true });
  context.subscriptions.push(output);

  preview = new GraphPreview(
    {
      render: async (params: RenderParams, token: vscode.CancellationToken): Promise<RenderResult> =>
        runningClient().sendRequest<RenderResult>(RENDER_METHOD, params, token),
      // (a token only when there is one: an `undefined` would be sent as a second parameter)
      simulate: async (params: { name: string; uri?: string }, token?: vscode.CancellationToken): Promise<Trace> =>
        token
          ? runningClient().sendRequest<Trace>(SIMULATE_METHOD, params, token)
          : runningClient().sendRequest<Trace>(SIMULATE_METHOD, params),
    },
    output,
  );
  context.subscriptions.push(preview);

  explorer = new TestExplorer(
    {
      listTests: async (token?: vscode.CancellationToken): Promise<TestList> =>
        token
          ? runningClient().sendRequest<TestList>(TESTS_METHOD, {}, token)
          : runningClient().sendRequest<TestList>(TESTS_METHOD, {}),
      runTest: async (uri: string, name: string, token?: vscode.CancellationToken): Promise<TestJson> => {
        const params = { command: RUN_TEST_COMMAND, arguments: [{ uri, name }] };
        return token
          ? runningClient().sendRequest(ExecuteCommandRequest.type, params, token)
          : runningClient().sendRequest(ExecuteCommandRequest.type, params);
      },
    },
    output,
  );
  context.subscriptions.push(explorer);

  context.subscriptions.push(
    vscode.commands.registerCommand('higraph.restartServer', () => queue(() => restart(context, true))),
    vscode.commands.registerCommand('higraph.showGraphPreview', () => preview?.show()),
    vscode.commands.registerCommand('higraph.playTrace', (arg?: unknown) => playTrace(arg)),
    vscode.commands.registerCommand('higraph.buildWorkspace', () => buildWorkspace()),
    // The count lenses' command: the server sends the arguments of `editor.action.showReferences`
    // in LSP types (URI, position, locations), converted here to VS Code's.
    vscode.commands.registerCommand('higraph.showReferences', (uri: string, position: LspPosition, locations: LspLocation[]) =>
      showReferences(uri, position, locations),
    ),
    vscode.workspace.onDidChangeConfiguration((e) => {
      if (e.affectsConfiguration('higraph.server.path')) {
        output.appendLine('higraph.server.path changed: restarting the server.');
        void queue(() => restart(context, false));
      } else if (e.affectsConfiguration('higraph.rulesBaseUri')) {
        output.appendLine('higraph.rulesBaseUri changed: restarting the server.');
        void queue(() => restart(context, false));
      }
    }),
  );

  void queue(() => start(context));
}

async function showReferences(uri: string, position: LspPosition, locations: LspLocation[]): Promise<void> {
  const convert = runningClient().protocol2CodeConverter;
  await vscode.commands.executeCommand(
    'editor.action.showReferences',
    convert.asUri(uri),
    convert.asPosition(position),
    (locations ?? []).map((location) => convert.asLocation(location)),
  );
}

export function deactivate(): Thenable<void> | undefined {
  return queue(stop);
}

function queue(step: () => Promise<void>): Promise<void> {
  lifecycle = lifecycle.then(step, step);
  return lifecycle;
}

async function start(context: vscode.ExtensionContext): Promise<void> {
  const setting = vscode.workspace.getConfiguration('higraph').get<string>('server.path', '');
  let command: string;
  try {
    const resolved = resolveServer({
      setting,
      extensionPath: context.extensionPath,
      workspaceFolder: vscode.workspace.workspaceFolders?.[0]?.uri.fsPath,
    });
    command = resolved.command;
    output.appendLine(`Starting ${command} (found ${describeSource(resolved.source)}).`);
  } catch (err) {
    if (err instanceof ServerNotFoundError) {
      output.appendLine(err.message);
      void showStartError(err.message, err.settingIsWrong);
      return;
    }
    throw err;
  }

  // stdio transport with no arguments: leaving `transport` unset makes the client talk over
  // stdin/stdout without adding `--stdio` to the command line
  const executable: Executable = { command, args: [] };
  const serverOptions: ServerOptions = { run: executable, debug: executable };

  // workspace/didChangeWatchedFiles for sources, the configuration and symbol-table imports
  watchers = ['**/*.higraph', '**/higraph.toml', '**/*.sdf'].map((glob) =>
    vscode.workspace.createFileSystemWatcher(glob),
  );
  // Where the rules' pages are (links on codes); empty: the server's own default.
  const rulesBaseUri = vscode.workspace.getConfiguration('higraph').get<string>('rulesBaseUri', '');
  const clientOptions: LanguageClientOptions = {
    documentSelector: [{ language: 'higraph' }],
    initializationOptions: rulesBaseUri ? { rulesBaseUri } : undefined,
    synchronize: { fileEvents: watchers },
    outputChannel: output,
    middleware: {
      // A click on the `▶ Run test` lens runs through the Testing view (results, gutter); the
      // code action "Build this group/chart" (`higraph.build` with an argument, registered by
      // the client because the server announces it) reports like "HiGraph: Build".
      executeCommand: async (command, args, next) => {
        if (command === RUN_TEST_COMMAND && explorer) return explorer.runFromLens(args[0], async () => next(command, args));
        if (command !== BUILD_COMMAND) return next(command, args);
        const what = buildTarget(args);
        try {
          const answer: unknown = await next(command, args);
          void showBuild(answer, what);
          return answer;
        } catch (err) {
          void showBuildError(err, what);
          return undefined;
        }
      },
    },
  };

  const newClient = new LanguageClient(CLIENT_ID, CLIENT_NAME, serverOptions, clientOptions);
  client = newClient;
  try {
    await newClient.start();
    output.appendLine('The HiGraph language server is running.');
    preview?.serverChanged();
    explorer?.serverChanged();
  } catch (err) {
    const message = `The HiGraph language server (${command}) could not be started: ${
      err instanceof Error ? err.message : String(err)
    }`;
    output.appendLine(message);
    void showStartError(message, false);
  }
}

async function stop(): Promise<void> {
  const old = client;
  client = undefined;
  if (!old) return;
  try {
    if (old.state !== State.Stopped) await old.stop(5000);
  } catch (err) {
    output.appendLine(`Stopping the server failed: ${err instanceof Error ? err.message : String(err)}`);
  }
  try {
    await old.dispose();
  } catch {
    // already disposed
  }
  for (const w of watchers) w.dispose();
  watchers = [];
}

async function restart(context: vscode.ExtensionContext, manual: boolean): Promise<void> {
  if (manual) output.appendLine('Restarting the HiGraph language server.');
  await stop();
  await start(context);
}

/**
 * "HiGraph: Play Test Trace": the test comes from the Testing view's context menu (a test
 * item), from the arguments `{ uri, name }`, from the test header above the cursor, or else
 * from a pick of the workspace's tests.
 */
async function playTrace(arg?: unknown): Promise<void> {
  let test: { name: string; uri?: string } | undefined;
  const item = arg as vscode.TestItem | { uri?: string; name?: string } | undefined;
  if (item && 'children' in item) {
    const entry = explorer?.entryOf(item as vscode.TestItem);
    if (entry) test = { name: entry.name, uri: entry.uri };
  } else if (item && typeof (item as { name?: unknown }).name === 'string') {
    const a = item as { uri?: string; name: string };
    test = { name: a.name, uri: a.uri };
  }
  const editor = vscode.window.activeTextEditor;
  if (!test && editor && editor.document.languageId === 'higraph') {
    const name = testAt(editor.document.getText(), editor.document.offsetAt(editor.selection.active));
    if (name) test = { name, uri: editor.document.uri.toString() };
  }
  if (!test) {
    const entries = explorer?.allEntries() ?? [];
    if (entries.length === 0) {
      void vscode.window.showInformationMessage('HiGraph: the workspace has no tests to play.');
      return;
    }
    const picked = await vscode.window.showQuickPick(
      entries.map((e) => ({ label: e.name, description: vscode.workspace.asRelativePath(vscode.Uri.parse(e.uri)), entry: e })),
      { placeHolder: 'The test whose trace to play' },
    );
    if (!picked) return;
    test = { name: picked.entry.name, uri: picked.entry.uri };
  }
  await preview?.play(test);
}

/**
 * "HiGraph: Build" (`higraph.buildWorkspace`): asks the server to build the whole workspace
 * (`higraph.build` without an argument: every target) and
 * shows its one-line summary; the "HiGraph" output channel lists the files written.
 */
async function buildWorkspace(): Promise<void> {
  const what = 'the workspace';
  // The command may be what activated the extension: let the server start first.
  await lifecycle;
  let running: LanguageClient;
  try {
    running = runningClient();
  } catch (err) {
    void showBuildError(err, what);
    return;
  }
  try {
    const answer: unknown = await vscode.window.withProgress(
      { location: vscode.ProgressLocation.Notification, title: `HiGraph: building ${what}`, cancellable: true },
      (_progress, token) =>
        running.sendRequest(ExecuteCommandRequest.type, { command: BUILD_COMMAND }, token),
    );
    await showBuild(answer, what);
  } catch (err) {
    await showBuildError(err, what);
  }
}

async function showBuild(answer: unknown, what: string): Promise<void> {
  const report = describeBuild(answer, what);
  for (const line of report.lines) output.appendLine(line);
  const showOutput = 'Show Output';
  const showProblems = 'Show Problems';
  const choice =
    report.severity === 'error'
      ? await vscode.window.showErrorMessage(report.notification, showProblems, showOutput)
      : await vscode.window.showInformationMessage(report.notification, showOutput);
  if (choice === showOutput) output.show(true);
  else if (choice === showProblems) await vscode.commands.executeCommand('workbench.actions.view.problems');
}

async function showBuildError(err: unknown, what: string): Promise<void> {
  const message = `building ${what} failed: ${err instanceof Error ? err.message : String(err)}`;
  output.appendLine(message);
  const showOutput = 'Show Output';
  if ((await vscode.window.showErrorMessage(`HiGraph: ${message}`, showOutput)) === showOutput) output.show(true);
}

function describeSource(source: string): string {
  switch (source) {
    case 'setting':
      return 'through the setting higraph.server.path';
    case 'bundled':
      return 'bundled with the extension';
    default:
      return 'on PATH';
  }
}

async function showStartError(message: string, settingIsWrong: boolean): Promise<void> {
  const openSettings = 'Open Settings';
  const showOutput = 'Show Output';
  const choice = await vscode.window.showErrorMessage(
    `HiGraph: ${message}`,
    ...(settingIsWrong ? [openSettings, showOutput] : [showOutput, openSettings]),
  );
  if (choice === openSettings) {
    await vscode.commands.executeCommand('workbench.action.openSettings', 'higraph.server.path');
  } else if (choice === showOutput) {
    output.show(true);
  }
}
