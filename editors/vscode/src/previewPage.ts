// The preview's web page and error texts (no `vscode` import, so it is unit-tested).
import type { Item } from './itemAtCursor';

export const RENDER_METHOD = 'higraph/render';

/** A readable message for an error of the request, including JSON-RPC error codes. */
export function describeError(err: unknown): string {
  const e = err as { code?: number; message?: string } | undefined;
  if (e && typeof e.code === 'number') {
    if (e.code === -32601) {
      return `The language server does not support ${RENDER_METHOD} (yet): MethodNotFound. Update higraph-lsp.`;
    }
    return `${e.message ?? String(err)} (error ${e.code})`;
  }
  if (e && typeof e.message === 'string') return e.message;
  return String(err);
}

function escapeHtml(s: string): string {
  return s.replace(/[&<>"']/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;', "'": '&#39;' })[c] as string);
}

/** The webview page: the SVG as an image from a data: URI, or the error. */
export function page(item: Item, content: { svg: string } | { error: string }): string {
  const csp = "default-src 'none'; img-src data:; style-src 'unsafe-inline';";
  const heading = `${item.kind} ${escapeHtml(item.name)}`;
  const body =
    'svg' in content
      ? `<div class="picture"><img alt="${heading}" src="data:image/svg+xml;base64,${Buffer.from(content.svg, 'utf8').toString('base64')}"></div>`
      : `<div class="error"><strong>No preview for ${heading}.</strong><p>${escapeHtml(content.error)}</p></div>`;
  return `<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="UTF-8">
<meta http-equiv="Content-Security-Policy" content="${csp}">
<meta name="viewport" content="width=device-width, initial-scale=1.0">
<title>${heading}</title>
<style>
  body { margin: 0; padding: 12px; font-family: var(--vscode-font-family, sans-serif); color: var(--vscode-foreground); background: var(--vscode-editor-background); }
  h1 { font-size: 1.05em; font-weight: 600; margin: 0 0 10px 0; }
  .picture { background: #ffffff; border-radius: 4px; padding: 8px; display: inline-block; max-width: calc(100% - 16px); }
  .picture img { max-width: 100%; height: auto; display: block; }
  .error { border-left: 3px solid var(--vscode-editorError-foreground, #e51400); padding: 4px 12px; }
  .error p { white-space: pre-wrap; font-family: var(--vscode-editor-font-family, monospace); }
</style>
</head>
<body>
<h1>${heading}</h1>
${body}
</body>
</html>`;
}
