#!/usr/bin/env python3
"""Memory of the language server under repeated messages (Linux: RSS and threads from /proc).

    scripts/server-rss.py BINARY WORKSPACE MESSAGES MODE

opens the first `.higraph` file of WORKSPACE and sends MESSAGES messages: MODE `req` only
requests (hover, completion, semantic tokens at moving lines), `edit` only edits (a space
inserted and removed again), `mixed` one edit per three requests. Prints the server's RSS and
thread count fifteen times along the way. Edits the document only in the server's memory.
"""
import json, os, subprocess, sys, threading, time

binary, workspace, total, mode = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
step = max(total // 15, 1)
p = subprocess.Popen([binary, "lsp"], stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, cwd=workspace)
answered = [0]
def reader():
    out = p.stdout
    while True:
        line = out.readline()
        if not line:
            return
        if line.lower().startswith(b"content-length"):
            n = int(line.split(b":")[1])
            out.readline()
            body = json.loads(out.read(n))
            if "id" in body and "method" in body:
                send({"jsonrpc": "2.0", "id": body["id"], "result": None})
            elif "id" in body:
                answered[0] += 1
lock = threading.Lock()
def send(msg):
    data = json.dumps(msg).encode()
    with lock:
        p.stdin.write(b"Content-Length: %d\r\n\r\n" % len(data) + data)
        p.stdin.flush()
threading.Thread(target=reader, daemon=True).start()
def rss():
    r = t = 0
    for line in open(f"/proc/{p.pid}/status"):
        if line.startswith("VmRSS"):
            r = int(line.split()[1]) // 1024
        if line.startswith("Threads"):
            t = int(line.split()[1])
    return f"{r} threads={t}"
uri_root = "file://" + os.path.abspath(workspace)
send({"jsonrpc": "2.0", "id": 0, "method": "initialize", "params": {"processId": None, "rootUri": uri_root, "capabilities": {}}})
send({"jsonrpc": "2.0", "method": "initialized", "params": {}})
files = sorted(f for f in os.listdir(workspace) if f.endswith(".higraph"))
uri = uri_root + "/" + files[0]
text = open(os.path.join(workspace, files[0])).read()
send({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {"textDocument": {"uri": uri, "languageId": "higraph", "version": 1, "text": text}}})
time.sleep(2)
print(f"start rss={rss()} MB", flush=True)
version, rid, sent = 1, 1, 0
lines = text.count("\n")
t0 = time.time()
while sent < total:
    kind = sent % 4 if mode == "mixed" else 0 if mode == "edit" else 1
    line = (sent * 7) % max(lines, 1)
    if kind == 0:
        version += 1
        insert = (version % 2 == 0)
        change = {"range": {"start": {"line": line, "character": 0}, "end": {"line": line, "character": 0}}, "text": " "} if insert else None
        if not insert:
            pl = ((sent - 4) * 7) % max(lines, 1)
            change = {"range": {"start": {"line": pl, "character": 0}, "end": {"line": pl, "character": 1}}, "text": ""}
        send({"jsonrpc": "2.0", "method": "textDocument/didChange", "params": {"textDocument": {"uri": uri, "version": version}, "contentChanges": [change]}})
    else:
        method = ["textDocument/hover", "textDocument/completion", "textDocument/semanticTokens/full"][sent % 3]
        rid += 1
        send({"jsonrpc": "2.0", "id": rid, "method": method, "params": {"textDocument": {"uri": uri}, "position": {"line": line, "character": 4}}})
    sent += 1
    if sent % step == 0:
        # let it catch up a little so RSS reflects retained memory, not queues
        while rid - answered[0] > 200:
            time.sleep(0.01)
        print(f"{sent} msgs rss={rss()} MB answered={answered[0]} t={time.time()-t0:.0f}s", flush=True)
time.sleep(3)
print(f"end rss={rss()} MB", flush=True)
p.kill()
