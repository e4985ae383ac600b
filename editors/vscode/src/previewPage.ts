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

/** What the player needs of a `higraph/simulate` trace (runtime.md §7). */
export interface Trace {
  test: string;
  result: string;
  cycle_ms: number;
  run: string[];
  cycles: Array<{
    cycle: number;
    time_ms: number;
    instances: Array<{
      group: string;
      instance: string;
      state: number;
      previous: number;
      fired: null | { kind: string; from: number | null; to: number; prio: number | null };
    }>;
    charts: Array<{
      chart: string;
      state: string;
      active: string[];
      fired: Array<{ sequencer: string; kind: string; name: string | null }>;
    }>;
    watch: Record<string, unknown>;
  }>;
}

/**
 * The `data-trans` key of a fired transition in a graph picture (`A->B:PRIO`, `any` for an
 * any- or startup transition, `return` for a return transition), or undefined when no
 * transition of the picture fired (the initial entry).
 */
export function firedKey(fired: Trace['cycles'][number]['instances'][number]['fired']): string | undefined {
  if (!fired || fired.kind === 'initial') return undefined;
  const from = fired.kind === 'any' || fired.kind === 'startup' ? 'any' : String(fired.from);
  const to = fired.kind === 'return' ? 'return' : String(fired.to);
  return `${from}->${to}${fired.prio === null || fired.prio === undefined ? '' : `:${fired.prio}`}`;
}

/** JSON that can stand inside a <script> element. */
function scriptJson(value: unknown): string {
  return JSON.stringify(value).replace(/</g, '\\u003c').replace(/\u2028/g, '\\u2028').replace(/\u2029/g, '\\u2029');
}

/**
 * The trace player: the SVG inline (so its `data-` attributes can be highlighted), a slider
 * over the cycles with play/pause, and for a graph a choice of the instance to follow. Only
 * the page's own script runs (its nonce); nothing in the SVG can.
 */
