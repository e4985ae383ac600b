// "HiGraph: Show Graph Preview": a webview showing the SVG that the server renders for the
// graph, group or chart under the cursor (custom request `higraph/render`, params
// `{ name }`, result `{ svg }`). It follows the cursor and refreshes, debounced, when a
// .higraph document changes. The page is self-contained: no scripts, and a Content Security
// Policy that allows only inline styles and images from data: URIs (the SVG is shown as an
// <img> from a data: URI, so nothing in it can run).
import * as vscode from 'vscode';
import { itemAt, type Item } from './itemAtCursor';
import { describeError, page, RENDER_METHOD } from './previewPage';

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
    if (!this.panel) {
      this.panel = vscode.window.createWebviewPanel(
        'higraph.graphPreview',
        this.title(item),
        { viewColumn: vscode.ViewColumn.Beside, preserveFocus: true },
        { enableScripts: false, enableCommandUris: false, localResourceRoots: [], retainContextWhenHidden: false },
      );
      this.panel.onDidDispose(() => {
        this.panel = undefined;
        this.pending?.cancel();
        if (this.timer) clearTimeout(this.timer);
      });
    } else {
      this.panel.reveal(undefined, true);
    }
    await this.refresh();
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
      panel.webview.html = page(item, { svg: result.svg });
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
