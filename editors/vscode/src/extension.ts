// The HiGraph extension: starts the `higraph-lsp` language server for .higraph files and
// adds the commands "HiGraph: Restart Server" and "HiGraph: Show Graph Preview". Colouring
// (TextMate grammar), the language configuration and the snippets are declarative
// (package.json) and work without the server.
import * as vscode from 'vscode';
import {
  LanguageClient,
  State,
  type Executable,
  type LanguageClientOptions,
  type ServerOptions,
} from 'vscode-languageclient/node';
import { GraphPreview, RENDER_METHOD, type RenderParams, type RenderResult } from './preview';
import { resolveServer, ServerNotFoundError } from './serverPath';

const CLIENT_ID = 'higraph'; // also the prefix of the setting `higraph.trace.server`
const CLIENT_NAME = 'HiGraph Language Server';

let client: LanguageClient | undefined;
let watchers: vscode.FileSystemWatcher[] = [];
let output: vscode.LogOutputChannel;
let preview: GraphPreview | undefined;
/** Serialises start/stop/restart so that two restarts never overlap. */
let lifecycle: Promise<void> = Promise.resolve();

export function activate(context: vscode.ExtensionContext): void {
  output = vscode.window.createOutputChannel('HiGraph', { log: true });
  context.subscriptions.push(output);

  preview = new GraphPreview(
    {
      render: async (params: RenderParams, token: vscode.CancellationToken): Promise<RenderResult> => {
        if (!client || client.state !== State.Running) {
          throw new Error(
            'The HiGraph language server is not running. See the "HiGraph" output channel, or run "HiGraph: Restart Server".',
          );
        }
        return client.sendRequest<RenderResult>(RENDER_METHOD, params, token);
      },
    },
    output,
  );
  context.subscriptions.push(preview);

  context.subscriptions.push(
    vscode.commands.registerCommand('higraph.restartServer', () => queue(() => restart(context, true))),
    vscode.commands.registerCommand('higraph.showGraphPreview', () => preview?.show()),
    vscode.workspace.onDidChangeConfiguration((e) => {
      if (e.affectsConfiguration('higraph.server.path')) {
        output.appendLine('higraph.server.path changed: restarting the server.');
        void queue(() => restart(context, false));
      }
    }),
  );

  void queue(() => start(context));
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
  const clientOptions: LanguageClientOptions = {
    documentSelector: [{ language: 'higraph' }],
    synchronize: { fileEvents: watchers },
    outputChannel: output,
  };

  const newClient = new LanguageClient(CLIENT_ID, CLIENT_NAME, serverOptions, clientOptions);
  client = newClient;
  try {
    await newClient.start();
    output.appendLine('The HiGraph language server is running.');
    preview?.serverChanged();
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
