// "HiGraph: Build": the shape of the server's answer to `workspace/executeCommand
// higraph.build`, and what the editor shows of it (no `vscode` import, so it is unit-tested).
//
// The server writes the files itself (`higraph-lsp build` for the whole workspace, or for one
// group or chart with the argument `{"kind": "group"|"chart", "name": ...}`) and answers
// `{"files": [workspace-relative paths written], "unchanged": [paths that already held the same
// bytes], "refused": bool, "message": one line}`.

export const BUILD_COMMAND = 'higraph.build';
/** The VS Code command of the palette (the server's own command id is registered by the
 * language client, which runs it for code actions). */
export const BUILD_WORKSPACE_COMMAND = 'higraph.buildWorkspace';

export interface BuildAnswer {
  files: string[];
  unchanged: string[];
  refused: boolean;
  message: string;
}

/** What the editor shows: a notification and the lines for the output channel. */
export interface BuildReport {
  /** `error` when the build was refused, else `info`. */
  severity: 'info' | 'error';
  /** The notification, prefixed with "HiGraph: ". */
  notification: string;
  /** Lines for the "HiGraph" output channel: the message, then one line per file. */
  lines: string[];
}

/** Reads the server's answer defensively: a missing or malformed answer is reported, not thrown. */
export function parseBuildAnswer(value: unknown): BuildAnswer | undefined {
  if (!value || typeof value !== 'object') return undefined;
  const v = value as Record<string, unknown>;
  if (typeof v.message !== 'string') return undefined;
  const strings = (a: unknown): string[] => (Array.isArray(a) ? a.filter((f): f is string => typeof f === 'string') : []);
  return { files: strings(v.files), unchanged: strings(v.unchanged), refused: v.refused === true, message: v.message };
}

/** The report of one build. `what` names what was built ("the workspace", "group Anlage"). */
export function describeBuild(value: unknown, what = 'the workspace'): BuildReport {
  const answer = parseBuildAnswer(value);
  if (!answer) {
    return {
      severity: 'error',
      notification: `HiGraph: building ${what} gave no answer the extension understands.`,
      lines: [`build of ${what}: unexpected answer ${safeJson(value)}`],
    };
  }
  const message = answer.message.trim() || (answer.refused ? 'build refused' : 'build finished');
  const lines = [`build of ${what}: ${message}`];
  if (answer.refused) {
    lines.push('  nothing was written; the errors are in the Problems panel');
  } else {
    for (const f of answer.files) lines.push(`  wrote ${f}`);
    for (const f of answer.unchanged) lines.push(`  unchanged ${f}`);
    if (answer.files.length === 0 && answer.unchanged.length === 0) lines.push('  no file written');
  }
  return { severity: answer.refused ? 'error' : 'info', notification: `HiGraph: ${message}`, lines };
}

/** What the argument of `higraph.build` names, for the report ("group Anlage"). */
export function buildTarget(args: unknown[] | undefined): string {
  const a = args?.[0] as { kind?: unknown; name?: unknown } | undefined;
  if (a && typeof a.name === 'string' && (a.kind === 'group' || a.kind === 'chart')) return `${a.kind} ${a.name}`;
  return 'the workspace';
}

function safeJson(value: unknown): string {
  try {
    return JSON.stringify(value) ?? String(value);
  } catch {
    return String(value);
  }
}
