// "HiGraph: Show Graph Preview": a webview showing the SVG that the server renders for the
// graph, group or chart under the cursor (custom request `higraph/render`, params
// `{ name }`, result `{ svg }`). It follows the cursor and refreshes, debounced, when a
// .higraph document changes. The page is self-contained: no scripts, and a Content Security
// Policy that allows only inline styles and images from data: URIs (the SVG is shown as an
// <img> from a data: URI, so nothing in it can run).
//
// "HiGraph: Play Test Trace" turns the preview into a player: it fetches the trace of a test
// run (`higraph/simulate`) and shows the picture inline with a slider over the cycles and
// play/pause; each cycle highlights the active state of the chosen instance (a graph), the
// instances that changed state (a group) or the active steps (a chart), and the transitions
// that fired, found by the SVG's `data-` attributes. Only the page's own script runs (a
// nonce in the Content Security Policy). An edit of a .higraph file ends the playback (the
// trace no longer describes the files).
import * as vscode from 'vscode';
import { itemAt, type Item } from './itemAtCursor';
import { describeError, page, playerPage, RENDER_METHOD, type Trace } from './previewPage';
import { SIMULATE_METHOD } from './testResult';

export { RENDER_METHOD };

export interface RenderParams {
  name: string;
}

export interface RenderResult {
  svg: string;
}

/** What the preview needs from the language client (so it can restart underneath). */
export interface RenderBackend {
  /** Sends `higraph/render`; rejects with the server's error or when no server runs. */
  render(params: RenderParams, token: vscode.CancellationToken): Promise<RenderResult>;
  /** Sends `higraph/simulate`: the JSON trace of a test run. */
  simulate(params: { name: string; uri?: string }, token?: vscode.CancellationToken): Promise<Trace>;
}

function nonce(): string {
  let out = '';
  const chars = 'ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789';
  for (let i = 0; i < 32; i++) out += chars.charAt(Math.floor(Math.random() * chars.length));
  return out;
}

const REFRESH_DELAY_MS = 400;

export class GraphPreview implements vscode.Disposable {
  private panel: vscode.WebviewPanel | undefined;
  private target: Item | undefined;
  /** A document changed since the picture was drawn. */
  private dirty = false;
  private timer: ReturnType<typeof setTimeout> | undefined;
  private pending: vscode.CancellationTokenSource | undefined;
  private generation = 0;
  /** The trace being played, if any. */
  private trace: Trace | undefined;
  private readonly disposables: vscode.Disposable[] = [];

  constructor(
    private readonly backend: RenderBackend,
    private readonly output: vscode.OutputChannel,
  ) {
    this.disposables.push(
      // any .higraph document: a group's picture depends on the graphs in other files
      vscode.workspace.onDidChangeTextDocument((e) => {
        if (this.panel && e.document.languageId === 'higraph' && e.contentChanges.length > 0) {
          this.dirty = true;
          this.trace = undefined;
          this.schedule();
        }
      }),
      // the cursor may have moved into another item
      vscode.window.onDidChangeTextEditorSelection((e) => {
        if (this.panel && e.textEditor.document.languageId === 'higraph') this.schedule();
      }),
    );
  }

  /** The command: show (or reveal) the preview for the item under the cursor. */
  async show(): Promise<void> {
    const editor = vscode.window.activeTextEditor;
    if (!editor || editor.document.languageId !== 'higraph') {
      void vscode.window.showInformationMessage('HiGraph: open a .higraph file and put the cursor into a graph, group or chart.');
      return;
    }
    const item = this.itemOf(editor);
    if (!item) {
      void vscode.window.showInformationMessage('HiGraph: this file has no graph, group or chart to preview.');
      return;
    }
    this.target = item;
    this.trace = undefined;
    this.open(item);
    await this.refresh();
  }

