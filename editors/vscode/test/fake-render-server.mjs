#!/usr/bin/env node
// A stand-in language server for the end-to-end check of the graph preview: it speaks just
// enough LSP over stdio (initialize, shutdown, exit) and answers `higraph/render` with a small
// SVG naming the requested item. Every other request gets MethodNotFound.
let buffer = Buffer.alloc(0);

function send(message) {
  const body = Buffer.from(JSON.stringify({ jsonrpc: '2.0', ...message }), 'utf8');
  process.stdout.write(`Content-Length: ${body.length}\r\n\r\n`);
  process.stdout.write(body);
}

function svgFor(name) {
  const esc = String(name).replace(/[&<>"]/g, (c) => `&#${c.charCodeAt(0)};`);
  return `<svg xmlns="http://www.w3.org/2000/svg" width="360" height="120" viewBox="0 0 360 120">
<circle cx="60" cy="60" r="40" fill="none" stroke="#0f4c81" stroke-width="4"/>
<text x="60" y="68" font-size="24" text-anchor="middle" fill="#0f4c81">0</text>
<text x="120" y="68" font-size="22" fill="#000">fake render of ${esc}</text>
</svg>`;
}

function handle(msg) {
  if (msg.id === undefined) {
    if (msg.method === 'exit') process.exit(0);
    return; // notifications
  }
  switch (msg.method) {
    case 'initialize':
      return send({ id: msg.id, result: { capabilities: { textDocumentSync: 1 }, serverInfo: { name: 'fake-render-server' } } });
    case 'shutdown':
      return send({ id: msg.id, result: null });
    case 'higraph/render':
      return send({ id: msg.id, result: { svg: svgFor(msg.params?.name) } });
    default:
      return send({ id: msg.id, error: { code: -32601, message: `unhandled method ${msg.method}` } });
  }
}

process.stdin.on('data', (chunk) => {
  buffer = Buffer.concat([buffer, chunk]);
  for (;;) {
    const headerEnd = buffer.indexOf('\r\n\r\n');
    if (headerEnd < 0) return;
    const match = /Content-Length: *(\d+)/i.exec(buffer.subarray(0, headerEnd).toString('ascii'));
    const length = match ? Number(match[1]) : 0;
    if (buffer.length < headerEnd + 4 + length) return;
    const body = buffer.subarray(headerEnd + 4, headerEnd + 4 + length).toString('utf8');
    buffer = buffer.subarray(headerEnd + 4 + length);
    handle(JSON.parse(body));
  }
});
process.stdin.on('end', () => process.exit(0));
