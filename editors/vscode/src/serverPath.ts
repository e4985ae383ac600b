// Where the `higraph-lsp` executable is found (no `vscode` import, so it is unit-tested):
//   1. the setting `higraph.server.path`, when it is not empty;
//   2. the binary bundled with the extension: `server/higraph-lsp` (`server/higraph-lsp.exe`
//      on Windows), if it is there and executable;
//   3. `higraph-lsp` on PATH.
import * as fs from 'node:fs';
import * as os from 'node:os';
import * as path from 'node:path';

export type ServerSource = 'setting' | 'bundled' | 'path';

export interface ResolvedServer {
  command: string;
  source: ServerSource;
}

export interface ResolveOptions {
  /** Value of `higraph.server.path` (may be empty). */
  setting: string | undefined;
  /** The extension's install folder. */
  extensionPath: string;
  /** The first workspace folder, for a relative setting. */
  workspaceFolder?: string;
  env?: NodeJS.ProcessEnv;
  platform?: NodeJS.Platform;
  homedir?: string;
}

export class ServerNotFoundError extends Error {
  constructor(
    message: string,
    /** True when the setting names a missing or unusable file (the fix is in the settings). */
    readonly settingIsWrong: boolean,
  ) {
    super(message);
    this.name = 'ServerNotFoundError';
  }
}

export const SERVER_NAME = 'higraph-lsp';

function exeName(platform: NodeJS.Platform): string {
  return platform === 'win32' ? `${SERVER_NAME}.exe` : SERVER_NAME;
}

/** True for an existing regular file that this process may execute. */
export function isExecutable(file: string, platform: NodeJS.Platform = process.platform): boolean {
  try {
    if (!fs.statSync(file).isFile()) return false;
    if (platform === 'win32') return true;
    fs.accessSync(file, fs.constants.X_OK);
    return true;
  } catch {
    return false;
  }
}

/** The first executable `name` in the PATH of `env` (with PATHEXT on Windows). */
export function findOnPath(name: string, env: NodeJS.ProcessEnv, platform: NodeJS.Platform): string | undefined {
  const pathVar = env.PATH ?? env.Path ?? env.path ?? '';
  const delimiter = platform === 'win32' ? ';' : ':';
  const exts =
    platform === 'win32'
      ? ['', ...(env.PATHEXT ?? '.COM;.EXE;.BAT;.CMD').split(';').filter(Boolean)]
      : [''];
  for (const dir of pathVar.split(delimiter)) {
    if (!dir) continue;
    for (const ext of exts) {
      const candidate = path.join(dir.replace(/^"(.*)"$/, '$1'), name + ext);
      if (isExecutable(candidate, platform)) return candidate;
    }
  }
  return undefined;
}

/** Expands a leading `~` and resolves a relative path against the workspace folder. */
export function expandSetting(value: string, workspaceFolder: string | undefined, homedir: string): string {
  let p = value.trim();
  if (p === '~' || p.startsWith('~/') || p.startsWith('~\\')) p = path.join(homedir, p.slice(1));
  if (!path.isAbsolute(p) && workspaceFolder) p = path.resolve(workspaceFolder, p);
  return p;
}

export function resolveServer(options: ResolveOptions): ResolvedServer {
  const env = options.env ?? process.env;
  const platform = options.platform ?? process.platform;
  const homedir = options.homedir ?? os.homedir();

  const setting = options.setting?.trim();
  if (setting) {
    const p = expandSetting(setting, options.workspaceFolder, homedir);
    if (isExecutable(p, platform)) return { command: p, source: 'setting' };
    // a bare command name in the setting (`higraph-lsp-dev`) is looked up on PATH
    if (!/[\\/]/.test(setting)) {
      const onPath = findOnPath(setting, env, platform);
      if (onPath) return { command: onPath, source: 'setting' };
    }
    const why = fs.existsSync(p) ? 'is not an executable file' : 'does not exist';
    throw new ServerNotFoundError(
      `The setting higraph.server.path is "${setting}", but ${p} ${why}. ` +
        `Fix the setting, or clear it to use the bundled server or ${SERVER_NAME} from PATH.`,
      true,
    );
  }

  const bundled = path.join(options.extensionPath, 'server', exeName(platform));
  if (isExecutable(bundled, platform)) return { command: bundled, source: 'bundled' };

  const onPath = findOnPath(SERVER_NAME, env, platform);
  if (onPath) return { command: onPath, source: 'path' };

  throw new ServerNotFoundError(
    `The HiGraph language server (${SERVER_NAME}) was not found: the setting higraph.server.path is empty, ` +
      `this extension has no bundled server, and ${SERVER_NAME} is not on PATH. ` +
      `Install it (in the higraph-lsp repository: cargo install --path crates/lsp) or set higraph.server.path. ` +
      `Syntax highlighting works without it.`,
    false,
  );
}