export function playerPage(item: Item, svg: string, trace: Trace, nonce: string): string {
  const csp = `default-src 'none'; img-src data:; style-src 'unsafe-inline'; script-src 'nonce-${nonce}';`;
  const heading = `${item.kind} ${escapeHtml(item.name)} — test ${escapeHtml(trace.test)} (${escapeHtml(trace.result)})`;
  // The SVG's own <script> elements, if any, are removed (the CSP would block them anyway).
  const picture = svg.replace(/<script[\s\S]*?<\/script>/gi, '').replace(/^<\?xml[^>]*>\s*/, '');
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
  .controls { display: flex; gap: 8px; align-items: center; flex-wrap: wrap; margin-bottom: 8px; }
  .controls input[type=range] { flex: 1; min-width: 160px; }
  #info { font-family: var(--vscode-editor-font-family, monospace); white-space: pre-wrap; margin: 0 0 8px 0; }
  .picture { background: #ffffff; border-radius: 4px; padding: 8px; display: inline-block; max-width: calc(100% - 16px); }
  .picture svg { max-width: 100%; height: auto; display: block; }
  .picture .active { fill: #ffe082; stroke: #e65100; stroke-width: 3; }
  .picture .fired { stroke: #d32f2f; stroke-width: 3.5; }
</style>
</head>
<body>
<h1>${heading}</h1>
<div class="controls">
  <button id="play" type="button">▶ Play</button>
  <input id="cycle" type="range" min="0" max="${trace.cycles.length}" value="0" aria-label="cycle">
  <span id="label"></span>
  <select id="instance" aria-label="instance"></select>
</div>
<pre id="info"></pre>
<div class="picture">${picture}</div>
<script id="trace" type="application/json">${scriptJson(trace)}</script>
<script nonce="${nonce}">${PLAYER_SCRIPT.replace('__KIND__', () => JSON.stringify(item.kind)).replace('__NAME__', () => scriptJson(item.name))}</script>
</body>
</html>`;
}

/** The player's script (runs in the webview). */
const PLAYER_SCRIPT = String.raw`
(() => {
  const kind = __KIND__;
  const name = __NAME__.toUpperCase();
  const trace = JSON.parse(document.getElementById('trace').textContent);
  const slider = document.getElementById('cycle');
  const label = document.getElementById('label');
  const info = document.getElementById('info');
  const select = document.getElementById('instance');
  const play = document.getElementById('play');
  const same = (a, b) => String(a).toUpperCase() === String(b).toUpperCase();
  const all = (attr) => [...document.querySelectorAll('.picture [data-' + attr + ']')];
  const first = trace.cycles[0] || { instances: [], charts: [] };
  if (kind === 'graph') {
    for (const i of first.instances) {
      const option = document.createElement('option');
      option.value = i.group + '.' + i.instance;
      option.textContent = i.group + '.' + i.instance;
      select.appendChild(option);
    }
  }
  select.hidden = kind !== 'graph' || select.options.length === 0;
  if (kind === 'graph') {
    // The trace does not say which instances are of this graph: start with the one whose
    // states the picture shows most often.
    const shown = new Set(all('state').map((el) => el.dataset.state));
    let best = 0, bestScore = -1;
    [...select.options].forEach((option, i) => {
      let score = 0;
      for (const c of trace.cycles) {
        const r = c.instances.find((x) => x.group + '.' + x.instance === option.value);
        if (r && shown.has(String(r.state))) score++;
      }
      if (score > bestScore) { best = i; bestScore = score; }
    });
    select.selectedIndex = best;
  }
  const firedKey = (f) => {
    if (!f || f.kind === 'initial') return undefined;
    const from = f.kind === 'any' || f.kind === 'startup' ? 'any' : String(f.from);
    const to = f.kind === 'return' ? 'return' : String(f.to);
    return from + '->' + to + (f.prio === null || f.prio === undefined ? '' : ':' + f.prio);
  };
  const show = (k) => {
    for (const el of document.querySelectorAll('.picture .active, .picture .fired')) el.classList.remove('active', 'fired');
    const c = k > 0 ? trace.cycles[k - 1] : undefined;
    label.textContent = c ? 'cycle ' + c.cycle + ' / ' + trace.cycles.length + ', t = ' + c.time_ms + ' ms' : 'before cycle 1';
    const lines = [];
    if (c && kind === 'graph') {
      const r = c.instances.find((i) => i.group + '.' + i.instance === select.value);
      if (r) {
        for (const el of all('state')) if (el.dataset.state === String(r.state)) el.classList.add('active');
        const key = firedKey(r.fired);
        if (key) for (const el of all('trans')) if (el.dataset.trans === key) el.classList.add('fired');
        lines.push(r.instance + ': state ' + r.state + ' (previous ' + r.previous + ')' + (r.fired ? ', fired ' + (key || r.fired.kind) : ''));
      }
    } else if (c && kind === 'group') {
      for (const r of c.instances) {
        if (!same(r.group, name)) continue;
        for (const el of all('instance')) {
          if (!same(el.dataset.instance, r.instance)) continue;
          el.classList.add(r.fired ? 'fired' : 'active');
        }
        lines.push(r.instance + ': state ' + r.state + (r.fired ? ' (fired ' + (firedKey(r.fired) || r.fired.kind) + ')' : ''));
      }
    } else if (c && kind === 'chart') {
      const r = c.charts.find((x) => same(x.chart, name));
      if (r) {
        for (const step of r.active) {
          const dot = step.indexOf('.');
          const seq = step.slice(0, dot), st = step.slice(dot + 1);
          for (const el of all('step')) if (same(el.dataset.sequencer, seq) && same(el.dataset.step, st)) el.classList.add('active');
        }
        for (const f of r.fired) {
          if (!f.name) continue;
          for (const el of all('trans')) if (same(el.dataset.sequencer, f.sequencer) && same(el.dataset.trans, f.name)) el.classList.add('fired');
        }
        lines.push(r.chart + ': ' + r.state + (r.active.length ? ', active ' + r.active.join(', ') : ''));
      }
    }
    const watch = c ? c.watch : (trace.initial && trace.initial.watch) || {};
    const values = Object.entries(watch || {}).map(([p, v]) => p + ' = ' + v);
    if (values.length) lines.push(values.join(', '));
    info.textContent = lines.join('\n');
  };
  let timer;
  const stop = () => { clearInterval(timer); timer = undefined; play.textContent = '▶ Play'; };
  play.addEventListener('click', () => {
    if (timer) return stop();
    if (Number(slider.value) >= trace.cycles.length) slider.value = '0';
    play.textContent = '⏸ Pause';
    timer = setInterval(() => {
      const next = Number(slider.value) + 1;
      if (next > trace.cycles.length) return stop();
      slider.value = String(next);
      show(next);
    }, 400);
  });
  slider.addEventListener('input', () => show(Number(slider.value)));
  select.addEventListener('change', () => show(Number(slider.value)));
  show(0);
})();
`;