  /**
   * Plays the trace of a test: fetches it, then shows the item under the cursor (when the
   * test runs it, or it is a graph) or else the first group or chart the test runs.
   */
  async play(test: { name: string; uri?: string }): Promise<void> {
    let trace: Trace;
    try {
      trace = await vscode.window.withProgress(
        { location: vscode.ProgressLocation.Window, title: `HiGraph: simulating test ${test.name}` },
        () => this.backend.simulate(test),
      );
    } catch (err) {
      void vscode.window.showErrorMessage(`HiGraph: cannot simulate test ${test.name}: ${describeError(err)}`);
      return;
    }
    if (!trace || !Array.isArray(trace.cycles)) {
      void vscode.window.showErrorMessage(`HiGraph: the server answered ${SIMULATE_METHOD} without a trace`);
      return;
    }
    const editor = vscode.window.activeTextEditor;
    const here = editor && editor.document.languageId === 'higraph' ? this.itemOf(editor) : undefined;
    const runs = (name: string) => trace.run.some((r) => r.toUpperCase() === name.toUpperCase());
    let item = here && (here.kind === 'graph' || runs(here.name)) ? here : undefined;
    if (!item) {
      const name = trace.run[0];
      if (!name) {
        void vscode.window.showInformationMessage(`HiGraph: test ${test.name} runs no group or chart`);
        return;
      }
      const isChart = (trace.cycles[0]?.charts ?? []).some((c) => c.chart.toUpperCase() === name.toUpperCase());
      item = { kind: isChart ? 'chart' : 'group', name, offset: 0 };
    }
    this.target = item;
    this.trace = trace;
    this.open(item);
    await this.refresh();
  }

  /** Creates or reveals the panel. */
  private open(item: Item): void {
    if (!this.panel) {
      this.panel = vscode.window.createWebviewPanel(
        'higraph.graphPreview',
        this.title(item),
        { viewColumn: vscode.ViewColumn.Beside, preserveFocus: true },
        // Scripts run only in the player page, whose CSP admits its own script by nonce.
        { enableScripts: true, enableCommandUris: false, localResourceRoots: [], retainContextWhenHidden: false },
      );
      this.panel.onDidDispose(() => {
        this.panel = undefined;
        this.pending?.cancel();
        if (this.timer) clearTimeout(this.timer);
      });
    } else {
      this.panel.reveal(undefined, true);
    }
  }

  /** Called after the server (re)started: draw again. */
  serverChanged(): void {
    if (this.panel) {
      this.dirty = true;
      this.schedule();
    }
  }

  private itemOf(editor: vscode.TextEditor): Item | undefined {
    const doc = editor.document;
    return itemAt(doc.getText(), doc.offsetAt(editor.selection.active));
  }

  private title(item: Item): string {
    return `Preview: ${item.kind} ${item.name}`;
  }

  /** Debounced: follow the cursor, and draw again when something changed. */
  private schedule(): void {
    if (this.timer) clearTimeout(this.timer);
    this.timer = setTimeout(() => {
      this.timer = undefined;
      const before = this.target;
      const editor = vscode.window.activeTextEditor;
      if (editor && editor.document.languageId === 'higraph') {
        this.target = this.itemOf(editor) ?? this.target;
      }
      const moved = this.target?.name !== before?.name || this.target?.kind !== before?.kind;
      if (this.dirty || moved) void this.refresh();
    }, REFRESH_DELAY_MS);
  }

  private async refresh(): Promise<void> {
    const panel = this.panel;
    const item = this.target;
    if (!panel || !item) return;
    this.dirty = false;
    panel.title = this.title(item);

    this.pending?.cancel();
    const cts = new vscode.CancellationTokenSource();
    this.pending = cts;
    const generation = ++this.generation;
    try {
      const result = await this.backend.render({ name: item.name }, cts.token);
      if (generation !== this.generation || !this.panel) return;
      if (!result || typeof result.svg !== 'string') {
        throw new Error(`the server answered ${RENDER_METHOD} without an "svg" string`);
      }
      panel.webview.html = this.trace ? playerPage(item, result.svg, this.trace, nonce()) : page(item, { svg: result.svg });
    } catch (err) {
      if (generation !== this.generation || !this.panel || cts.token.isCancellationRequested) return;
      const message = describeError(err);
      this.output.appendLine(`[preview] ${RENDER_METHOD} for ${item.kind} ${item.name} failed: ${message}`);
      panel.webview.html = page(item, { error: message });
    } finally {
      cts.dispose();
      if (this.pending === cts) this.pending = undefined;
    }
  }

  dispose(): void {
    if (this.timer) clearTimeout(this.timer);
    this.pending?.cancel();
    this.panel?.dispose();
    for (const d of this.disposables) d.dispose();
  }
}
